// Spherical ortho pyramids (six cube faces) as a library: tile borders identical across faces at
// every level, finest pixels equal to the map at their geodetic point, partial extents, 16-bit
// input, determinism, colour residuals rebuilt by the CPU producer, bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <numbers>
#include <tuple>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/sphere/map_sources.hpp"
#include "libpyramid/sphere/planet_body.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "tests/support/box_map.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

constexpr double kRad = std::numbers::pi / 180.0;

// A smooth RGB colour of a point of the globe (continuous across the date line and the poles),
// 8-bit scale: two colours follow the point's direction, the third a ring pattern in latitude.
std::array<double, 3> colourOf(double latitude, double longitude) {
    const double lat = latitude * kRad, lon = longitude * kRad;
    return {127.5 + 120.0 * std::cos(lat) * std::cos(lon), 127.5 + 120.0 * std::cos(lat) * std::sin(lon),
            127.5 - 120.0 * std::cos(8.0 * (90.0 - latitude) * kRad)};
}

// A global equirectangular image of colourOf at its pixel centres, row 0 = north; `noise` adds
// a pixel-sized texture so that misplaced pixels show. `scale` 257 writes the same values in 16
// bits.
std::vector<uint16_t> globe(int w, int h, bool noise, int scale = 1) {
    std::vector<uint16_t> v(static_cast<size_t>(w) * h * 3);
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            const auto c = colourOf(90.0 - (j + 0.5) * 180.0 / h, -180.0 + (i + 0.5) * 360.0 / w);
            for (int k = 0; k < 3; ++k) {
                const long jitter = noise ? (i * 7 + j * 13 + k * 5) % 9 - 4 : 0;
                v[(static_cast<size_t>(j) * w + i) * 3 + k] =
                    static_cast<uint16_t>((std::lround(c[static_cast<size_t>(k)]) + jitter) * scale);
            }
        }
    }
    return v;
}

SphericalOrthoOptions small(int tileSize, std::optional<int> maxLevel) {
    SphericalOrthoOptions o;
    o.ortho.levels.tileSize = tileSize;
    o.ortho.levels.maxLevel = maxLevel; // none: chosen from the map
    return o;
}

using TileKey = std::tuple<int, int, int, int>; // face, level, tx, ty

// Every decoded tile of the TIFF files RGB1.dat .. RGB6.dat (of the faces present).
std::map<TileKey, std::vector<uint8_t>> readFaces(const std::string& dir, const std::vector<int>& faces) {
    std::map<TileKey, std::vector<uint8_t>> tiles;
    for (const int f : faces) {
        const auto reader = OrthoFileReader::open(dir + "/RGB" + std::to_string(f) + ".dat");
        for (int l = 0; l <= reader->header().maxLevel; ++l) {
            for (int ty = 0; ty < (1 << l); ++ty) {
                for (int tx = 0; tx < (1 << l); ++tx) {
                    tiles[{f, l, tx, ty}] = reader->readTile(l, tx, ty);
                }
            }
        }
    }
    return tiles;
}

// Level-l pixel (x, y) of face f, which must lie inside the face, from its tile's interior.
const uint8_t* facePixel(const std::map<TileKey, std::vector<uint8_t>>& tiles, int T, int l, const FaceSample& s) {
    const int side = T + 4;
    const auto& tile = tiles.at({s.face, l, static_cast<int>(s.x / T), static_cast<int>(s.y / T)});
    return &tile[(static_cast<size_t>(s.y % T + 2) * side + static_cast<size_t>(s.x % T + 2)) * 3];
}

