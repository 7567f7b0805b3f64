// Resolution where the data is (doc/spherical.md, "Files where the map is"): a planet built in one
// run from a coarse global base and a fine inset goes down to the inset's level where the inset
// is, and no deeper than the base's level elsewhere; its heights are the inset's in the inset and
// the base's elsewhere, the faces the inset does not reach are those of the base alone, and the
// files are a small fraction of the dense layout's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/aperture/aperture.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/face_locate.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

// The base: 5-degree pixels over the globe, a smooth field. The inset: 2 x 2 degrees of
// 1/60-degree pixels at 46..48 N, 123..121 W, with relief the base does not have.
double baseHeight(double lon, double lat) { return 800.0 + 600.0 * std::cos(lat * M_PI / 180.0) * std::sin(lon * M_PI / 60.0); }
double insetHeight(double lon, double lat) {
    return 1500.0 + 900.0 * std::sin((lon + 122.0) * 9.0) * std::cos((lat - 47.0) * 7.0);
}

struct Maps {
    std::string base, inset;
};

Maps writeMaps(const test::TempDir& dir) {
    Maps m{dir.file("base.tif"), dir.file("inset.tif")};
    std::vector<float> base(72 * 36);
    for (int j = 0; j < 36; ++j) {
        for (int i = 0; i < 72; ++i) {
            base[static_cast<size_t>(i + 72 * j)] =
                static_cast<float>(baseHeight(-180.0 + 5.0 * (i + 0.5), 90.0 - 5.0 * (j + 0.5)));
        }
    }
    test::writeGeoTiff(m.base, 72, 36, base, test::geographicTags(4326, -180.0, 90.0, 5.0));
    std::vector<float> inset(120 * 120);
    for (int j = 0; j < 120; ++j) {
        for (int i = 0; i < 120; ++i) {
            inset[static_cast<size_t>(i + 120 * j)] =
                static_cast<float>(insetHeight(-123.0 + (i + 0.5) / 60.0, 48.0 - (j + 0.5) / 60.0));
        }
    }
    test::writeGeoTiff(m.inset, 120, 120, inset, test::geographicTags(4326, -123.0, 48.0, 1.0 / 60.0));
    return m;
}

// 32-interval tiles under 4-interval roots, heights in quarters of a metre.
SphericalDemOptions demOptions() {
    SphericalDemOptions o;
    o.dem.tileSize = 32;
    o.dem.rootTileSize = 4;
    o.dem.scale = 0.25;
    return o;
}

// The height the set of the face holding (lon, lat) gives there, and its level.
PointHeight heightAtLonLat(const std::string& directory, double lon, double lat) {
    const FacePoint p = facePointOf(directionOf(PlanetBody::parse("wgs84"), GeodeticPoint{lat, lon}));
    return setHeightAt(faceFilePath(directory, "DEM", p.face), (p.u + 1.0) / 2.0, (p.v + 1.0) / 2.0);
}

TEST(SphereMultiResolution, AnInsetOverABaseGoesDeepOnlyWhereItIs) {
    test::TempDir dir;
    const Maps maps = writeMaps(dir);
    SphericalDemOptions o = demOptions();
    const SphericalDemReport both = encodeSphericalDem(std::vector<std::string>{maps.base, maps.inset}, dir.file("both"), o);
    const SphericalDemReport base = encodeSphericalDem(maps.base, dir.file("base"), o);
    // The inset's 21600 columns around the equator: level 11 of 4-interval roots; the base's 72: level 3.
    EXPECT_EQ(both.faces[0].dem.header.maxLevel, 11);
    EXPECT_EQ(base.faces[0].dem.header.maxLevel, 3);
    // The faces far from the inset are the base's, byte for byte (face 2's borders reach into
    // face 1 near the inset).
    for (int face = 3; face <= 6; ++face) {
        EXPECT_TRUE(test::readFile(faceFilePath(dir.file("both"), "DEM", face)) ==
                    test::readFile(faceFilePath(dir.file("base"), "DEM", face)))
            << "face " << face;
    }
    // Every face against both maps: each level's tiles where a map of that level or a finer one is.
    SphericalDemVerifyOptions vo;
    for (const DemVerifyReport& r : verifySphericalDem(dir.file("both"), std::vector<std::string>{maps.base, maps.inset}, vo)) {
        EXPECT_TRUE(r.ok()) << r.file;
    }
    // In the inset, its heights at its level; beyond it, the base's level and the base's heights.
    std::vector<double> errors;
    for (int j = 0; j < 10; ++j) {
        for (int i = 0; i < 10; ++i) {
            const double lon = -122.9 + 0.18 * i, lat = 46.1 + 0.18 * j;
            const PointHeight p = heightAtLonLat(dir.file("both"), lon, lat);
            EXPECT_EQ(p.level, 11) << lon << "," << lat;
            errors.push_back(std::fabs(p.height - insetHeight(lon, lat)));
        }
    }
    std::sort(errors.begin(), errors.end());
    EXPECT_LT(errors[errors.size() / 2], 15.0);
    // (The base's bilinear samples of 5-degree pixels are within a few metres of its field.)
    for (const auto& [lon, lat] : std::vector<std::pair<double, double>>{{10.0, 50.0}, {-100.0, 30.0}, {-122.0, 30.0}}) {
        const PointHeight p = heightAtLonLat(dir.file("both"), lon, lat);
        EXPECT_LT(p.level, 9) << lon << "," << lat;
        EXPECT_NEAR(p.height, baseHeight(lon, lat), 15.0) << lon << "," << lat;
    }
    // A small fraction of every level of every face at the inset's level.
    o.dem.layout = PyramidLayout::Dense;
    o.faces = {1};
    const SphericalDemReport dense = encodeSphericalDem(std::vector<std::string>{maps.base, maps.inset}, dir.file("dense"), o);
    EXPECT_LT(both.faces[0].dem.bytes * 5, dense.faces[0].dem.bytes);
    EXPECT_LT(test::bytesUnder(dir.file("both")), dense.faces[0].dem.bytes);
}

