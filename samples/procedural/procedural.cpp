// A procedural planet through libpyramid's encoder API (doc/library.md): heights that are a
// function of the direction from the planet's centre are encoded into the six cube-face residual
// pyramids preprocessSphericalDem writes, then every level of every face is rebuilt and checked
// against the same function.
//
// Usage: procedural OUTPUT_DIR [RESOLUTION [THREADS]]
//   RESOLUTION: samples around the equator (default 1024); faces are a quarter of it across.
// Exit status 0 when every face verifies within scale / 2, 1 otherwise, 2 on an error.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "libpyramid/api/encoders.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;

// Heights in metres of the unit direction (x, y, z): a few long waves, a ridge along a great
// circle, and a crater. Smooth, so the residuals stay small, and cheap to evaluate.
double height(double x, double y, double z) {
    double h = 900.0 * std::sin(2.0 * x + 0.5) * std::cos(3.0 * y - 0.2) + 400.0 * std::sin(5.0 * z + x);
    h += 1500.0 * std::exp(-std::pow((x + y + z) / std::sqrt(3.0) / 0.08, 2.0)); // a ridge
    const double d = std::acos(std::fmin(1.0, 0.6 * x + 0.8 * z));                  // a crater at (0.6, 0, 0.8)
    h -= 2000.0 * std::exp(-std::pow(d / 0.12, 2.0));
    return h;
}

double heightAt(double latitude, double longitude) {
    const double p = latitude * kPi / 180.0, l = longitude * kPi / 180.0;
    return height(std::cos(p) * std::cos(l), std::cos(p) * std::sin(l), std::sin(p));
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argc > 4) {
        std::fprintf(stderr, "usage: %s OUTPUT_DIR [RESOLUTION [THREADS]]\n", argv[0]);
        return 2;
    }
    const std::string directory = argv[1];
    const int resolution = argc > 2 ? std::atoi(argv[2]) : 1024;
    const int threads = argc > 3 ? std::atoi(argv[3]) : 0;
    try {
        const pyramid::PlanetFunction planet(heightAt, resolution, "waves");
        pyramid::SphericalDemOptions options;
        options.body = "sphere";     // heights are a function of the geocentric direction
        options.dem.scale = 0.5;     // residual step in metres: every height within 0.25 m
        options.dem.threads = threads;
        const pyramid::SphericalDemReport report = pyramid::encodeSphericalDem(planet, directory, options);
        std::printf("%s: %zu faces, levels 0..%d of %d-interval tiles, %.1f s\n", directory.c_str(),
                    report.faces.size(), report.faces.front().dem.header.maxLevel,
                    report.faces.front().dem.header.tileSize, report.seconds);

        pyramid::SphericalDemVerifyOptions check;
        check.body = options.body;
        check.threads = threads;
        bool ok = true;
        for (const pyramid::DemVerifyReport& face : pyramid::verifySphericalDem(directory, planet, check)) {
            double worst = 0.0;
            long long samples = 0;
            for (const pyramid::DemVerifyLevel& level : face.levels) {
                worst = std::fmax(worst, level.maxError);
                samples += level.samples;
            }
            std::printf("  %s: %lld samples, max error %.4f m (bound %.2f): %s\n", face.file.c_str(), samples, worst,
                        face.bound, face.ok() ? "ok" : "FAILED");
            ok = ok && face.ok();
        }
        if (ok) {
            std::printf("all 6 faces verify within scale / 2\n");
        }
        return ok ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "procedural: %s\n", e.what());
        return 2;
    }
}
