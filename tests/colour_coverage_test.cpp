// Which pixels of imagery hold a value (input/colour_coverage.hpp), in every reader of several
// colour rasters as one: a pixel of alpha 0, or with every channel at the declared nodata, lets
// the next file show through, whichever channels are read; a pixel with only some channels at
// the nodata value is a colour, taken whole. Same-grid mosaics (RasterSource::openMosaic), planar
// mosaics of several grids (openPlanarMosaic, the finest group's own pixels and the others
// sampled), planets' maps (MapMosaic), and through the ortho encoder, one run over a coarse base
// and a fine inset whose east half is transparent.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/input/colour_coverage.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/map_mosaic.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using Pixel = std::vector<uint8_t>;

// A w x h image of `pixel(x, y)` (3 or 4 channels), 8 bits, pixel (0, 0)'s corner at (west,
// north) degrees, `step` degrees a pixel, with GDAL_NODATA `nodata` when not empty; a fourth
// channel is alpha, or with `alpha` false a band of unspecified data (near-infrared).
template <class Colour>
std::string image(const test::TempDir& dir, const std::string& name, int w, int h, double west, double north,
                  double step, size_t channels, const std::string& nodata, const Colour& pixel, bool alpha = true) {
    std::vector<uint8_t> v;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const Pixel p = pixel(x, y);
            v.insert(v.end(), p.begin(), p.begin() + static_cast<std::ptrdiff_t>(channels));
        }
    }
    test::GeoTiffTags tags = test::geographicTags(4326, west, north, step);
    tags.gdalNodata = nodata;
    const std::string path = dir.file(name);
    if (channels == 4) {
        test::writeGeoTiffRgba(path, w, h, v, tags, alpha);
    } else {
        test::writeGeoTiffRgb(path, w, h, v, tags);
    }
    return path;
}

// How a fine image marks its east half as without a value.
enum class Gap {
    Nodata, // 3 channels, nodata 0 in every one
    Alpha,  // 4 channels, alpha 0
    Mask,   // 3 channels of (9, 9, 9), an internal transparency mask
};
const Gap kGaps[] = {Gap::Nodata, Gap::Alpha, Gap::Mask};

size_t channelsOf(Gap gap) { return gap == Gap::Alpha ? 4 : 3; }

// A fine image (1/128 degree, 16 x 8) whose east half has no value, marked as `gap` says, over a
// coarse one (1/64 degree, 12 x 6) of one colour, both from 10 E, 50 N: {fine, coarse}.
std::pair<std::string, std::string> fineOverCoarse(const test::TempDir& dir, Gap gap) {
    const size_t channels = channelsOf(gap);
    const std::string nodata = gap == Gap::Nodata ? "0" : "";
    const std::string tag = std::to_string(static_cast<int>(gap));
    const Pixel none = gap == Gap::Mask ? Pixel{9, 9, 9, 255} : Pixel{0, 0, 0, 0};
    std::pair<std::string, std::string> files{
        image(dir, "fine" + tag + ".tif", 16, 8, 10.0, 50.0, 1.0 / 128.0, channels, nodata,
              [&](int x, int) -> Pixel { return x < 8 ? Pixel{50, 60, 70, 255} : none; }),
        image(dir, "coarse" + tag + ".tif", 12, 6, 10.0, 50.0, 1.0 / 64.0, channels, nodata,
              [](int, int) -> Pixel { return {100, 150, 200, 255}; })};
    if (gap == Gap::Mask) {
        std::vector<uint8_t> valid(16 * 8);
        for (size_t k = 0; k < valid.size(); ++k) {
            valid[k] = k % 16 < 8 ? 1 : 0;
        }
        test::appendTiffMask(files.first, 16, 8, valid, 3);
    }
    return files;
}

std::vector<uint16_t> at(const RasterSource& s, int x, int y, int c0, int c1) {
    std::vector<uint16_t> v(static_cast<size_t>(c1 - c0));
    s.readUInt16(x, y, x + 1, y + 1, c0, c1, v.data());
    return v;
}