// Checks every border pixel of every tile of every face against the pixel of the face holding
// its cube point (beyond a cube corner there is none).
void expectSeamless(int T, int maxLevel) {
    test::TempDir dir;
    test::writeImage(dir.file("globe.png"), 256, 128, 3, globe(256, 128, true), false);
    SphericalOrthoOptions o = small(T, maxLevel);
    o.ortho.writeDxt = o.ortho.writeResiduals = false;
    encodeSphericalOrtho(dir.file("globe.png"), dir.file("out"), o);
    const auto tiles = readFaces(dir.file("out"), o.faces);
    ASSERT_EQ(tiles.size(), 6u * static_cast<size_t>(((int64_t{1} << (2 * (maxLevel + 1))) - 1) / 3));
    const int side = T + 4;
    int64_t compared = 0, acrossFaces = 0;
    for (const auto& [key, tile] : tiles) {
        const auto [f, l, tx, ty] = key;
        const FaceGrid grid{int64_t{T} << l, FaceGridKind::PixelCentres};
        for (int j = 0; j < side; ++j) {
            for (int i = 0; i < side; ++i) {
                if (i >= 2 && i < T + 2 && j >= 2 && j < T + 2) {
                    continue; // the tile itself
                }
                const FaceSample s{f, static_cast<int64_t>(tx) * T + i - 2, static_cast<int64_t>(ty) * T + j - 2};
                const bool outsideX = s.x < 0 || s.x >= grid.n, outsideY = s.y < 0 || s.y >= grid.n;
                if (outsideX && outsideY) {
                    continue;
                }
                const FaceSample owner = canonicalSample(grid, s);
                ASSERT_EQ(cubePoint(grid, owner), cubePoint(grid, s));
                const uint8_t* want = facePixel(tiles, T, l, owner);
                const uint8_t* got = &tile[(static_cast<size_t>(j) * side + static_cast<size_t>(i)) * 3];
                for (int c = 0; c < 3; ++c) {
                    ASSERT_EQ(got[c], want[c]) << "tile size " << T << ", face " << f << " level " << l << " tile ("
                                               << tx << "," << ty << ") border pixel (" << i << "," << j
                                               << ") is face " << owner.face << " pixel (" << owner.x << ","
                                               << owner.y << ")";
                }
                ++compared;
                acrossFaces += owner.face != f;
            }
        }
    }
    // Across each of the 4 edges of 6 faces, 2 border rows of T << l pixels at every level.
    EXPECT_GE(acrossFaces, 6 * 4 * 2 * T * ((int64_t{2} << maxLevel) - 1));
    EXPECT_GT(compared, acrossFaces);
}

TEST(SphereOrtho, BordersAreTheNeighbourFacesPixels) {
    // Levels 0..1 are built whole with a margin beyond the face, levels 2..5 in subtrees.
    expectSeamless(8, 5);
    // The smallest tiles reach furthest beyond the face, relative to its size.
    expectSeamless(4, 5);
}

TEST(SphereOrtho, FinestPixelsAreTheMapAtTheirGeodeticPoint) {
    test::TempDir dir;
    test::writeImage(dir.file("globe.png"), 512, 256, 3, globe(512, 256, false), false);
    SphericalOrthoOptions o = small(16, std::nullopt);
    o.ortho.writeDxt = o.ortho.writeResiduals = false;
    const SphericalOrthoReport report = encodeSphericalOrtho(dir.file("globe.png"), dir.file("out"), o);
    ASSERT_EQ(report.faces.size(), 6u);
    const PlanetBody body = PlanetBody::parse("wgs84");
    EXPECT_EQ(report.body, body.describe());
    for (const SphericalOrthoFaceReport& f : report.faces) {
        EXPECT_EQ(f.ortho.maxLevel, 3); // 16 << 3 = 128 = 512 / 4 pixels across a face
        EXPECT_EQ(f.ortho.outputs.size(), 1u);
        ASSERT_EQ(f.gsd.size(), 4u);
        // Level 3: 90 degrees in 128 pixels, about 78 km at the equator, closer at the corners.
        EXPECT_GT(f.gsd[3].min, 40e3);
        EXPECT_LT(f.gsd[3].min, f.gsd[3].max);
        EXPECT_LT(f.gsd[3].max, 110e3);
        EXPECT_NEAR(f.gsd[2].max, 2 * f.gsd[3].max, 0.05 * f.gsd[2].max);
    }
    const auto tiles = readFaces(dir.file("out"), o.faces);
    const int T = 16, side = T + 4, l = 3;
    const FaceGrid grid{int64_t{T} << l, FaceGridKind::PixelCentres};
    int worst = 0;
    for (const auto& [key, tile] : tiles) {
        const auto [f, level, tx, ty] = key;
        if (level != l) {
            continue;
        }
        for (int j = 0; j < side; ++j) {
            for (int i = 0; i < side; ++i) {
                const FaceSample s{f, static_cast<int64_t>(tx) * T + i - 2, static_cast<int64_t>(ty) * T + j - 2};
                const GeodeticPoint p = body.geodeticOf(direction(cubePoint(grid, s)));
                const auto want = colourOf(p.latitude, p.longitude);
                for (int c = 0; c < 3; ++c) {
                    const int got = tile[(static_cast<size_t>(j) * side + static_cast<size_t>(i)) * 3 +
                                         static_cast<size_t>(c)];
                    const int error = static_cast<int>(std::lround(std::abs(got - want[static_cast<size_t>(c)])));
                    worst = std::max(worst, error);
                    ASSERT_LE(error, 2) << "face " << f << " pixel (" << s.x << "," << s.y << ") channel " << c
                                        << " at " << p.latitude << "," << p.longitude;
                }
            }
        }
    }
    EXPECT_GE(worst, 1); // the comparison saw real rounding, not an empty set
}

