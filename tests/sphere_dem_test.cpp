// preprocessSphericalDem as a library: six faces whose borders are their neighbours' samples,
// reconstructions equal to the CPU producer bit for bit, an analytic map rebuilt within the
// error bound, the geodesy of the body visible end to end, partial extents, determinism and
// bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <tuple>

#include "formats/error.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using Recon = std::map<std::tuple<int, int, int, int>, std::vector<float>>; // face, level, tx, ty

constexpr double kPi = 3.14159265358979323846;

// A global float map of W x H pixel centres holding f(latitude, longitude) in degrees.
template <class F>
std::string writeGlobalMap(const test::TempDir& dir, int W, int H, F f) {
    std::vector<float> v(static_cast<size_t>(W) * H);
    for (int j = 0; j < H; ++j) {
        for (int i = 0; i < W; ++i) {
            const double lat = 90.0 - (j + 0.5) * 180.0 / H;
            const double lon = -180.0 + (i + 0.5) * 360.0 / W;
            v[static_cast<size_t>(i + j * W)] = static_cast<float>(f(lat, lon));
        }
    }
    const std::string path = dir.file("map.tif");
    test::writeFloatRaster(path, W, H, v);
    return path;
}

// Smooth everywhere on the sphere, poles included: a function of the unit vector.
double smoothHeight(double lat, double lon) {
    const double p = lat * kPi / 180.0, l = lon * kPi / 180.0;
    const double x = std::cos(p) * std::cos(l), y = std::cos(p) * std::sin(l), z = std::sin(p);
    return 1000.0 * x + 2000.0 * y + 3000.0 * z + 800.0 * x * y;
}

SphericalDemOptions smallOptions() {
    SphericalDemOptions o;
    o.dem.tileSize = 8;
    o.dem.rootTileSize = 4; // minLevel 1
    o.dem.maxLevel = 3;     // 32 intervals per face: one in-memory level pass, then subtrees
    o.dem.scale = 0.25;
    return o;
}

TEST(SphericalDem, ReconstructionEqualsProducerAndAnalyticMapWithinBound) {
    test::TempDir dir;
    const std::string map = writeGlobalMap(dir, 360, 180, smoothHeight);
    SphericalDemOptions o = smallOptions();
    Recon recon;
    o.reconstruction = [&](int f, int l, int tx, int ty, const std::vector<float>& z) { recon[{f, l, tx, ty}] = z; };
    const SphericalDemReport report = encodeSphericalDem(map, dir.file("out"), o);
    ASSERT_EQ(report.faces.size(), 6u);
    const PlanetBody body = PlanetBody::parse("wgs84");
    for (const SphericalDemFaceReport& fr : report.faces) {
        const ResidualHeader h = fr.dem.header;
        EXPECT_EQ(h.maxLevel, 3);
        EXPECT_EQ(fr.dem.output, dir.file("out") + "/DEM" + std::to_string(fr.face) + ".dat");
        ASSERT_EQ(fr.gsd.size(), 4u);
        // A face spans about 10000 km: 32 intervals of 200 to 400 km at level 3.
        EXPECT_GT(fr.gsd[3].min, 150e3);
        EXPECT_LT(fr.gsd[3].max, 450e3);
        EXPECT_GT(fr.gsd[3].max, fr.gsd[3].min * 1.3);
        for (const ResidualLevelReport& l : fr.dem.levels) {
            EXPECT_LE(l.maxError, 0.125 + 1e-3) << "face " << fr.face << " level " << l.level;
        }
        const int64_t N = 32;
        for (int l = 0; l <= h.maxLevel; ++l) {
            const FileLevelProducer producer = makeFileLevelProducer(fr.dem.output, l);
            const int side = l < h.minLevel ? 1 : 1 << (l - h.minLevel);
            const int n = l < h.minLevel ? h.tileSize >> (h.minLevel - l) : h.tileSize;
            for (int ty = 0; ty < side; ++ty) {
                for (int tx = 0; tx < side; ++tx) {
                    const std::vector<float>& mine = recon.at({fr.face, l, tx, ty});
                    ASSERT_EQ(producer.fileTile(l, tx, ty)->zf, mine) << fr.face << " " << l << " " << tx << " " << ty;
                    if (l != h.maxLevel) {
                        continue;
                    }
                    // The finest level against the function at each vertex's geodetic point:
                    // quantization (scale/2) plus the map's bilinear interpolation error.
                    const FaceGrid grid{N, FaceGridKind::Vertices};
                    for (int j = 2; j < n + 3; ++j) {
                        for (int i = 2; i < n + 3; ++i) {
                            const FaceSample s{fr.face, tx * n + i - 2, ty * n + j - 2};
                            const GeodeticPoint g = body.geodeticOf(direction(cubePoint(grid, s)));
                            const float z = mine[static_cast<size_t>(i + j * (n + 5))];
                            // Within a pixel of a pole the map holds only its last row: the
                            // function varies by up to 3000 x sin(1 degree) around the pole.
                            const double interpolation = std::fabs(g.latitude) > 89.0 ? 60.0 : 2.0;
                            EXPECT_NEAR(z, smoothHeight(g.latitude, g.longitude), 0.125 + interpolation);
                        }
                    }
                }
            }
        }
    }
}