TEST(ColourCoverage, AlphaZeroOrNodataInEveryChannelIsNoValue) {
    const ColourCoverage rgb(3, false, SampleType::UInt8, 0.0);
    EXPECT_FALSE(rgb.has(std::array<uint16_t, 3>{0, 0, 0}.data()));
    EXPECT_TRUE(rgb.has(std::array<uint16_t, 3>{0, 40, 0}.data()));
    const ColourCoverage rgba(4, true, SampleType::UInt8, std::nullopt);
    EXPECT_FALSE(rgba.has(std::array<float, 4>{9, 9, 9, 0}.data()));
    EXPECT_TRUE(rgba.has(std::array<float, 4>{0, 0, 0, 1}.data()));
    // A fourth band that is not alpha (near-infrared) is a colour at 0 too.
    EXPECT_TRUE(ColourCoverage(4, false, SampleType::UInt8, std::nullopt).has(std::array<float, 4>{9, 9, 9, 0}.data()));
    const ColourCoverage grey(1, false, SampleType::UInt16, 65535.0);
    EXPECT_FALSE(grey.has(std::array<uint16_t, 1>{65535}.data()));
    EXPECT_TRUE(grey.has(std::array<uint16_t, 1>{0}.data()));
    // A nodata no sample of the type holds marks nothing.
    for (const double nodata : {-9999.0, 256.0, 0.5}) {
        EXPECT_TRUE(ColourCoverage(1, false, SampleType::UInt8, nodata).has(std::array<uint16_t, 1>{0}.data())) << nodata;
    }
}

// Two files on one grid, a (listed first) over b's west half. a's east half: row 0 nodata (or
// alpha 0), row 1 (0, 40, 0), row 2 (9, 0, 0); b everywhere (200, 201, 202).
TEST(ColourCoverage, SameGridMosaicsTakeWholePixels) {
    test::TempDir dir;
    constexpr double kStep = 1.0 / 64.0;
    auto aPixel = [](int x, int y) -> Pixel {
        if (x < 4) {
            return {static_cast<uint8_t>(10 + x), static_cast<uint8_t>(20 + y), 30, 255};
        }
        return y == 0 ? Pixel{0, 0, 0, 0} : y == 1 ? Pixel{0, 40, 0, 255} : Pixel{9, 0, 0, 255};
    };
    auto bPixel = [](int, int) -> Pixel { return {200, 201, 202, 255}; };
    for (const size_t channels : {size_t{3}, size_t{4}}) {
        const std::string nodata = channels == 3 ? "0" : "";
        const std::string tag = std::to_string(channels);
        const std::string a = image(dir, "a" + tag + ".tif", 8, 3, 10.0, 50.0, kStep, channels, nodata, aPixel);
        const std::string b = image(dir, "b" + tag + ".tif", 8, 3, 10.0 + 4 * kStep, 50.0, kStep, channels, nodata, bPixel);
        const auto mosaic = RasterSource::openMosaic({a, b}, 16);
        ASSERT_EQ(mosaic->info().width, 12);
        for (int x = 4; x < 8; ++x) {
            EXPECT_EQ(at(*mosaic, x, 0, 0, 3), (std::vector<uint16_t>{200, 201, 202})) << tag << " " << x;
            EXPECT_EQ(at(*mosaic, x, 1, 0, 3), (std::vector<uint16_t>{0, 40, 0})) << tag << " " << x;
            EXPECT_EQ(at(*mosaic, x, 2, 0, 3), (std::vector<uint16_t>{9, 0, 0})) << tag << " " << x;
            // One channel read is judged by the whole pixel all the same.
            EXPECT_EQ(at(*mosaic, x, 0, 1, 2), std::vector<uint16_t>{201}) << tag << " " << x;
            EXPECT_EQ(at(*mosaic, x, 2, 1, 2), std::vector<uint16_t>{0}) << tag << " " << x;
        }
        EXPECT_EQ(at(*mosaic, 1, 1, 0, 3), (std::vector<uint16_t>{11, 21, 30})) << tag;
        EXPECT_EQ(at(*mosaic, 10, 1, 0, 3), (std::vector<uint16_t>{200, 201, 202})) << tag;
    }
    // Four bands of which the last is near-infrared, not alpha: a pixel whose fourth band is 0
    // is a colour, listed first, whole.
    const std::string a = image(dir, "an.tif", 8, 3, 10.0, 50.0, kStep, 4, "", aPixel, false);
    const std::string b = image(dir, "bn.tif", 8, 3, 10.0 + 4 * kStep, 50.0, kStep, 4, "", bPixel, false);
    const auto rgbn = RasterSource::openMosaic({a, b}, 16);
    EXPECT_FALSE(rgbn->info().alpha);
    EXPECT_EQ(at(*rgbn, 5, 0, 0, 4), (std::vector<uint16_t>{0, 0, 0, 0}));
    EXPECT_TRUE(RasterSource::open(image(dir, "alpha.tif", 1, 1, 10.0, 50.0, kStep, 4, "", bPixel))->info().alpha);
}

