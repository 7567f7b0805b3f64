// Ambient aperture (libpyramid/encode/aperture/aperture.hpp, doc/shading.md): the sky a horizon
// profile leaves; a flat plain sees the whole hemisphere, the bottom of a conical pit the cap the
// cone's walls leave (1 - sin of their slope angle); the file is the same for 1 and 2 threads;
// the program refuses a plane without a ground size.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/encode/aperture/aperture.hpp"
#include "libpyramid/api/sources.hpp"
#include "libpyramid/runtime/level_heights.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::TempDir;

TEST(Aperture, TheSkyAHorizonLeaves) {
    std::vector<double> open(16, 0.0);
    Aperture a = apertureOfHorizons(open.data(), 16);
    EXPECT_NEAR(a.visible, 1.0, 1e-12);
    EXPECT_NEAR(a.direction[2], 1.0, 1e-12);
    const double wall = std::atan(0.5);
    std::vector<double> pit(16, wall);
    a = apertureOfHorizons(pit.data(), 16);
    EXPECT_NEAR(a.visible, 1.0 - std::sin(wall), 1e-12);
    EXPECT_NEAR(a.direction[2], 1.0, 1e-12);
    // A wall to the east only: the sky's mean direction leans west.
    std::vector<double> east(16, 0.0);
    east[0] = east[1] = east[15] = 1.2;
    a = apertureOfHorizons(east.data(), 16);
    EXPECT_LT(a.visible, 1.0);
    EXPECT_LT(a.direction[0], -0.05);
    EXPECT_NEAR(a.direction[1], 0.0, 1e-12);
    EXPECT_EQ(encodeAperture(Aperture{}), (std::array<uint8_t, 3>{255, 128, 128}));
}

// A DEM of 129 x 129 samples, 1 height unit apart at its finest level (size 128), from f(x, y)
// in vertex coordinates (x east, y north).
std::string demOf(const TempDir& dir, const std::string& name, double (*f)(double, double)) {
    constexpr int w = 129;
    std::vector<float> v(static_cast<size_t>(w) * w);
    for (int row = 0; row < w; ++row) {
        for (int col = 0; col < w; ++col) {
            v[static_cast<size_t>(row) * w + col] = static_cast<float>(f(col, w - 1 - row));
        }
    }
    test::writeFloatRaster(dir.file(name + ".tif"), w, w, v);
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 32;
    o.scale = 0.01;
    encodeDem(dir.file(name + ".tif"), dir.file(name + ".dat"), o);
    return dir.file(name + ".dat");
}

// Pixel (x, y) of ortho level `level` (y counted from the south), channel c.
int pixel(const std::string& file, int level, int x, int y, int c) {
    const OrthoProducer p(file);
    const int T = p.header().tileSize, b = p.header().border(), C = p.header().channels;
    const std::vector<uint8_t> t = p.tile(level, x / T, y / T);
    const size_t side = static_cast<size_t>(T + 2 * b);
    return t[((static_cast<size_t>(y % T + b)) * side + static_cast<size_t>(x % T + b)) * static_cast<size_t>(C) +
             static_cast<size_t>(c)];
}

TEST(Aperture, AFlatPlainSeesTheWholeHemisphere) {
    TempDir dir;
    const std::string dem = demOf(dir, "flat", [](double, double) { return 100.0; });
    ApertureEncodeOptions o;
    o.size = 128.0;
    o.search.directions = 12;
    o.search.radius = 6;
    o.search.levels = 2;
    const ApertureReport r = encodeApertureFile(dem, dir.file("APERTURE.dat"), o);
    EXPECT_EQ(r.maxLevel, 2);
    EXPECT_EQ(r.tiles, 21);
    const nlohmann::json j = toJson(r); // the search under the keys the spherical report uses
    EXPECT_EQ(j.at("directions"), 12);
    EXPECT_EQ(j.at("radius_steps"), 6);
    EXPECT_EQ(j.at("levels"), 2);
    EXPECT_FALSE(j.contains("radius"));
    const OrthoProducer p(dir.file("APERTURE.dat"));
    ASSERT_EQ(p.header().channels, 3);
    for (int level = 0; level <= 2; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                const std::vector<uint8_t> t = p.tile(level, tx, ty);
                for (int y = 2; y < 34; ++y) {
                    for (int x = 2; x < 34; ++x) {
                        const size_t k = (static_cast<size_t>(y) * 36 + static_cast<size_t>(x)) * 3;
                        ASSERT_EQ(t[k], 255);
                        ASSERT_EQ(t[k + 1], 128);
                        ASSERT_EQ(t[k + 2], 128);
                    }
                }
            }
        }
    }
}