TEST(SphereOrtho, SixteenBitInputRoundsToEightBits) {
    test::TempDir dir;
    test::writeImage(dir.file("g8.png"), 128, 64, 3, globe(128, 64, true), false);
    test::writeImage(dir.file("g16.tif"), 128, 64, 3, globe(128, 64, true, 257), true);
    SphericalOrthoOptions o = small(8, 2);
    o.faces = {1, 5};
    o.ortho.writeDxt = o.ortho.writeResiduals = false;
    encodeSphericalOrtho(dir.file("g8.png"), dir.file("eight"), o);
    encodeSphericalOrtho(dir.file("g16.tif"), dir.file("sixteen"), o);
    // v16 = 257 v8, so v16 * 255 / 65535 is the 8-bit interpolation itself, up to float rounding.
    const auto a = readFaces(dir.file("eight"), o.faces);
    const auto b = readFaces(dir.file("sixteen"), o.faces);
    size_t same = 0, total = 0;
    for (const auto& [key, tile] : a) {
        const auto& other = b.at(key);
        ASSERT_EQ(tile.size(), other.size());
        for (size_t k = 0; k < tile.size(); ++k) {
            ASSERT_LE(std::abs(tile[k] - other[k]), 1);
            same += tile[k] == other[k];
        }
        total += tile.size();
    }
    EXPECT_GT(same, total * 99 / 100);
}

TEST(SphereOrtho, IdenticalFilesForAnyThreadCount) {
    test::TempDir dir;
    test::writeImage(dir.file("globe.png"), 128, 64, 3, globe(128, 64, true), false);
    SphericalOrthoOptions o = small(8, 5); // level-5 subtrees in several groups
    o.faces = {2, 6};
    o.ortho.dxtQuality = 0; // the fastest: the test is about the order of the work, not DXT
    int64_t last = 0, total = 0;
    o.ortho.progress = [&](int64_t done, int64_t all) {
        EXPECT_EQ(done, last + 1);
        last = done;
        total = all;
    };
    o.ortho.levels.threads = 1;
    const SphericalOrthoReport one = encodeSphericalOrtho(dir.file("globe.png"), dir.file("one"), o);
    EXPECT_EQ(last, 2 * 1365);
    EXPECT_EQ(total, 2 * 1365);
    last = 0;
    o.ortho.levels.threads = 2;
    const SphericalOrthoReport two = encodeSphericalOrtho(dir.file("globe.png"), dir.file("two"), o);
    EXPECT_EQ(one.threads, 1);
    EXPECT_EQ(two.threads, 2);
    for (const char* f : {"/RGB2.dat", "/dxt/RGB2.dat", "/residuals/RGB2.dat", "/RGB6.dat", "/dxt/RGB6.dat",
                          "/residuals/RGB6.dat"}) {
        const std::string a = test::readFile(dir.file("one") + f);
        EXPECT_GT(a.size(), 500u) << f;
        EXPECT_EQ(a, test::readFile(dir.file("two") + f)) << f;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("one/RGB1.dat")));
    const nlohmann::json j = toJson(one);
    EXPECT_EQ(j["faces"].size(), 2u);
    EXPECT_EQ(j["faces"][1]["face"], 6);
    EXPECT_EQ(j["faces"][1]["ortho"]["max_level"], 5);
    EXPECT_EQ(j["faces"][1]["ground_sample_distance"].size(), 6u);
}

