// A C++ loader built against an installed copy (tests/install/install_test.sh): the runtime's
// classes from libpyramid-runtime.a, found with COMPONENTS runtime alone. Produces the root
// elevation tile of the original tools' DEM.dat and prints its centre.
// Usage: runtime_static_consumer DATA_DIR
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/residual_producer.hpp"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: runtime_static_consumer DATA_DIR\n");
        return 2;
    }
    try {
        pyramid::ResidualProducerOptions ro;
        ro.delta = 3; // elevation tiles of the file's tile size: its minLevel
        auto residuals = std::make_shared<pyramid::ResidualProducer>(std::string(argv[1]) + "/proland/DEM.dat",
                                                                     std::vector<std::string>{}, ro);
        pyramid::ElevationProducer producer(residuals, {});
        const auto root = producer.tile(0, 0, 0);
        const int side = producer.tileSize() + 5;
        const float centre = root->zf[static_cast<size_t>(side / 2 + side / 2 * side)];
        std::printf("runtime_static_consumer: root tile of %d, centre %.1f\n", side, centre);
        return centre > 0.0f ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "runtime_static_consumer: %s\n", e.what());
        return 1;
    }
}