TEST(SphericalDem, BordersAreTheNeighbourFacesSamples) {
    test::TempDir dir;
    const std::string map = writeGlobalMap(dir, 360, 180, smoothHeight);
    const auto source = RasterSource::open(map);
    const EquirectSampler equirect(*source, GeoExtent{}, 0, 1, SampleRead::Float, std::nullopt);
    const PlanetBody body = PlanetBody::parse("wgs84");
    SphericalDemOptions o = smallOptions();
    Recon recon;
    o.reconstruction = [&](int f, int l, int tx, int ty, const std::vector<float>& z) { recon[{f, l, tx, ty}] = z; };
    encodeSphericalDem(map, dir.file("out"), o);
    const int T = 8, minLevel = 1, R = 4;
    int64_t compared = 0;
    for (int face = 1; face <= 6; ++face) {
        for (int l = 0; l <= 3; ++l) {
            const int64_t Nl = static_cast<int64_t>(R) << l;
            const FaceGrid grid{Nl, FaceGridKind::Vertices};
            const FaceSampler here(equirect, body, face, grid);
            const int side = l < minLevel ? 1 : 1 << (l - minLevel);
            const int n = l < minLevel ? T >> (minLevel - l) : T;
            for (int ty = 0; ty < side; ++ty) {
                for (int tx = 0; tx < side; ++tx) {
                    const std::vector<float>& mine = recon.at({face, l, tx, ty});
                    for (int j = 0; j < n + 5; ++j) {
                        for (int i = 0; i < n + 5; ++i) {
                            const int64_t x = static_cast<int64_t>(tx) * n + i - 2, y = static_cast<int64_t>(ty) * n + j - 2;
                            const bool outX = x < 0 || x > Nl, outY = y < 0 || y > Nl;
                            const bool onEdge = x == 0 || x == Nl || y == 0 || y == Nl;
                            if (outX && outY) {
                                continue; // beyond a cube corner: no neighbour
                            }
                            if (!outX && !outY && !onEdge) {
                                continue; // an inner sample of this face
                            }
                            // The other faces holding this cube point: the neighbour across the
                            // edge for a border sample; for an edge sample the face across the
                            // edge (and, at a cube corner, the third face too).
                            std::vector<FaceSample> others;
                            if (outX || outY) {
                                others.push_back(canonicalSample(grid, FaceSample{face, x, y}));
                            } else {
                                const CubePoint p = cubePoint(grid, FaceSample{face, x, y});
                                for (int g = 1; g <= 6; ++g) {
                                    try {
                                        if (g != face) {
                                            others.push_back(faceSampleAt(grid, g, p));
                                        }
                                    } catch (const Error&) { // not on face g
                                    }
                                }
                                const bool corner = (x == 0 || x == Nl) && (y == 0 || y == Nl);
                                EXPECT_EQ(others.size(), corner ? 2u : 1u) << face << " " << x << " " << y;
                            }
                            for (const FaceSample& s : others) {
                                // The source heights are bit-identical: both are the same cube point.
                                float a = 0, b = 0;
                                uint8_t va = 0, vb = 0;
                                here.sample(x, y, 1, 1, 1, &a, &va);
                                FaceSampler(equirect, body, s.face, grid).sample(s.x, s.y, 1, 1, 1, &b, &vb);
                                ASSERT_EQ(a, b);
                                // The reconstructions agree within twice the error bound.
                                const int otx = static_cast<int>(std::min<int64_t>(s.x / n, side - 1));
                                const int oty = static_cast<int>(std::min<int64_t>(s.y / n, side - 1));
                                const std::vector<float>& theirs = recon.at({s.face, l, otx, oty});
                                const int64_t oi = s.x - static_cast<int64_t>(otx) * n + 2, oj = s.y - static_cast<int64_t>(oty) * n + 2;
                                const float z = theirs[static_cast<size_t>(oi + oj * (n + 5))];
                                EXPECT_NEAR(mine[static_cast<size_t>(i + j * (n + 5))], z, 0.25 + 1e-3);
                                EXPECT_NEAR(mine[static_cast<size_t>(i + j * (n + 5))], a, 0.125 + 1e-3);
                                ++compared;
                            }
                        }
                    }
                }
            }
        }
    }
    EXPECT_GT(compared, 6 * 4 * 4 * 4);
}