TEST(SphereOrtho, ColourResidualsRebuildBitForBit) {
    test::TempDir dir;
    test::writeImage(dir.file("globe.png"), 128, 64, 3, globe(128, 64, true), false);
    SphericalOrthoOptions o = small(8, 5);
    o.faces = {4};
    o.ortho.writeTiff = o.ortho.writeDxt = false;
    std::map<std::tuple<int, int, int>, std::vector<uint8_t>> recon;
    o.ortho.colourReconstruction = [&](int l, int tx, int ty, const std::vector<uint8_t>& r) {
        recon[{l, tx, ty}] = r;
    };
    const SphericalOrthoReport report = encodeSphericalOrtho(dir.file("globe.png"), dir.file("out"), o);
    ASSERT_EQ(report.faces.size(), 1u);
    ASSERT_EQ(static_cast<int64_t>(recon.size()), report.faces[0].ortho.tiles);
    ColourProducer producer(std::make_shared<OrthoProducer>(dir.file("out/residuals/RGB4.dat")));
    for (const auto& [key, tile] : recon) {
        const auto [l, tx, ty] = key;
        ASSERT_EQ(*producer.tile(l, tx, ty), tile) << "tile (" << l << "," << tx << "," << ty << ")";
    }
    for (const OrthoLevelReport& l : report.faces[0].ortho.levels) {
        EXPECT_LE(l.residualMaxError, 1);
    }
}

TEST(SphereOrtho, PixelsOutsideThePartialExtentAreZero) {
    test::TempDir dir;
    std::vector<uint16_t> px(60 * 40 * 3);
    for (size_t k = 0; k < px.size(); ++k) {
        px[k] = static_cast<uint16_t>(50 + k % 200); // never 0
    }
    test::writeImage(dir.file("part.png"), 60, 40, 3, px, false);
    SphericalOrthoOptions o = small(8, 2);
    o.extent = GeoExtent::parse("-30,-20,30,20");
    o.faces = {1, 3};
    o.ortho.writeDxt = o.ortho.writeResiduals = false;
    encodeSphericalOrtho(dir.file("part.png"), dir.file("out"), o);
    const auto tiles = readFaces(dir.file("out"), o.faces);
    const PlanetBody body = PlanetBody::parse("wgs84");
    const int T = 8, side = T + 4, l = 2;
    const FaceGrid grid{int64_t{T} << l, FaceGridKind::PixelCentres};
    int inside = 0, outside = 0;
    for (const auto& [key, tile] : tiles) {
        const auto [f, level, tx, ty] = key;
        if (level != l) {
            continue;
        }
        for (int j = 2; j < T + 2; ++j) {
            for (int i = 2; i < T + 2; ++i) {
                const FaceSample s{f, static_cast<int64_t>(tx) * T + i - 2, static_cast<int64_t>(ty) * T + j - 2};
                const GeodeticPoint p = body.geodeticOf(direction(cubePoint(grid, s)));
                const bool in = std::abs(p.latitude) < 20.0 - 1e-9 && std::abs(p.longitude) < 30.0 - 1e-9;
                const bool out = std::abs(p.latitude) > 20.0 + 1e-9 || std::abs(p.longitude) > 30.0 + 1e-9;
                const uint8_t* v = &tile[(static_cast<size_t>(j) * side + static_cast<size_t>(i)) * 3];
                for (int c = 0; c < 3; ++c) {
                    if (in) {
                        ASSERT_GT(v[c], 0) << "face " << f << " pixel (" << s.x << "," << s.y << ")";
                    } else if (out) {
                        ASSERT_EQ(v[c], 0) << "face " << f << " pixel (" << s.x << "," << s.y << ")";
                    }
                }
                inside += in && f == 3;
                outside += out;
            }
        }
    }
    EXPECT_GT(inside, 100);
    EXPECT_GT(outside, 32 * 32); // all of face 1, and the rest of face 3
}

// Every file under `dir`, by its path relative to it.
std::map<std::string, std::string> filesUnder(const std::string& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) {
            files[std::filesystem::relative(e.path(), dir).string()] = test::readFile(e.path().string());
        }
    }
    return files;
}