// A same-grid mosaic's gap holds the declared nodata (255 here), so that it is no value to the
// rule, as the files' own nodata pixels are; a nodata no sample holds leaves gaps at 0.
TEST(ColourCoverage, AMosaicsGapsHoldTheDeclaredNodata) {
    test::TempDir dir;
    constexpr double kStep = 1.0 / 64.0;
    auto grey = [](int, int) -> Pixel { return {70, 80, 90}; };
    for (const std::string nodata : {"255", "-9999"}) {
        const std::string a = image(dir, "ga" + nodata + ".tif", 4, 2, 10.0, 50.0, kStep, 3, nodata, grey);
        const std::string b = image(dir, "gb" + nodata + ".tif", 4, 2, 10.0 + 6 * kStep, 50.0, kStep, 3, nodata, grey);
        const auto mosaic = RasterSource::openMosaic({a, b}, 16);
        ASSERT_EQ(mosaic->info().width, 10);
        const uint16_t gap = nodata == "255" ? 255 : 0;
        EXPECT_EQ(at(*mosaic, 5, 1, 0, 3), (std::vector<uint16_t>{gap, gap, gap})) << nodata;
        EXPECT_EQ(ColourCoverage(mosaic->info()).has(at(*mosaic, 5, 1, 0, 3).data()), nodata != "255") << nodata;
        EXPECT_EQ(at(*mosaic, 7, 0, 0, 3), (std::vector<uint16_t>{70, 80, 90})) << nodata;
    }
}