TEST(SphericalDem, Wgs84AndSphereDifferAsGeodesySays) {
    test::TempDir dir;
    // Height = 100 x latitude: bilinear interpolation is exact, so heights read latitudes.
    const std::string map = writeGlobalMap(dir, 720, 360, [](double lat, double) { return 100.0 * lat; });
    SphericalDemOptions o = smallOptions();
    o.faces = {3};
    o.dem.scale = 0.5; // heights up to 9000: residuals fit int16
    std::map<std::string, Recon> finest;
    for (const std::string body : {"wgs84", "sphere"}) {
        o.body = body;
        o.reconstruction = [&](int f, int l, int tx, int ty, const std::vector<float>& z) {
            finest[body][{f, l, tx, ty}] = z;
        };
        encodeSphericalDem(map, dir.file(body), o);
    }
    const double wgs84Squash = std::pow(1.0 - 1.0 / 298.257223563, 2); // (b / a)^2
    auto geodeticOf = [&](double geocentric) {
        return std::atan(std::tan(geocentric * kPi / 180.0) / wgs84Squash) * 180.0 / kPi;
    };
    // Face 3 is (1, u, v): vertex (16, 32) is (1, 0, 1), geocentric latitude 45 degrees, where
    // WGS84's geodetic latitude is 0.192 degrees more; vertex (32, 32) is the corner (1, 1, 1),
    // latitude atan(1 / sqrt 2) = 35.26 degrees, 0.181 degrees more.
    struct Probe {
        int tx, i;
        double geocentric;
    };
    for (const Probe p : {Probe{2, 0, 45.0}, Probe{3, 8, std::atan(1.0 / std::sqrt(2.0)) * 180.0 / kPi}}) {
        const size_t k = static_cast<size_t>((p.i + 2) + (8 + 2) * 13);
        const float sphere = finest["sphere"].at({3, 3, p.tx, 3})[k];
        const float wgs84 = finest["wgs84"].at({3, 3, p.tx, 3})[k];
        EXPECT_NEAR(sphere, 100.0 * p.geocentric, 0.25 + 1e-3);
        EXPECT_NEAR(wgs84, 100.0 * geodeticOf(p.geocentric), 0.25 + 1e-3);
        EXPECT_NEAR(wgs84 - sphere, 100.0 * (geodeticOf(p.geocentric) - p.geocentric), 0.5 + 1e-3);
    }
    EXPECT_NEAR(geodeticOf(45.0) - 45.0, 0.192, 0.001);
}