// Levels 0..C of a face are stored only in the blocks the map may reach (sparse_level.hpp), and
// a tile no stored block meets is blank: a map over a box across the edge of faces 3 and 4
// gives, with every output, residuals alone (the coarse-first walk), TIFF alone (one single-pass
// walk) and a region build, the files of the same map saying that it may have values anywhere,
// byte for byte, while asking for a fraction of the points (the subtrees and the bands of
// levels 0..C sample only where the map may reach).
TEST(SphereOrtho, AMapThatSaysWhereItReachesGivesTheFilesOfOneThatMayReachEverywhere) {
    test::TempDir dir;
    const GeoExtent box = GeoExtent::parse("35,5,55,30");
    struct Case {
        const char* name;
        bool tiff, dxt, residuals;
        std::optional<RegionRoot> region;
    };
    for (const Case& c : {Case{"every output", true, true, true, std::nullopt},
                          Case{"residuals", false, false, true, std::nullopt},
                          Case{"tiff", true, false, false, std::nullopt},
                          Case{"region", true, true, true, RegionRoot{3, 7, 5}}}) {
        SCOPED_TRACE(c.name);
        std::map<std::string, std::string> files[2];
        int64_t asked[2] = {0, 0};
        for (const bool everywhere : {true, false}) {
            std::atomic<int64_t> points{0};
            SphericalOrthoOptions o = small(16, 6); // levels 0..2 (coarse first) or 0..4 (single pass) held
            o.ortho.writeTiff = c.tiff;
            o.ortho.writeDxt = c.dxt;
            o.ortho.writeResiduals = c.residuals;
            o.ortho.dxtQuality = 0;
            o.faces = {3, 4};
            if (c.region) {
                o.faces = {3};
                o.ortho.region = RegionRequest{*c.region, ""};
            }
            const std::string out = dir.file(std::string(c.name) + (everywhere ? "-everywhere" : "-box"));
            encodeSphericalOrtho(globalMapSources("box", std::make_unique<test::BoxMap>(box, everywhere, points), 3, 1024,
                                                 SampleType::UInt8),
                                 out, o);
            files[everywhere] = filesUnder(out);
            asked[everywhere] = points;
        }
        ASSERT_FALSE(files[0].empty());
        for (const auto& [name, bytes] : files[1]) {
            ASSERT_TRUE(files[0].count(name)) << name;
            EXPECT_TRUE(files[0].at(name) == bytes) << name << " differs";
        }
        EXPECT_EQ(files[0].size(), files[1].size());
        EXPECT_LT(asked[0] * 2, asked[1]) << asked[0] << " points asked of the box, " << asked[1] << " of everywhere";
    }
}

TEST(SphereOrtho, BadInputWritesNothing) {
    test::TempDir dir;
    std::vector<float> f(32 * 16, 0.5f);
    test::writeFloatRaster(dir.file("float.tif"), 32, 16, f);
    test::writeImage(dir.file("globe.png"), 64, 32, 3, globe(64, 32, false), false);
    auto message = [&](const std::string& input, const SphericalOrthoOptions& o) -> std::string {
        try {
            encodeSphericalOrtho(input, dir.file("out"), o);
        } catch (const Error& e) {
            return e.what();
        }
        return "no error";
    };
    const SphericalOrthoOptions good = small(8, 1);
    EXPECT_NE(message(dir.file("float.tif"), good).find(dir.file("float.tif")), std::string::npos);
    EXPECT_NE(message(dir.file("missing.png"), good).find("missing.png"), std::string::npos);
    SphericalOrthoOptions o = good;
    o.body = "jupiter";
    EXPECT_EQ(message(dir.file("globe.png"), o).rfind("body: ", 0), 0u);
    o = good;
    o.faces = {1, 7};
    EXPECT_EQ(message(dir.file("globe.png"), o).rfind("faces: ", 0), 0u);
    o.faces = {2, 2};
    EXPECT_EQ(message(dir.file("globe.png"), o).rfind("faces: ", 0), 0u);
    o = good;
    o.ortho.levels.tileSize = 2;
    EXPECT_EQ(message(dir.file("globe.png"), o).rfind("tileSize: ", 0), 0u);
    o = good;
    o.extent = GeoExtent{-180.0, -100.0, 180.0, 90.0};
    EXPECT_EQ(message(dir.file("globe.png"), o).rfind("extent: ", 0), 0u);
    o = good;
    o.ortho.levels.channels = 4;
    EXPECT_EQ(message(dir.file("globe.png"), o).rfind("channels: ", 0), 0u);
    o = good;
    o.ortho.name = "";
    EXPECT_EQ(message(dir.file("globe.png"), o).rfind("name: ", 0), 0u);
    EXPECT_FALSE(std::filesystem::exists(dir.file("out")));
}

} // namespace
} // namespace pyramid