// A TIFF's internal transparency mask (1 bit a pixel, in strips or tiles, over a width that is
// no multiple of 8) hides its pixels from a same-grid mosaic, whatever their colours; the file
// itself reads its colours as stored, and its mask as a channel after them. The mosaic has a mask
// of its own, which marks its gaps too (b stops at column 10).
TEST(ColourCoverage, SameGridMosaicsSeeThroughATiffsInternalMask) {
    test::TempDir dir;
    constexpr double kStep = 1.0 / 64.0;
    constexpr int kWidth = 13, kHeight = 5;
    // a's pixels without a value: the columns from 6 on, and pixel (2, 3).
    auto valid = [](int x, int y) { return x < 6 && !(x == 2 && y == 3); };
    std::vector<uint8_t> mask;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            mask.push_back(valid(x, y) ? 1 : 0);
        }
    }
    auto aPixel = [](int x, int y) -> Pixel { return {static_cast<uint8_t>(10 + x), static_cast<uint8_t>(20 + y), 30}; };
    for (const int tile : {0, 16}) {
        const std::string tag = std::to_string(tile);
        const std::string a = image(dir, "ma" + tag + ".tif", kWidth, kHeight, 10.0, 50.0, kStep, 3, "", aPixel);
        test::appendTiffMask(a, kWidth, kHeight, mask, 2, tile);
        const std::string b = image(dir, "mb" + tag + ".tif", 10, kHeight, 10.0, 50.0, kStep, 3, "",
                                    [](int, int) -> Pixel { return {200, 201, 202}; });
        const auto file = RasterSource::open(a, 16);
        ASSERT_TRUE(file->info().mask) << tag;
        EXPECT_EQ(file->info().channels, 3) << tag;
        const auto mosaic = RasterSource::openMosaic({a, b}, 16);
        EXPECT_TRUE(mosaic->info().mask) << tag;
        for (int y = 0; y < kHeight; ++y) {
            for (int x = 0; x < kWidth; ++x) {
                const Pixel p = aPixel(x, y);
                EXPECT_EQ(at(*file, x, y, 0, 4), (std::vector<uint16_t>{p[0], p[1], p[2], uint16_t(valid(x, y) ? 255 : 0)}))
                    << tag << " " << x << "," << y;
                const std::vector<uint16_t> want = valid(x, y) ? std::vector<uint16_t>{p[0], p[1], p[2], 255}
                                                   : x < 10    ? std::vector<uint16_t>{200, 201, 202, 255}
                                                               : std::vector<uint16_t>{0, 0, 0, 0};
                EXPECT_EQ(at(*mosaic, x, y, 0, 4), want) << tag << " " << x << "," << y;
                EXPECT_EQ(at(*mosaic, x, y, 1, 2), std::vector<uint16_t>{want[1]}) << tag << " " << x << "," << y;
            }
        }
        // A whole window, and the mask alone.
        std::vector<uint16_t> window(static_cast<size_t>(kWidth * kHeight));
        file->readUInt16(0, 0, kWidth, kHeight, 3, 4, window.data());
        for (size_t k = 0; k < window.size(); ++k) {
            EXPECT_EQ(window[k], mask[k] ? 255 : 0) << tag << " " << k;
        }
    }
}

// A fine image whose east half has no value (nodata, alpha 0 or a mask) over a coarse one of one
// colour: the coarse one shows through there, in the planar mosaic on the fine grid.
TEST(ColourCoverage, PlanarMosaicsShowTheCoarserGridThroughTheFinersGaps) {
    test::TempDir dir;
    for (const Gap gap : kGaps) {
        const size_t channels = channelsOf(gap);
        const std::string tag = std::to_string(static_cast<int>(gap));
        const auto [fine, coarse] = fineOverCoarse(dir, gap);
        const auto mosaic = openPlanarMosaic({fine, coarse}, 16);
        ASSERT_EQ(mosaic->info().width, 24) << tag;
        const int n = static_cast<int>(channels);
        std::vector<uint16_t> all(static_cast<size_t>(24 * 12 * n));
        mosaic->readUInt16(0, 0, 24, 12, 0, n, all.data());
        for (int y = 0; y < 8; ++y) {
            for (int x = 0; x < 24; ++x) {
                const uint16_t* p = &all[static_cast<size_t>((y * 24 + x) * n)];
                const std::vector<uint16_t> want = x < 8 ? std::vector<uint16_t>{50, 60, 70} : std::vector<uint16_t>{100, 150, 200};
                EXPECT_EQ(std::vector<uint16_t>(p, p + 3), want) << tag << " " << x << "," << y;
            }
        }
        // The same pixels read alone, and a single channel.
        EXPECT_EQ(at(*mosaic, 12, 3, 0, 3), (std::vector<uint16_t>{100, 150, 200})) << tag;
        std::vector<uint16_t> green(2);
        mosaic->readUInt16At({3, 12}, {3}, 1, 2, green.data());
        EXPECT_EQ(green, (std::vector<uint16_t>{60, 150})) << tag;
    }
}