TEST(SphericalDem, IdenticalBytesForAnyThreadCount) {
    test::TempDir dir;
    const std::string map = writeGlobalMap(dir, 360, 180, smoothHeight);
    SphericalDemOptions o = smallOptions();
    o.dem.threads = 1;
    encodeSphericalDem(map, dir.file("one"), o);
    o.dem.threads = 2;
    encodeSphericalDem(map, dir.file("two"), o);
    for (int f = 1; f <= 6; ++f) {
        const std::string name = "/DEM" + std::to_string(f) + ".dat";
        EXPECT_EQ(test::readFile(dir.file("one") + name), test::readFile(dir.file("two") + name)) << name;
    }
}

TEST(SphericalDem, PartialExtentFillsTheRest) {
    test::TempDir dir;
    // A map of Europe only; faces 1 (north pole) and 3 (longitude 0) see it, face 6 does not.
    std::vector<float> v(40 * 20, 500.0f);
    const std::string map = dir.file("europe.tif");
    test::writeFloatRaster(map, 40, 20, v);
    SphericalDemOptions o = smallOptions();
    o.extent = GeoExtent::parse("-10,35,30,75");
    o.faces = {3, 6};
    const SphericalDemReport r = encodeSphericalDem(map, dir.file("out"), o);
    ASSERT_EQ(r.faces.size(), 2u);
    EXPECT_GT(r.faces[0].dem.levels.back().samples, 0);
    EXPECT_GT(r.faces[0].dem.nodataFilled, 0);
    EXPECT_EQ(r.faces[1].dem.levels.back().samples, 0);
    EXPECT_EQ(r.faces[1].dem.nodataFilled, 33 * 33);
    EXPECT_EQ(r.faces[1].dem.sharedTiles, r.faces[1].dem.tiles - 2); // zeros: one blob per tile size
    EXPECT_FALSE(std::filesystem::exists(dir.file("out") + "/DEM1.dat"));
}

// A map of one region (longitudes -30..60, latitudes 10..70: faces 1, 3 and 4) holding heights
// from 300 to 700: the rest of the planet is nodata, filled as one surface.
std::string writeRegionMap(const test::TempDir& dir) {
    const int W = 90, H = 60;
    std::vector<float> v(static_cast<size_t>(W) * H);
    for (int j = 0; j < H; ++j) {
        for (int i = 0; i < W; ++i) {
            const double lat = 70.0 - (j + 0.5), lon = -30.0 + (i + 0.5);
            v[static_cast<size_t>(i + j * W)] =
                static_cast<float>(500.0 + 150.0 * std::sin(lon * kPi / 45.0) + 50.0 * std::cos(lat * kPi / 30.0));
        }
    }
    const std::string path = dir.file("region.tif");
    test::writeFloatRaster(path, W, H, v);
    return path;
}

SphericalDemOptions regionOptions() {
    SphericalDemOptions o = smallOptions();
    o.extent = GeoExtent::parse("-30,10,60,70");
    return o;
}