TEST(Aperture, TheBottomOfAConicalPitSeesTheCapItsWallsLeave) {
    TempDir dir;
    // Walls of slope 1/2 around (64.5, 64.5), the centre of finest pixel (64, 64).
    const std::string dem = demOf(dir, "pit", [](double x, double y) { return 0.5 * std::hypot(x - 64.5, y - 64.5); });
    ApertureEncodeOptions o;
    o.size = 128.0;
    o.threads = 1;
    encodeApertureFile(dem, dir.file("one/APERTURE.dat"), o);
    const double expected = 1.0 - std::sin(std::atan(0.5)); // 0.553: a cap of half-angle 63.4 degrees
    // 8-bit storage (1/255) and bilinear heights between the cone's vertices: within 2/255.
    EXPECT_NEAR(pixel(dir.file("one/APERTURE.dat"), 2, 64, 64, 0) / 255.0, expected, 2.0 / 255.0);
    EXPECT_NEAR(pixel(dir.file("one/APERTURE.dat"), 2, 64, 64, 1), 128, 1);
    EXPECT_NEAR(pixel(dir.file("one/APERTURE.dat"), 2, 64, 64, 2), 128, 1);
    // On the pit's west wall the ground rises westward: the sky leans east, over the pit.
    EXPECT_GT(pixel(dir.file("one/APERTURE.dat"), 2, 40, 64, 1), 136);
    EXPECT_NEAR(pixel(dir.file("one/APERTURE.dat"), 2, 40, 64, 2), 128, 2);
    // The same bytes for 2 threads.
    o.threads = 2;
    encodeApertureFile(dem, dir.file("two/APERTURE.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("one/APERTURE.dat")), test::readFile(dir.file("two/APERTURE.dat")));
}

// Every finest pixel is the aperture of the direct search of doc/shading.md, byte for byte: each
// azimuth's horizon the largest of 0 and atan2(rise, run) over every step of every level searched,
// on rough ground whose horizons come from near and far steps alike.
TEST(Aperture, EveryPixelIsTheDirectSearchsAperture) {
    TempDir dir;
    const std::string dem = demOf(dir, "rough", [](double x, double y) {
        const auto grain = static_cast<double>((static_cast<int64_t>(x) * 7919 + static_cast<int64_t>(y) * 104729) % 97);
        return 30.0 * std::sin(x * 0.3) * std::cos(y * 0.23) + 20.0 * std::sin(x * 0.07 + y * 0.11) + 0.1 * grain;
    });
    ApertureEncodeOptions o;
    o.size = 128.0; // 1 height unit between the finest samples
    encodeApertureFile(dem, dir.file("APERTURE.dat"), o);
    const auto producer = openElevationSet(dem);
    const int n = producer->tileSize(), finest = 2, W = n << finest;
    const auto height = [&](int level, double x, double y) {
        const LevelCell cell = levelCell(n, int64_t{1} << level, x, y);
        return cellHeight(producer->tile(level, cell.tx, cell.ty)->zf.data(), n, cell);
    };
    const ApertureSearch& search = o.search;
    int compared = 0;
    for (int js = 0; js < W; js += 5) {     // rows from the south
        for (int i = 0; i < W; i += 3) {
            const double x = i + 0.5, y = js + 0.5;
            const double z0 = height(finest, x, y);
            std::vector<double> horizons(static_cast<size_t>(search.directions));
            for (int d = 0; d < search.directions; ++d) {
                const double azimuth = 2.0 * std::numbers::pi * d / search.directions;
                double horizon = 0.0;
                for (int q = 0; q < search.levels && finest - q >= 0; ++q) {
                    const double scale = std::ldexp(1.0, q);
                    for (int k = q == 0 ? 1 : search.radius / 2 + 1; k <= search.radius; ++k) {
                        const double distance = k * scale;
                        const double z = height(finest - q, (x + distance * std::cos(azimuth)) / scale,
                                                (y + distance * std::sin(azimuth)) / scale);
                        horizon = std::max(horizon, std::atan2(z - z0, distance * 1.0));
                    }
                }
                horizons[static_cast<size_t>(d)] = horizon;
            }
            const std::array<uint8_t, 3> want = encodeAperture(apertureOfHorizons(horizons.data(), search.directions));
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(pixel(dir.file("APERTURE.dat"), finest, i, js, c), want[static_cast<size_t>(c)])
                    << "pixel " << i << "," << js << " channel " << c;
            }
            ++compared;
        }
    }
    EXPECT_EQ(compared, 26 * 43);
}

TEST(Aperture, TheProgramNeedsAGroundSize) {
    TempDir dir;
    const std::string dem = demOf(dir, "flat", [](double, double) { return 10.0; });
    const std::string program = test::programPath("preprocessAperture") + " " + dem + " -q -o ";
    const test::RunResult unknown = test::run(program + dir.file("a/APERTURE.dat"));
    EXPECT_EQ(unknown.exitCode, 1);
    EXPECT_NE(unknown.err.find("--size"), std::string::npos) << unknown.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("a")));
    const test::RunResult ok =
        test::run(program + dir.file("b/APERTURE.dat") + " --size 128 --directions 8 --radius 4 --report -");
    ASSERT_EQ(ok.exitCode, 0) << ok.err;
    const nlohmann::json report = nlohmann::json::parse(ok.out);
    EXPECT_EQ(report.at("directions"), 8);
    EXPECT_EQ(report.at("spacing"), 1.0);
    EXPECT_EQ(test::run(program + dir.file("c/APERTURE.dat") + " --size 128 --radius 3").exitCode, 1);
}

