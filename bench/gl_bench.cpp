// Tiles per second of the CPU and GL producers over every tile of a residual file (one run per
// elevation tile size) and of an ortho file read as colour residuals. GL times are taken twice:
// with the tiles left on the GPU (glFinish after each) and read back to host memory.
//
//   gl_bench [DEM.dat [RGB.dat]]    (default: the original tools' files in tests/data/proland)
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include "formats/error.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/gl/egl_context.hpp"
#include "libpyramid/gl/gl_elevation_producer.hpp"
#include "libpyramid/gl/gl_colour_producer.hpp"
#include "libpyramid/runtime/colour_producer.hpp"

namespace {

using namespace pyramid;

// Every tile of levels 0..last, each right after its ancestors (as a renderer descends).
void walk(int level, int tx, int ty, int last, const std::function<void(int, int, int)>& visit) {
    visit(level, tx, ty);
    if (level < last) {
        for (int q = 0; q < 4; ++q) {
            walk(level + 1, 2 * tx + (q & 1), 2 * ty + (q >> 1), last, visit);
        }
    }
}

// Tiles per second of one walk.
double rate(int last, const std::function<void(int, int, int)>& produce) {
    long tiles = 0;
    const auto start = std::chrono::steady_clock::now();
    walk(0, 0, 0, last, [&](int l, int x, int y) {
        produce(l, x, y);
        ++tiles;
    });
    const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
    return static_cast<double>(tiles) / seconds.count();
}

void benchElevation(const std::string& path) {
    const ResidualHeader h = ResidualFileReader::open(path)->header();
    std::printf("%s\n  %-22s %12s %12s %12s\n", path.c_str(), "elevation tiles", "CPU t/s", "GL t/s", "GL+read t/s");
    for (int k = 0; k <= h.minLevel && (h.tileSize >> k) >= 2; ++k) {
        const int n = h.tileSize >> k;
        ResidualProducerOptions ro;
        ro.delta = elevationDelta(h, n);
        auto residuals = std::make_shared<const ResidualProducer>(path, std::vector<std::string>{}, ro);
        ElevationProducerOptions eo;
        eo.tileSize = n;
        ElevationProducer cpu(residuals, eo);
        GlElevationProducer gl(residuals, eo);
        GlElevationProducer glRead(residuals, eo);
        const int last = cpu.maxLevel();
        const double cpuRate = rate(last, [&](int l, int x, int y) { cpu.tile(l, x, y); });
        const double glRate = rate(last, [&](int l, int x, int y) {
            gl.tile(l, x, y);
            glFinish();
        });
        const double readRate =
            rate(last, [&](int l, int x, int y) { GlElevationProducer::read(*glRead.tile(l, x, y)); });
        std::printf("  n=%-4d delta=%-10d %12.0f %12.0f %12.0f\n", n, ro.delta, cpuRate, glRate, readRate);
    }
}

void benchColours(const std::string& path) {
    auto residuals = std::make_shared<const OrthoProducer>(path);
    const int last = residuals->maxLevel() + 2; // two levels refined without residuals
    ColourProducer cpu(residuals);
    GlColourProducer gl(residuals);
    GlColourProducer glRead(residuals);
    const double cpuRate = rate(last, [&](int l, int x, int y) { cpu.tile(l, x, y); });
    const double glRate = rate(last, [&](int l, int x, int y) {
        gl.tile(l, x, y);
        glFinish();
    });
    const double readRate = rate(last, [&](int l, int x, int y) { GlColourProducer::read(*glRead.tile(l, x, y)); });
    std::printf("%s\n  %-22s %12s %12s %12s\n  %-22s %12.0f %12.0f %12.0f\n", path.c_str(), "colour tiles", "CPU t/s",
                "GL t/s", "GL+read t/s", ("levels 0.." + std::to_string(last)).c_str(), cpuRate, glRate, readRate);
}

} // namespace

int main(int argc, char** argv) {
    const std::string dem = argc > 1 ? argv[1] : PYRAMID_TEST_DATA "/proland/DEM.dat";
    const std::string rgb = argc > 2 ? argv[2] : PYRAMID_TEST_DATA "/proland/RGB.dat";
    try {
        EglContext context;
        std::printf("GL: %s\n", context.renderer().c_str());
        benchElevation(dem);
        benchColours(rgb);
    } catch (const Error& e) {
        std::fprintf(stderr, "gl_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