// The largest difference between the values that faces' tiles of `level` hold at one cube point
// (edges, corners, the borders beyond one edge); counts the points compared.
double sharedPointSpread(const Recon& recon, int level, int64_t& compared) {
    const int T = 8, minLevel = 1, R = 4;
    const int64_t Nl = static_cast<int64_t>(R) << level;
    const FaceGrid grid{Nl, FaceGridKind::Vertices};
    const int side = level < minLevel ? 1 : 1 << (level - minLevel);
    const int n = level < minLevel ? T >> (minLevel - level) : T;
    std::map<std::tuple<int64_t, int64_t, int64_t>, std::pair<float, float>> range; // smallest, largest
    for (int face = 1; face <= 6; ++face) {
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                const std::vector<float>& z = recon.at({face, level, tx, ty});
                for (int j = 0; j < n + 5; ++j) {
                    for (int i = 0; i < n + 5; ++i) {
                        const int64_t x = static_cast<int64_t>(tx) * n + i - 2, y = static_cast<int64_t>(ty) * n + j - 2;
                        if ((x < 0 || x > Nl) && (y < 0 || y > Nl)) {
                            continue; // beyond a cube corner: the face's own
                        }
                        const CubePoint p = cubePoint(grid, FaceSample{face, x, y});
                        const float v = z[static_cast<size_t>(i + j * (n + 5))];
                        auto [it, fresh] = range.try_emplace({p.x, p.y, p.z}, v, v);
                        if (!fresh) {
                            it->second.first = std::min(it->second.first, v);
                            it->second.second = std::max(it->second.second, v);
                            ++compared;
                        }
                    }
                }
            }
        }
    }
    double spread = 0.0;
    for (const auto& [key, r] : range) {
        spread = std::max(spread, static_cast<double>(r.second - r.first));
    }
    return spread;
}

TEST(SphericalDem, NodataIsFilledAsOneSurfaceAcrossTheCube) {
    test::TempDir dir;
    const std::string map = writeRegionMap(dir);
    SphericalDemOptions o = regionOptions();
    Recon recon;
    o.reconstruction = [&](int f, int l, int tx, int ty, const std::vector<float>& z) { recon[{f, l, tx, ty}] = z; };
    const SphericalDemReport r = encodeSphericalDem(map, dir.file("out"), o);
    ASSERT_EQ(r.faces.size(), 6u);
    EXPECT_EQ(r.faces[5].dem.levels.back().samples, 0); // face 6 (south pole): no source height
    // The root tiles: every cube point that several faces hold has one value in all of them.
    int64_t compared = 0;
    EXPECT_EQ(sharedPointSpread(recon, 0, compared), 0.0);
    EXPECT_GT(compared, 6 * 4 * 4);
    // The fill stays within the source heights (300 to 700) everywhere, faces without a source
    // height included (not 0, not a constant of their own).
    float low = 1e9f, high = -1e9f;
    for (int face = 1; face <= 6; ++face) {
        for (const float z : recon.at({face, 0, 0, 0})) {
            low = std::min(low, z), high = std::max(high, z);
        }
    }
    EXPECT_GT(low, 300.0f - 0.125f);
    EXPECT_LT(high, 700.0f + 0.125f);
    // Deeper levels predict the holes from these roots, each face with its own tiles: where
    // faces meet, the filled heights meet too, but for a few metres where a cube corner lies
    // next to the map's edge (each face unfolds the corner its own way). A fill of each face
    // from its own samples left steps of 520 m here.
    for (int level = 1; level <= 3; ++level) {
        compared = 0;
        EXPECT_LT(sharedPointSpread(recon, level, compared), 12.0) << "level " << level;
        EXPECT_GT(compared, 0);
    }
}

TEST(SphericalDem, AMapBetweenRootSamplesLeavesOneHeightEverywhere) {
    test::TempDir dir;
    // Heights 100 to 300 over 4 x 4 degrees, between the root samples (22.5 degrees apart).
    std::vector<float> v(16 * 16);
    for (size_t k = 0; k < v.size(); ++k) {
        v[k] = 100.0f + 200.0f * static_cast<float>(k % 16) / 15.0f;
    }
    const std::string map = dir.file("patch.tif");
    test::writeFloatRaster(map, 16, 16, v);
    SphericalDemOptions o = smallOptions();
    o.extent = GeoExtent::parse("5,44,9,48");
    Recon recon;
    o.reconstruction = [&](int f, int l, int tx, int ty, const std::vector<float>& z) { recon[{f, l, tx, ty}] = z; };
    encodeSphericalDem(map, dir.file("out"), o);
    // The six root tiles hold one height, from the map's samples: no face at 0, none at a
    // height of its own.
    const float first = recon.at({1, 0, 0, 0})[0];
    EXPECT_GT(first, 100.0f);
    EXPECT_LT(first, 300.0f);
    for (int face = 1; face <= 6; ++face) {
        for (const float z : recon.at({face, 0, 0, 0})) {
            ASSERT_EQ(z, first) << "face " << face;
        }
    }
}

