// An encoder built against an installed copy (tests/install/install_test.sh): describes
// samples/dem.tif, encodes it into a residual pyramid with libpyramid::preprocess, and reads the
// result back through the C API (in the static runtime the preprocess library stands on).
// Usage: preprocess_consumer SAMPLES_DIR OUTPUT_DIR
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "libpyramid/capi/pyramid.h"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: preprocess_consumer SAMPLES_DIR OUTPUT_DIR\n");
        return 2;
    }
    const std::string input = std::string(argv[1]) + "/dem.tif";
    const std::string output = std::string(argv[2]) + "/dem.dat";
    try {
        const pyramid::RasterInfo info = pyramid::RasterSource::describe(input);
        if (info.width != 385 || info.height != 385 || info.channels != 1 || info.type != pyramid::SampleType::Float32) {
            std::fprintf(stderr, "preprocess_consumer: %s: unexpected description %dx%d x%d %s\n", input.c_str(),
                         info.width, info.height, info.channels, pyramid::sampleTypeName(info.type));
            return 1;
        }
        pyramid::DemEncodeOptions options;
        options.threads = 2;
        const pyramid::DemReport report = pyramid::encodeDem(input, output, options);

        pyramid_file* file = nullptr;
        pyramid_info read{};
        std::vector<short> tile(197 * 197);
        if (pyramid_open(output.c_str(), &file) != PYRAMID_OK || pyramid_get_info(file, &read) != PYRAMID_OK ||
            pyramid_read_tile(file, read.min_level, 0, 0, tile.data(), tile.size() * sizeof(short), nullptr) !=
                PYRAMID_OK) {
            std::fprintf(stderr, "preprocess_consumer: %s\n", pyramid_last_error());
            pyramid_close(file);
            return 1;
        }
        pyramid_close(file);
        if (read.kind != PYRAMID_KIND_RESIDUAL || read.tile_count != report.tiles ||
            read.max_level != report.header.maxLevel || read.tile_size != 192) {
            std::fprintf(stderr, "preprocess_consumer: %s: the file read back is not the one written\n",
                         output.c_str());
            return 1;
        }
        std::printf("encoded %s: %dx%d %s, %lld tiles, levels %d..%d\n", input.c_str(), info.width, info.height,
                    pyramid::sampleTypeName(info.type), read.tile_count, read.min_level, read.max_level);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "preprocess_consumer: %s\n", e.what());
        return 1;
    }
    return 0;
}