// The aperture of such a planet (preprocessSphericalAperture) has each face's levels where the
// face has them: deep over the inset, the base's level elsewhere, each level searched at its own
// spacing, so that a face far from the inset is the aperture of the base alone, byte for byte.
TEST(SphereMultiResolution, TheApertureGoesDeepOnlyWhereTheInsetIs) {
    test::TempDir dir;
    const Maps maps = writeMaps(dir);
    SphericalDemOptions o = demOptions();
    encodeSphericalDem(std::vector<std::string>{maps.base, maps.inset}, dir.file("both"), o);
    encodeSphericalDem(maps.base, dir.file("base"), o);
    SphericalApertureOptions a;
    a.search.directions = 8;
    a.search.radius = 4;
    a.threads = 2;
    // DEM levels 3..11 (minLevel 3): aperture levels 0..8; the base alone: level 0.
    const SphericalApertureReport both = encodeSphericalApertureFiles(dir.file("both"), dir.file("ap-both"), a);
    EXPECT_EQ(both.maxLevel, 8);
    EXPECT_EQ(encodeSphericalApertureFiles(dir.file("base"), dir.file("ap-base"), a).maxLevel, 0);
    EXPECT_TRUE(test::readFile(faceFilePath(dir.file("ap-both"), "APERTURE", 6)) ==
                test::readFile(faceFilePath(dir.file("ap-base"), "APERTURE", 6)));
    // The deepest aperture tile at a point, and its pixel's visible sky there.
    const auto deepest = [&](double lon, double lat) {
        const FacePoint p = facePointOf(directionOf(PlanetBody::parse("wgs84"), GeodeticPoint{lat, lon}));
        const auto set = openOrthoSet(faceFilePath(dir.file("ap-both"), "APERTURE", p.face));
        std::pair<int, int> d{-1, 0};
        for (int l = 0; l <= set->maxLevel(); ++l) {
            const double x = (p.u + 1.0) / 2.0 * (32 << l), y = (p.v + 1.0) / 2.0 * (32 << l);
            const int tx = static_cast<int>(x) / 32, ty = static_cast<int>(y) / 32;
            if (!set->hasTile(l, tx, ty)) {
                break;
            }
            const std::vector<uint8_t> t = set->tile(l, tx, ty);
            const int px = static_cast<int>(x) - tx * 32 + 2, py = static_cast<int>(y) - ty * 32 + 2;
            d = {l, t[static_cast<size_t>((py * 36 + px) * 3)]};
        }
        return d;
    };
    int hidden = 0;
    for (int k = 0; k < 9; ++k) {
        const auto [level, visible] = deepest(-122.8 + 0.2 * k, 46.2 + 0.2 * k);
        EXPECT_EQ(level, 8);
        hidden += visible < 250; // the inset's relief hides some sky
    }
    EXPECT_GT(hidden, 0);
    // Elsewhere, the levels the face's files hold there (DEM level 3 + l): its main file's, which
    // the sparse layout takes a few levels past the base's, far short of the inset's.
    for (const auto& [lon, lat] : std::vector<std::pair<double, double>>{{10.0, 50.0}, {-100.0, 30.0}, {60.0, -40.0}}) {
        const FacePoint p = facePointOf(directionOf(PlanetBody::parse("wgs84"), GeodeticPoint{lat, lon}));
        const PyramidSet set = openPyramidSet(faceFilePath(dir.file("both"), "DEM", p.face));
        int held = 0;
        while (held < 8) {
            const int l = held + 1;
            const auto tx = static_cast<int>((p.u + 1.0) / 2.0 * (1 << l)), ty = static_cast<int>((p.v + 1.0) / 2.0 * (1 << l));
            if (!residualSetHolds(set, 3 + l, tx, ty)) {
                break;
            }
            held = l;
        }
        EXPECT_LT(held, 4) << lon << "," << lat;
        EXPECT_EQ(deepest(lon, lat).first, held) << lon << "," << lat;
    }
}

} // namespace
} // namespace pyramid