// The faces of a planet of `height(latitude, longitude)` metres: 16-interval tiles, levels 0..2.
std::string planet(const TempDir& dir, std::function<double(double, double)> height) {
    SphericalDemOptions o;
    o.dem.tileSize = 16;
    o.dem.rootTileSize = 16;
    o.dem.maxLevel = 2;
    o.dem.autoScale = true;
    encodeSphericalDem(PlanetFunction(std::move(height), 256), dir.file("dem"), o);
    return dir.file("dem");
}

TEST(SphericalAperture, ASphereOfConstantHeightSeesTheWholeSkyEverywhere) {
    TempDir dir;
    SphericalApertureOptions o;
    o.search.directions = 8;
    o.search.radius = 4;
    const SphericalApertureReport r = encodeSphericalApertureFiles(planet(dir, [](double, double) { return 500.0; }),
                                                                   dir.file("out"), o);
    ASSERT_EQ(r.outputs.size(), 6u);
    EXPECT_EQ(r.maxLevel, 2);
    const nlohmann::json j = toJson(r);
    EXPECT_EQ(j.at("directions"), 8);
    EXPECT_EQ(j.at("radius_steps"), 4);
    EXPECT_EQ(j.at("levels"), 3);
    EXPECT_EQ(j.at("radius"), r.radius); // the sphere's, in metres
    for (const std::string& face : r.outputs) {
        const OrthoProducer p(face);
        ASSERT_EQ(p.header().channels, 3);
        for (int level = 0; level <= 2; ++level) {
            for (int ty = 0; ty < (1 << level); ++ty) {
                for (int tx = 0; tx < (1 << level); ++tx) {
                    const std::vector<uint8_t> t = p.tile(level, tx, ty);
                    for (size_t k = 0; k < t.size(); k += 3) {
                        ASSERT_EQ(t[k], 255) << face;
                        ASSERT_EQ(t[k + 1], 128) << face;
                        ASSERT_EQ(t[k + 2], 128) << face;
                    }
                }
            }
        }
    }
}