// A planet's map: the fine member's samples whose interpolation reaches a pixel without a value
// come from the coarse member, never a blend with the gap.
TEST(ColourCoverage, MapMosaicsFallToTheNextMemberAtAGapsEdge) {
    test::TempDir dir;
    for (const Gap gap : kGaps) {
        const std::string tag = std::to_string(static_cast<int>(gap));
        const auto [fine, coarse] = fineOverCoarse(dir, gap);
        const MapMosaic map({{fine}, {coarse}}, PlanetBody::parse("wgs84"), 0, 3, SampleRead::UInt16,
                            [](const RasterInfo& info, const std::string&) { return info.nodata; }, 16);
        std::vector<GeodeticPoint> points;
        for (int k = 0; k < 46; ++k) {
            points.push_back({50.0 - 3.5 / 128.0, 10.0 + (k + 0.5) / 256.0}); // across the fine one's edge
        }
        std::vector<float> out(points.size() * 3);
        std::vector<uint8_t> valid(points.size());
        map.sample(points.data(), points.size(), out.data(), valid.data());
        int fromFine = 0, fromCoarse = 0;
        for (size_t k = 0; k < points.size(); ++k) {
            ASSERT_TRUE(valid[k]) << tag << " " << k;
            const std::vector<float> v(out.begin() + static_cast<std::ptrdiff_t>(k * 3),
                                       out.begin() + static_cast<std::ptrdiff_t>(k * 3 + 3));
            const std::vector<float> fineColour{50, 60, 70}, coarseColour{100, 150, 200};
            const bool fineOne = v == fineColour;
            EXPECT_TRUE(fineOne || v == coarseColour) << tag << " " << k << ": " << v[0];
            (fineOne ? fromFine : fromCoarse) += 1;
        }
        // The fine one's west half, to within a pixel of its edge; the coarse one beyond.
        EXPECT_GE(fromFine, 14) << tag;
        EXPECT_GE(fromCoarse, 30) << tag;
    }
}

// Through preprocessOrtho's encoder: a 4-channel base and a finer inset whose east half is
// transparent; the inset's level over its east half holds the base's colour.
TEST(ColourCoverage, AnOrthoPyramidShowsTheBaseThroughAnInsetsTransparentHalf) {
    test::TempDir dir;
    const std::string base = image(dir, "base.tif", 32, 32, 10.0, 50.0, 1.0 / 64.0, 4, "",
                                   [](int, int) -> Pixel { return {100, 150, 200, 255}; });
    const std::string inset = image(dir, "inset.tif", 64, 64, 10.0 + 8.0 / 64.0, 50.0 - 8.0 / 64.0, 1.0 / 256.0, 4,
                                    "", [](int x, int) -> Pixel {
                                        return x < 32 ? Pixel{50, 60, 70, 255} : Pixel{9, 9, 9, 0};
                                    });
    OrthoEncodeOptions o;
    o.levels.tileSize = 32;
    o.levels.threads = 2;
    o.writeDxt = false;
    o.writeResiduals = false;
    encodeOrtho(std::vector<std::string>{inset, base}, dir.file("out"), o);
    const auto set = openOrthoSet(dir.file("out/RGB.dat"));
    // The grid: 128 pixels of 1/256 degree over the base's half degree, four levels; the inset's
    // is level 2. (e, s): degrees east and south of the base's corner.
    ASSERT_EQ(set->maxLevel(), 2);
    auto pixel = [&](double e, double s) {
        const double x = e / 0.5 * 128.0, y = (1.0 - s / 0.5) * 128.0;
        const int tx = static_cast<int>(x) / 32, ty = static_cast<int>(y) / 32;
        const std::vector<uint8_t> tile = set->tile(2, tx, ty);
        const int px = static_cast<int>(x) - tx * 32 + 2, py = static_cast<int>(y) - ty * 32 + 2;
        const uint8_t* p = &tile[(static_cast<size_t>(py) * 36 + static_cast<size_t>(px)) * 4];
        return std::vector<int>(p, p + 4);
    };
    EXPECT_EQ(pixel(0.1875, 0.25), (std::vector<int>{50, 60, 70, 255}));   // the inset's opaque half
    EXPECT_EQ(pixel(0.3125, 0.25), (std::vector<int>{100, 150, 200, 255})); // its transparent half
    EXPECT_EQ(pixel(0.3125, 0.20), (std::vector<int>{100, 150, 200, 255}));
    EXPECT_EQ(pixel(0.05, 0.45), (std::vector<int>{100, 150, 200, 255})); // the base alone
}

} // namespace
} // namespace pyramid
