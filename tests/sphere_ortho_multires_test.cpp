// Imagery of several resolutions on a planet (ortho_levels.hpp, "Several resolutions";
// doc/spherical.md, "Maps of several resolutions"): a coarse global image and a fine inset, built
// in one run, go down to the inset's level where the inset is and no deeper than the base's
// elsewhere. The colours are the inset's in the inset and the base's elsewhere, the base is read
// at its own level (not resampled at the inset's), the build verifies, is deterministic and
// writes a small fraction of what one resolution would.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/face_locate.hpp"
#include "libpyramid/verify/ortho_verify.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

constexpr int kTile = 32;
// The base: 2-degree pixels over the globe (a face needs 45 pixels: level 1 of 32-pixel tiles).
// The inset: 2 x 2 degrees of 0.01-degree pixels at 46..48 N, 123..121 W (9000 pixels a face:
// level 9).
constexpr int kBaseLevel = 1, kInsetLevel = 9;

int clampByte(double v) { return static_cast<int>(std::lround(std::fmin(255.0, std::fmax(0.0, v)))); }
std::array<int, 3> baseColour(double lon, double lat) {
    return {clampByte(100.0 + 50.0 * std::sin(lon * M_PI / 90.0)), clampByte(120.0 + 40.0 * std::cos(lat * M_PI / 60.0)), 80};
}
std::array<int, 3> insetColour(double lon, double lat) {
    return {clampByte(200.0 + 40.0 * std::sin((lon + 122.0) * 6.0)), 40, clampByte(180.0 + 50.0 * std::cos((lat - 47.0) * 5.0))};
}

struct Maps {
    std::string base, inset;
};

Maps writeMaps(const test::TempDir& dir) {
    Maps m{dir.file("base.tif"), dir.file("inset.tif")};
    std::vector<uint8_t> base(180 * 90 * 3);
    for (int j = 0; j < 90; ++j) {
        for (int i = 0; i < 180; ++i) {
            const auto c = baseColour(-180.0 + 2.0 * (i + 0.5), 90.0 - 2.0 * (j + 0.5));
            for (int k = 0; k < 3; ++k) {
                base[static_cast<size_t>((i + 180 * j) * 3 + k)] = static_cast<uint8_t>(c[static_cast<size_t>(k)]);
            }
        }
    }
    test::writeGeoTiffRgb(m.base, 180, 90, base, test::geographicTags(4326, -180.0, 90.0, 2.0));
    std::vector<uint8_t> inset(200 * 200 * 3);
    for (int j = 0; j < 200; ++j) {
        for (int i = 0; i < 200; ++i) {
            const auto c = insetColour(-123.0 + (i + 0.5) / 100.0, 48.0 - (j + 0.5) / 100.0);
            for (int k = 0; k < 3; ++k) {
                inset[static_cast<size_t>((i + 200 * j) * 3 + k)] = static_cast<uint8_t>(c[static_cast<size_t>(k)]);
            }
        }
    }
    test::writeGeoTiffRgb(m.inset, 200, 200, inset, test::geographicTags(4326, -123.0, 48.0, 0.01));
    return m;
}

SphericalOrthoReport build(const Maps& maps, const std::string& out, int threads = 2,
                           PyramidLayout layout = PyramidLayout::Sparse) {
    SphericalOrthoOptions o;
    o.ortho.levels.tileSize = kTile;
    o.ortho.levels.threads = threads;
    o.ortho.layout = layout;
    return encodeSphericalOrtho(std::vector<std::string>{maps.base, maps.inset}, out, o);
}

// The deepest stored tile of `sub` (a subdirectory of outputs) holding (lon, lat), its level, and
// the colour of the pixel there.
struct Deepest {
    int level = -1;
    std::array<int, 3> colour{};
};
Deepest deepestAt(const std::string& directory, double lon, double lat) {
    const FacePoint p = facePointOf(directionOf(PlanetBody::parse("wgs84"), GeodeticPoint{lat, lon}));
    const auto set = openOrthoSet(faceFilePath(directory, "RGB", p.face));
    Deepest d;
    const double s = (p.u + 1.0) / 2.0, t = (p.v + 1.0) / 2.0;
    for (int l = 0; l <= set->maxLevel(); ++l) {
        const double x = s * (kTile << l), y = t * (kTile << l);
        const int tx = static_cast<int>(x) / kTile, ty = static_cast<int>(y) / kTile;
        if (!set->hasTile(l, tx, ty)) {
            break;
        }
        const std::vector<uint8_t> tile = set->tile(l, tx, ty);
        const int side = kTile + 4; // with its border
        const int px = static_cast<int>(x) - tx * kTile + 2, py = static_cast<int>(y) - ty * kTile + 2;
        d.level = l;
        for (int k = 0; k < 3; ++k) {
            d.colour[static_cast<size_t>(k)] = tile[static_cast<size_t>((py * side + px) * 3 + k)];
        }
    }
    return d;
}