TEST(SphericalDem, AFillHeightIsTheHeightOfTheRootsNodata) {
    test::TempDir dir;
    const std::string map = writeRegionMap(dir);
    SphericalDemOptions o = regionOptions();
    o.fillHeight = -20.0;
    Recon recon;
    o.reconstruction = [&](int f, int l, int tx, int ty, const std::vector<float>& z) { recon[{f, l, tx, ty}] = z; };
    const SphericalDemReport r = encodeSphericalDem(map, dir.file("out"), o);
    EXPECT_EQ(r.fillHeight, -20.0);
    // Every root sample on the cube is the map's (300 to 700) or the given height, on every face
    // (those beyond a cube corner, each face's own, lie between); the south pole's face holds
    // none of the map.
    int64_t given = 0;
    for (int face = 1; face <= 6; ++face) {
        const std::vector<float>& root = recon.at({face, 0, 0, 0});
        for (int k = 0; k < 81; ++k) {
            const int x = k % 9 - 2, y = k / 9 - 2;
            if ((x < 0 || x > 4) && (y < 0 || y > 4)) {
                continue;
            }
            const float z = root[static_cast<size_t>(k)];
            if (z == -20.0f) {
                ++given;
            } else {
                EXPECT_GT(z, 300.0f - 0.125f) << "face " << face;
                EXPECT_LT(z, 700.0f + 0.125f) << "face " << face;
            }
        }
    }
    for (const float z : recon.at({6, 0, 0, 0})) {
        ASSERT_EQ(z, -20.0f);
    }
    EXPECT_GT(given, 2 * 9 * 9);
    int64_t compared = 0;
    EXPECT_EQ(sharedPointSpread(recon, 0, compared), 0.0);
    o.fillHeight = std::nan("");
    EXPECT_THROW(encodeSphericalDem(map, dir.file("bad"), o), OptionError);
}

TEST(SphericalDem, AFaceBuiltAloneIsTheFaceOfTheWholePlanet) {
    test::TempDir dir;
    const std::string map = writeRegionMap(dir);
    SphericalDemOptions o = regionOptions();
    encodeSphericalDem(map, dir.file("all"), o);
    for (const int face : {3, 6}) { // one the map reaches, one it does not
        o.faces = {face};
        const std::string alone = dir.file("face" + std::to_string(face));
        encodeSphericalDem(map, alone, o);
        const std::string name = "/DEM" + std::to_string(face) + ".dat";
        EXPECT_EQ(test::readFile(alone + name), test::readFile(dir.file("all") + name)) << name;
    }
}

TEST(SphericalDem, BadInputWritesNothing) {
    test::TempDir dir;
    const std::string map = writeGlobalMap(dir, 36, 18, smoothHeight);
    const std::string out = dir.file("out");
    auto expectError = [&](SphericalDemOptions o, const std::string& input, const std::string& words) {
        try {
            encodeSphericalDem(input, out, o);
            ADD_FAILURE() << "no error for " << words;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
        EXPECT_TRUE(!std::filesystem::exists(out) || std::filesystem::is_empty(out)) << words;
    };
    SphericalDemOptions o = smallOptions();
    o.body = "jupiter";
    expectError(o, map, "body: ");
    o = smallOptions();
    o.faces = {1, 7};
    expectError(o, map, "faces: ");
    o = smallOptions();
    expectError(o, dir.file("missing.tif"), "missing.tif");
    o = smallOptions();
    o.dem.band = 3;
    expectError(o, map, "band: ");
    // An overflow at the last face: the first five faces must not be left behind.
    o = smallOptions();
    o.dem.scale = 0.001;
    expectError(o, map, "overflow");
}

} // namespace
} // namespace pyramid
