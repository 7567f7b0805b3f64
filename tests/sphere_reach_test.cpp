// A small map on a planet: the spherical encoders skip the parts of the cube the map cannot
// reach, and the files are those that encoding every sample would give.
// * FaceSampler::mayHaveValues never says "no value" for a rectangle holding a valid sample
//   (maps near a pole, across the antimeridian, small ones; rectangles across face edges);
// * a DEM encoded with the skip is byte-identical to one encoded without it (the
//   reconstruction hook turns it off);
// * a fine map at its default finest level (hundreds of thousands of tiles a face) is
//   encoded, with its colours where the map lies and black elsewhere.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "formats/ortho_file.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/face_locate.hpp"
#include "libpyramid/sphere/face_sampler.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sparse_sets.hpp"

namespace pyramid {
namespace {

std::vector<uint8_t> bytesOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct MapCase {
    double west, north, step;
    int width, height;
};

TEST(SphericalReach, MayHaveValuesNeverMissesAValue) {
    test::TempDir dir;
    const PlanetBody body = PlanetBody::parse("wgs84");
    const MapCase cases[] = {
        {-122.0, 48.0, 1.0 / 16.0, 32, 32}, // a small map
        {170.0, 10.0, 0.5, 40, 40},         // across the antimeridian
        {60.0, 89.5, 0.5, 120, 30},         // up to half a degree from the north pole
        {-30.0, -70.0, 0.5, 120, 39},       // down to half a degree from the south pole
    };
    std::mt19937 random(7);
    int refused = 0, held = 0;
    for (const MapCase& c : cases) {
        const std::string path = dir.file("map" + std::to_string(refused + held) + ".tif");
        test::writeGeoTiff(path, c.width, c.height,
                           std::vector<float>(static_cast<size_t>(c.width * c.height), 1.0f),
                           test::geographicTags(4326, c.west, c.north, c.step));
        const auto source = RasterSource::open(path);
        const MapPlacement placement = placeMap(source->info(), path, std::nullopt, body);
        const EquirectSampler map(*source, placement, 0, 1, SampleRead::Float, std::nullopt);
        constexpr int64_t N = 512;
        for (int face = 1; face <= 6; ++face) {
            const FaceSampler sampler(map, body, face, FaceGrid{N, FaceGridKind::Vertices});
            std::uniform_int_distribution<int64_t> corner(-16, N + 16), side(0, 63);
            std::vector<float> values;
            std::vector<uint8_t> valid;
            for (int k = 0; k < 150; ++k) {
                const int64_t x0 = corner(random), y0 = corner(random);
                const int64_t x1 = std::min(N + 16, x0 + side(random)), y1 = std::min(N + 16, y0 + side(random));
                values.resize(static_cast<size_t>((x1 - x0 + 1) * (y1 - y0 + 1)));
                valid.resize(values.size());
                sampler.sample(x0, y0, 1, x1 - x0 + 1, y1 - y0 + 1, values.data(), valid.data());
                const bool any = std::find(valid.begin(), valid.end(), uint8_t{1}) != valid.end();
                const bool may = sampler.mayHaveValues(x0, y0, x1, y1);
                if (any) {
                    ++held;
                    EXPECT_TRUE(may) << "face " << face << " [" << x0 << "," << x1 << "]x[" << y0 << "," << y1
                                     << "] holds a value of the map at " << c.west << "," << c.north;
                }
                refused += may ? 0 : 1;
            }
        }
    }
    // Both answers occurred: the test saw rectangles with values and rectangles it skipped.
    EXPECT_GT(held, 20);
    EXPECT_GT(refused, 1000);
}

TEST(SphericalReach, AFaceBeyondTheMapsLongitudesIsRefusedWhole) {
    test::TempDir dir;
    const PlanetBody body = PlanetBody::parse("wgs84");
    // Longitudes -90 to 90, latitudes -22.5 to 67.5: face 5 (longitude 180, 135 E to 135 W at
    // the equator) shares its latitudes but none of its longitudes.
    const std::string path = dir.file("half.tif");
    test::writeGeoTiff(path, 64, 32, std::vector<float>(64 * 32, 1.0f), test::geographicTags(4326, -90.0, 67.5, 2.8125));
    const auto source = RasterSource::open(path);
    const MapPlacement placement = placeMap(source->info(), path, std::nullopt, body);
    const EquirectSampler map(*source, placement, 0, 1, SampleRead::Float, std::nullopt);
    constexpr int64_t N = 512;
    const FaceSampler face5(map, body, 5, FaceGrid{N, FaceGridKind::Vertices});
    EXPECT_FALSE(face5.mayHaveValues(0, 0, N, N));
    for (int64_t y = 0; y < N; y += 64) {
        for (int64_t x = 0; x < N; x += 64) {
            EXPECT_FALSE(face5.mayHaveValues(x, y, x + 64, y + 64)) << x << "," << y;
        }
    }
    // Face 3 (longitude 0) holds the map, face 4 (90 E) its eastern edge.
    EXPECT_TRUE(FaceSampler(map, body, 3, FaceGrid{N, FaceGridKind::Vertices}).mayHaveValues(0, 0, N, N));
    EXPECT_TRUE(FaceSampler(map, body, 4, FaceGrid{N, FaceGridKind::Vertices}).mayHaveValues(0, 0, N, N));
}

TEST(SphericalReach, SkippedSubtreesAreTheTilesEncodingWouldWrite) {
    test::TempDir dir;
    // 2 x 2 degrees near Mount Rainier, heights varying in both directions.
    const int W = 64;
    std::vector<float> heights(static_cast<size_t>(W * W));
    for (int j = 0; j < W; ++j) {
        for (int i = 0; i < W; ++i) {
            heights[static_cast<size_t>(i + j * W)] = 1000.0f + 37.0f * static_cast<float>(i) - 21.0f * static_cast<float>(j) +
                                                      (i * j % 7 == 0 ? 50.0f : 0.0f);
        }
    }
    const std::string map = dir.file("map.tif");
    test::writeGeoTiff(map, W, W, heights, test::geographicTags(4326, -122.5, 47.5, 2.0 / W));
    SphericalDemOptions o;
    o.dem.tileSize = 32;
    o.dem.rootTileSize = 4;
    o.dem.maxLevel = 8; // subtrees below level 5: most of them beyond the map
    o.dem.scale = 0.25;
    o.dem.layout = PyramidLayout::Dense; // one file of every tile per face, to compare byte for byte
    const SphericalDemReport skipped = encodeSphericalDem(map, dir.file("skipped"), o);
    int64_t tiles = 0;
    o.reconstruction = [&](int, int, int, int, const std::vector<float>&) { ++tiles; };
    const SphericalDemReport full = encodeSphericalDem(map, dir.file("full"), o);
    EXPECT_EQ(tiles, 6 * full.faces[0].dem.tiles);
    ASSERT_EQ(skipped.faces.size(), 6u);
    for (int f = 1; f <= 6; ++f) {
        const std::string name = "/DEM" + std::to_string(f) + ".dat";
        const std::vector<uint8_t> a = bytesOf(dir.file("skipped") + name), b = bytesOf(dir.file("full") + name);
        EXPECT_FALSE(a.empty());
        EXPECT_TRUE(a == b) << "face " << f;
        const auto& s = skipped.faces[static_cast<size_t>(f - 1)].dem;
        const auto& u = full.faces[static_cast<size_t>(f - 1)].dem;
        EXPECT_EQ(s.nodataFilled, u.nodataFilled) << "face " << f;
        ASSERT_EQ(s.levels.size(), u.levels.size());
        for (size_t l = 0; l < s.levels.size(); ++l) {
            EXPECT_EQ(s.levels[l].samples, u.levels[l].samples);
            EXPECT_EQ(s.levels[l].maxError, u.levels[l].maxError);
            EXPECT_EQ(s.levels[l].rmsError, u.levels[l].rmsError);
        }
    }
    // The map reached face 1 (47 N): its finest level compared source samples.
    EXPECT_GT(skipped.faces[0].dem.levels.back().samples, 100);
    // The sparse default at a finer level: face 1 is the dense file where the map is and nothing
    // elsewhere; face 2, which the map does not reach, is its top levels alone (levels 0..minLevel).
    o.reconstruction = nullptr;
    o.faces = {1, 2};
    o.dem.maxLevel = 11;
    o.dem.layout = PyramidLayout::Sparse;
    const SphericalDemReport sparse = encodeSphericalDem(map, dir.file("sparse"), o);
    o.dem.layout = PyramidLayout::Dense;
    const SphericalDemReport dense = encodeSphericalDem(map, dir.file("dense"), o);
    for (int f = 1; f <= 2; ++f) {
        const std::string name = "/DEM" + std::to_string(f) + ".dat";
        const int64_t beyond = test::expectSparseSetOfDense(dir.file("dense") + name, dir.file("sparse") + name);
        const auto& s = sparse.faces[static_cast<size_t>(f - 1)].dem;
        const auto& d = dense.faces[static_cast<size_t>(f - 1)].dem;
        EXPECT_LT(s.bytes * 5, d.bytes) << "face " << f;
        uint64_t total = 0;
        for (const auto& [file, bytes] : s.files) {
            total += bytes;
            EXPECT_EQ(std::filesystem::file_size(dir.file("sparse") + "/" + file), bytes) << file;
        }
        EXPECT_EQ(s.bytes, total) << "face " << f;
        if (f == 1) {
            EXPECT_GE(s.files.size(), 2u);
        } else {
            EXPECT_EQ(s.tiles, 4);
            EXPECT_EQ(beyond, d.tiles - 4);
        }
    }
    SphericalDemVerifyOptions vo;
    vo.faces = {1, 2};
    for (const DemVerifyReport& r : verifySphericalDem(dir.file("sparse"), std::vector<std::string>{map}, vo)) {
        EXPECT_TRUE(r.ok()) << r.file;
    }
    EXPECT_EQ(verifySphericalDem(dir.file("sparse"), std::vector<std::string>{map}, vo).front().levels.size(), 12u);
}

TEST(SphericalReach, FineImageryAtItsDefaultLevel) {
    test::TempDir dir;
    // 96 x 96 pixels of 12 arc-seconds (1/300 degree) at 46.5 N 121.5 W, one colour.
    const int W = 96;
    std::vector<uint8_t> rgb(static_cast<size_t>(W * W * 3));
    for (size_t k = 0; k < rgb.size(); k += 3) {
        rgb[k] = 200;
        rgb[k + 1] = 120;
        rgb[k + 2] = 40;
    }
    const std::string map = dir.file("map.tif");
    test::writeGeoTiffRgb(map, W, W, rgb, test::geographicTags(4326, -121.66, 46.66, 1.0 / 300.0));
    SphericalOrthoOptions o;
    o.ortho.writeDxt = false;
    o.ortho.writeResiduals = false;
    o.faces = {1}; // the face under the map (87381 tiles, nearly all skipped as blank)
    const SphericalOrthoReport r = encodeSphericalOrtho(map, dir.file("out"), o);
    // 108000 pixels around the equator: 27000 a face, level 8 of 192-pixel tiles (87381 tiles).
    ASSERT_EQ(r.faces.size(), 1u);
    const int T = r.faces[0].ortho.tileSize, M = r.faces[0].ortho.maxLevel;
    EXPECT_EQ(M, 8);
    // The finest tile under the map's centre holds its colour; tiles far from it are black.
    const PlanetBody body = PlanetBody::parse(o.body);
    const FacePoint p = facePointOf(directionOf(body, GeodeticPoint{46.5, -121.5}));
    ASSERT_EQ(p.face, 1);
    const int64_t n = int64_t{T} << M;
    const int64_t x = static_cast<int64_t>((p.u + 1.0) / 2.0 * static_cast<double>(n));
    const int64_t y = static_cast<int64_t>((p.v + 1.0) / 2.0 * static_cast<double>(n));
    // A sparse set (the default layout): the map's tiles, and no tile far from it.
    const auto reader = openOrthoSet(dir.file("out") + "/RGB1.dat");
    const std::vector<uint8_t> tile = reader->tile(M, static_cast<int>(x / T), static_cast<int>(y / T));
    ASSERT_EQ(tile.size(), static_cast<size_t>((T + 4) * (T + 4) * 3));
    int64_t coloured = 0;
    for (size_t k = 0; k < tile.size(); k += 3) {
        coloured += tile[k] == 200 && tile[k + 1] == 120 && tile[k + 2] == 40;
    }
    EXPECT_GT(coloured, T * T / 8) << "tile " << x / T << "," << y / T << " of level " << M;
    EXPECT_FALSE(reader->hasTile(M, 0, 0));
    EXPECT_TRUE(reader->hasTile(0, 0, 0));
    // The set is the map's few tiles: a main file of the top levels and a region or two.
    EXPECT_LT(r.faces[0].ortho.bytes[0], 200000u);
}

} // namespace
} // namespace pyramid