class SphereOrthoMultiResolution : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir();
        maps_ = new Maps(writeMaps(*dir_));
        report_ = new SphericalOrthoReport(build(*maps_, dir_->file("both")));
    }
    static void TearDownTestSuite() {
        delete report_;
        delete maps_;
        delete dir_;
    }
    static test::TempDir* dir_;
    static Maps* maps_;
    static SphericalOrthoReport* report_;
};
test::TempDir* SphereOrthoMultiResolution::dir_ = nullptr;
Maps* SphereOrthoMultiResolution::maps_ = nullptr;
SphericalOrthoReport* SphereOrthoMultiResolution::report_ = nullptr;

TEST_F(SphereOrthoMultiResolution, DeepWhereTheInsetIsAndAtTheBasesLevelElsewhere) {
    const std::string out = dir_->file("both");
    // In the inset: its level, its colours.
    for (const auto& [lon, lat] : {std::pair{-122.0, 47.0}, std::pair{-122.6, 46.3}, std::pair{-121.3, 47.8}}) {
        SCOPED_TRACE(std::to_string(lon) + "," + std::to_string(lat));
        const Deepest d = deepestAt(out, lon, lat);
        EXPECT_EQ(d.level, kInsetLevel);
        const auto want = insetColour(lon, lat);
        for (size_t k = 0; k < 3; ++k) {
            EXPECT_NEAR(d.colour[k], want[k], 3) << "channel " << k;
        }
    }
    // Elsewhere, on every face: the base's level and colours (smooth, so bilinear is close).
    for (const auto& [lon, lat] : {std::pair{10.0, 20.0}, std::pair{100.0, -30.0}, std::pair{-150.0, 60.0},
                                   std::pair{-60.0, -5.0}, std::pair{30.0, 80.0}, std::pair{-20.0, -75.0},
                                   std::pair{-80.0, 40.0}}) {
        SCOPED_TRACE(std::to_string(lon) + "," + std::to_string(lat));
        const Deepest d = deepestAt(out, lon, lat);
        EXPECT_EQ(d.level, kBaseLevel);
        const auto want = baseColour(lon, lat);
        for (size_t k = 0; k < 3; ++k) {
            EXPECT_NEAR(d.colour[k], want[k], 6) << "channel " << k;
        }
    }
}

TEST_F(SphereOrthoMultiResolution, VerifiesAndTheColourProducerMagnifiesTheBase) {
    SphericalOrthoVerifyOptions v;
    v.threads = 2;
    for (const OrthoVerifyReport& r : verifySphericalOrtho(dir_->file("both"), {maps_->base, maps_->inset}, v)) {
        EXPECT_TRUE(r.ok) << r.file;
        for (const OrthoVerifyLevel& l : r.levels) {
            EXPECT_EQ(l.maxError, 0) << r.file << " level " << l.level;
        }
    }
    v.colourResiduals = true;
    for (const OrthoVerifyReport& r :
         verifySphericalOrtho(dir_->file("both/residuals"), {maps_->base, maps_->inset}, v)) {
        EXPECT_TRUE(r.ok) << r.file;
    }
    // Below the base's level, away from the inset, the colour residuals are a magnification of
    // the base's level: residual 128 where no file holds a tile.
    const FacePoint p = facePointOf(directionOf(PlanetBody::parse("wgs84"), GeodeticPoint{20.0, 10.0}));
    ColourProducer colours(openOrthoSet(faceFilePath(dir_->file("both/residuals"), "RGB", p.face)), 64);
    const int l = kBaseLevel + 2;
    const int tx = static_cast<int>((p.u + 1.0) / 2.0 * (1 << l)), ty = static_cast<int>((p.v + 1.0) / 2.0 * (1 << l));
    const std::vector<uint8_t> tile = *colours.tile(l, tx, ty);
    const auto want = baseColour(10.0, 20.0);
    const int side = kTile + 4, mid = side / 2;
    for (size_t k = 0; k < 3; ++k) {
        EXPECT_NEAR(tile[static_cast<size_t>((mid * side + mid) * 3) + k], want[k], 6) << "channel " << k;
    }
}

TEST_F(SphereOrthoMultiResolution, SmallAndTheSameBytesWhateverTheThreads) {
    // One resolution at level 9 would be 6 faces of 512 x 512 tiles; this is the base's levels and
    // the inset's tiles.
    EXPECT_LT(test::bytesUnder(dir_->file("both")), uint64_t{3} << 20);
    build(*maps_, dir_->file("one-thread"), 1);
    EXPECT_TRUE(test::filesUnder(dir_->file("both")) == test::filesUnder(dir_->file("one-thread")));
}

TEST_F(SphereOrthoMultiResolution, DenseLayoutIsRefusedWithTheReason) {
    try {
        build(*maps_, dir_->file("dense"), 2, PyramidLayout::Dense);
        FAIL() << "a dense layout of several resolutions was accepted";
    } catch (const OptionError& e) {
        EXPECT_NE(std::string(e.what()).find("several resolutions"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir_->file("dense/RGB1.dat")));
}

} // namespace
} // namespace pyramid