// Pixel X, Y (from the south-west, borders beyond the face included) of a face's finest level.
std::array<uint8_t, 3> facePixel(const OrthoProducer& p, int level, int64_t X, int64_t Y) {
    const int T = p.header().tileSize, b = p.header().border();
    const int64_t tiles = int64_t{1} << level;
    const int64_t tx = std::clamp<int64_t>(X < 0 ? 0 : X / T, 0, tiles - 1), ty = std::clamp<int64_t>(Y < 0 ? 0 : Y / T, 0, tiles - 1);
    const std::vector<uint8_t> t = p.tile(level, static_cast<int>(tx), static_cast<int>(ty));
    const auto x = static_cast<size_t>(X - tx * T + b), y = static_cast<size_t>(Y - ty * T + b);
    const size_t k = (y * static_cast<size_t>(T + 2 * b) + x) * 3;
    return {t[k], t[k + 1], t[k + 2]};
}

// Over varied terrain, the faces join without seams: every border pixel beyond a face's edge is
// the neighbouring face's pixel at the same point (sphere/cube_faces.hpp), byte for byte, and the
// aperture does vary; 1 and 2 threads write the same files.
TEST(SphericalAperture, FacesJoinWithoutSeams) {
    TempDir dir;
    const std::string faces = planet(dir, [](double latitude, double longitude) {
        return 50000.0 + 40000.0 * std::sin(latitude * 1.0) * std::cos(longitude * 0.8); // slopes up to 0.36
    });
    SphericalApertureOptions o;
    o.search.directions = 8;
    o.search.radius = 4;
    o.threads = 2;
    const SphericalApertureReport r = encodeSphericalApertureFiles(faces, dir.file("out"), o);
    std::vector<std::unique_ptr<OrthoProducer>> p;
    for (const std::string& face : r.outputs) {
        p.push_back(std::make_unique<OrthoProducer>(face));
    }
    const int level = 2, N = 16 << level;
    const FaceGrid grid{N, FaceGridKind::PixelCentres};
    int compared = 0, varied = 0;
    for (int f = 1; f <= 6; ++f) {
        for (int along = 0; along < N; ++along) {
            for (int beyond = 1; beyond <= 2; ++beyond) {
                for (const auto& [X, Y] : {std::pair<int64_t, int64_t>{N - 1 + beyond, along}, {-beyond, along},
                                           {along, N - 1 + beyond}, {along, -beyond}}) {
                    const FaceSample other = canonicalSample(grid, FaceSample{f, X, Y});
                    ASSERT_NE(other.face, f);
                    const auto border = facePixel(*p[static_cast<size_t>(f - 1)], level, X, Y);
                    const auto inside = facePixel(*p[static_cast<size_t>(other.face - 1)], level, other.x, other.y);
                    ASSERT_EQ(border, inside) << "face " << f << " pixel " << X << "," << Y;
                    ++compared;
                    varied += border[0] < 245;
                }
            }
        }
    }
    EXPECT_EQ(compared, 6 * 4 * 2 * N);
    EXPECT_GT(varied, compared / 10) << "the terrain hides some of the sky";
    o.threads = 1;
    encodeSphericalApertureFiles(faces, dir.file("one"), o);
    for (int f = 1; f <= 6; ++f) {
        const std::string name = "/APERTURE" + std::to_string(f) + ".dat";
        EXPECT_EQ(test::readFile(dir.file("one") + name), test::readFile(dir.file("out") + name)) << name;
    }
}

} // namespace
} // namespace pyramid
