// Planar mosaics of several resolutions (doc/input.md, "Mosaics"; doc/dem-encoding.md, "Sparse
// outputs"): a coarse base with a fine inset, one run of preprocessDem. The pyramid goes down to
// the inset's level over the inset and no deeper than the base's level elsewhere, without
// encoding the base at the inset's resolution: its heights are the inset's in the inset, the
// base's elsewhere, `pyramid verify` passes, and the files are a small fraction of those of the
// same mosaic encoded as one resolution.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "formats/residual_file.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/runtime/height_query.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

// UTM 10N metres from the mosaic's north-west corner.
constexpr double kWest = 500000.0, kNorth = 5200000.0;
// The base: 64 x 64 pixels of 30 m. The inset: 240 x 240 pixels of 1 m, 840 m in from the corner.
constexpr int kBase = 64, kInset = 240;
constexpr double kBaseStep = 30.0, kInsetAt = 840.0;

double baseHeight(double e, double s) { return 500.0 + 80.0 * std::sin(e / 400.0) * std::cos(s / 500.0); }
double insetHeight(double e, double s) { return 900.0 + 40.0 * std::sin(e / 13.0) * std::cos(s / 17.0); }

struct Maps {
    std::string directory, base, inset;
};

Maps writeMaps(const test::TempDir& dir) {
    Maps m{dir.file("maps"), dir.file("maps/base.tif"), dir.file("maps/inset.tif")};
    std::filesystem::create_directories(m.directory);
    std::vector<float> base(static_cast<size_t>(kBase * kBase));
    for (int j = 0; j < kBase; ++j) {
        for (int i = 0; i < kBase; ++i) {
            // A smooth field and a checkerboard of +-0.6 m: at the inset's 1 m, the base's pixels
            // interpolated bilinearly have kinks that residuals at every level must carry.
            base[static_cast<size_t>(i + kBase * j)] = static_cast<float>(
                baseHeight((i + 0.5) * kBaseStep, (j + 0.5) * kBaseStep) + ((i + j) % 2 != 0 ? 0.6 : -0.6));
        }
    }
    test::writeGeoTiff(m.base, kBase, kBase, base, test::projectedTags(32610, kWest, kNorth, kBaseStep));
    std::vector<float> inset(static_cast<size_t>(kInset * kInset));
    for (int j = 0; j < kInset; ++j) {
        for (int i = 0; i < kInset; ++i) {
            inset[static_cast<size_t>(i + kInset * j)] = static_cast<float>(insetHeight(i + 0.5, j + 0.5));
        }
    }
    test::writeGeoTiff(m.inset, kInset, kInset, inset,
                       test::projectedTags(32610, kWest + kInsetAt, kNorth - kInsetAt, 1.0));
    return m;
}

DemEncodeOptions options() {
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 4;
    o.scale = 0.25;
    return o;
}

uint64_t bytesOf(const std::string& directory) {
    uint64_t bytes = 0;
    for (const auto& e : std::filesystem::directory_iterator(directory)) {
        if (e.path().extension() == ".dat") {
            bytes += e.file_size();
        }
    }
    return bytes;
}

// A raster's samples with its parts forgotten: the mosaic as one resolution, what encoding it
// gave before the parts were known.
class Forwarded final : public RasterPixels {
public:
    explicit Forwarded(const RasterSource& s) : s_(s) {}
    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const override {
        s_.readFloat(x0, y0, x1, y1, channel, out);
    }
    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const override {
        s_.readUInt16(x0, y0, x1, y1, c0, c1, out);
    }

private:
    const RasterSource& s_;
};

TEST(PlanarMultires, TheInsetsLevelWhereItIsTheBasesElsewhere) {
    test::TempDir dir;
    const Maps maps = writeMaps(dir);
    const auto mosaic = openPlanarMosaic({maps.base, maps.inset}, 16);
    const RasterInfo& info = mosaic->info();
    ASSERT_EQ(info.width, 1920); // the inset's 1 m grid over the base's 1920 m
    ASSERT_EQ(info.parts.size(), 2u); // in list order
    EXPECT_NEAR(info.parts[0].pixelsPerSample, 30.0, 0.01);
    EXPECT_NEAR(info.parts[1].pixelsPerSample, 1.0, 0.01);

    const std::string out = dir.file("sparse");
    std::filesystem::create_directories(out);
    const DemReport r = encodeDem({maps.base, maps.inset}, out + "/DEM.dat", options());
    DemVerifyOptions vo;
    const DemVerifyReport verified = verifyDem(out + "/DEM.dat", maps.directory, vo);
    EXPECT_TRUE(verified.ok());

    // Residuals at the deepest level: over the inset, and nowhere far from it (the base's
    // heights there are its own level's, upsampled).
    const auto residuals = openResidualSet(out + "/DEM.dat");
    const int L = residuals->maxLevel();
    const auto side = static_cast<int>(ResidualFileReader::readHeader(out + "/DEM.dat").tilesPerSide(L));
    const auto zero = [&](int tx, int ty) {
        if (!residuals->hasTile(L, tx, ty)) {
            return true;
        }
        const std::vector<float> t = residuals->tile(L, tx, ty);
        return std::all_of(t.begin(), t.end(), [](float v) { return v == 0.0f; });
    };
    EXPECT_FALSE(zero(side / 2, side / 2));
    int far = 0;
    for (int ty = 0; ty < side; ++ty) {
        for (int tx = 0; tx < side; ++tx) {
            // Tiles more than a quarter of the quad from its centre: the base alone.
            if (std::abs(tx - side / 2) > side / 4 || std::abs(ty - side / 2) > side / 4) {
                ++far;
                ASSERT_TRUE(zero(tx, ty)) << "tile (" << L << "," << tx << "," << ty << ")";
            }
        }
    }
    EXPECT_GT(far, side * side / 2);

    // Heights: the inset's in it, the base's elsewhere (its own samples, interpolated).
    const auto elevations = openElevationSet(out + "/DEM.dat");
    const double quad = 1919.0; // metres of the root quad (1919 finest intervals of 1 m)
    for (const auto& [e, s] : {std::pair{960.3, 950.7}, std::pair{1000.5, 1010.5}, std::pair{870.2, 1060.9}}) {
        const PointHeight h = heightAt(*elevations, (e - 0.5) / quad, 1.0 - (s - 0.5) / quad);
        EXPECT_NEAR(h.height, insetHeight(e - kInsetAt, s - kInsetAt), 0.5) << e << "," << s;
    }
    for (const auto& [e, s] : {std::pair{200.0, 300.0}, std::pair{1700.0, 400.0}, std::pair{500.0, 1800.0}}) {
        const PointHeight h = heightAt(*elevations, (e - 0.5) / quad, 1.0 - (s - 0.5) / quad);
        EXPECT_NEAR(h.height, baseHeight(e, s), 1.2) << e << "," << s; // the checkerboard's 0.6 and more
    }

    // The same mosaic encoded as one resolution (the base resampled at 1 m everywhere).
    const std::string whole = dir.file("one-resolution");
    std::filesystem::create_directories(whole);
    RasterInfo flat = info;
    flat.parts.clear();
    const auto oneResolution = RasterSource::fromPixels(mosaic->path(), flat, std::make_shared<Forwarded>(*mosaic));
    encodeDem(*oneResolution, whole + "/DEM.dat", options());
    EXPECT_LT(bytesOf(out) * 5, bytesOf(whole)) << bytesOf(out) << " against " << bytesOf(whole);
    EXPECT_EQ(r.header.maxLevel, ResidualFileReader::readHeader(whole + "/DEM.dat").maxLevel);
}

} // namespace
} // namespace pyramid
