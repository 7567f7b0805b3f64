// preprocessDem's input side: every sample type is read by value (never normalised), a
// vertex-registered input is the finest grid sample for sample, NaN heights are an error unless
// declared as nodata, and holes are filled from their surroundings.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <tiffio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/dem/dem_sampling.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

// Writes `values` (one channel, row 0 = north) as `type` without any conversion by OIIO.
template <typename T>
void writeRaster(const std::string& path, int width, int height, const std::vector<T>& values) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out) << path;
    const OIIO::ImageSpec spec(width, height, 1, OIIO::BaseTypeFromC<T>::value);
    ASSERT_TRUE(out->open(path, spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::BaseTypeFromC<T>::value, values.data())) << out->geterror();
    ASSERT_TRUE(out->close());
}

// Values of T spread over most of its range, including negative ones for signed types.
template <typename T>
std::vector<T> spreadValues(int count, double low, double high) {
    std::vector<T> v(static_cast<size_t>(count));
    for (int k = 0; k < count; ++k) {
        const double t = static_cast<double>((k * 7919) % count) / static_cast<double>(count - 1);
        v[static_cast<size_t>(k)] = static_cast<T>(std::floor(low + (high - low) * t));
    }
    return v;
}

template <typename T>
void expectReadByValue(const std::string& path, double low, double high, SampleType type) {
    const int w = 23, h = 17;
    const std::vector<T> values = spreadValues<T>(w * h, low, high);
    writeRaster(path, w, h, values);
    const auto source = RasterSource::open(path);
    EXPECT_EQ(source->info().type, type) << path;
    std::vector<float> read(static_cast<size_t>(w * h));
    source->readFloat(0, 0, w, h, 0, read.data());
    for (size_t k = 0; k < read.size(); ++k) {
        ASSERT_EQ(read[k], static_cast<float>(values[k])) << path << " sample " << k;
    }
    // A window: columns 5..11, rows 3..9.
    std::vector<float> window(7 * 7);
    source->readFloat(5, 3, 12, 10, 0, window.data());
    EXPECT_EQ(window[0], static_cast<float>(values[5 + 3 * w]));
    EXPECT_EQ(window[48], static_cast<float>(values[11 + 9 * w]));
}

TEST(DemInput, EverySampleTypeIsReadByValue) {
    test::TempDir dir;
    expectReadByValue<uint8_t>(dir.file("u8.png"), 0, 255, SampleType::UInt8);
    expectReadByValue<uint16_t>(dir.file("u16.png"), 0, 65535, SampleType::UInt16);
    expectReadByValue<int16_t>(dir.file("i16.tif"), -32768, 32767, SampleType::Int16);
    expectReadByValue<uint16_t>(dir.file("u16.tif"), 0, 65535, SampleType::UInt16);
    expectReadByValue<int32_t>(dir.file("i32.tif"), -1e6, 1e6, SampleType::Int32);
    expectReadByValue<double>(dir.file("f64.tif"), -500.25, 8848.5, SampleType::Float64);
}

TEST(DemInput, VertexRegisteredInputIsTheFinestGridSampleForSample) {
    test::TempDir dir;
    const int side = 33; // N = 32
    const std::vector<float> heights = test::syntheticHeights(side, side);
    test::writeFloatRaster(dir.file("dem.tif"), side, side, heights);
    const auto source = RasterSource::open(dir.file("dem.tif"));
    const DemGeometry g = makeDemGeometry(side, side, 32, false, "dem.tif");
    ASSERT_TRUE(g.exact());
    const DemSampler sampler(*source, g, 0, std::nullopt);
    SourceGrid grid;
    grid.nx = grid.ny = side;
    sampler.sample(grid);
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            const size_t k = grid.index(x, y);
            ASSERT_EQ(grid.valid[k], 1);
            // Bit for bit: no interpolation arithmetic touches an exact-size input.
            ASSERT_EQ(grid.height[k], heights[static_cast<size_t>(x + (32 - y) * side)]) << x << "," << y;
        }
    }
    // A decimated grid (every 4th sample from (4, 8)) reads the same values.
    SourceGrid coarse;
    coarse.x0 = 4;
    coarse.y0 = 8;
    coarse.stride = 4;
    coarse.nx = 7;
    coarse.ny = 5;
    sampler.sample(coarse);
    for (int j = 0; j < 5; ++j) {
        for (int i = 0; i < 7; ++i) {
            const int x = 4 + 4 * i, y = 8 + 4 * j;
            ASSERT_EQ(coarse.height[static_cast<size_t>(i + j * 7)], heights[static_cast<size_t>(x + (32 - y) * side)]);
        }
    }
}

// The documented bilinear formula (dem_sampling.hpp), evaluated sample by sample: the heights
// the sampler must give, bit for bit, whichever way it computes them. `nodata` marks an input
// sample as missing; a grid sample needing it with a non-zero weight is nodata (returns false).
bool referenceHeight(const std::vector<float>& in, int width, int height, int64_t N, int64_t lx, int64_t ly,
                     int64_t x, int64_t y, float nodata, float& h) {
    const int64_t nx = x * lx, ny = (N - y) * ly;
    const int64_t c = nx / N, r = ny / N;
    const double fx = static_cast<double>(nx % N) / static_cast<double>(N);
    const double fy = static_cast<double>(ny % N) / static_cast<double>(N);
    if (c > width - 1 || (c == width - 1 && fx > 0.0) || r > height - 1 || (r == height - 1 && fy > 0.0)) {
        return false; // beyond the input
    }
    const auto at = [&](int64_t i, int64_t j, double weight, double& v) {
        if (weight == 0.0) {
            return true; // not read
        }
        v = in[static_cast<size_t>(i + j * width)];
        return v != nodata;
    };
    double v00 = 0, v10 = 0, v01 = 0, v11 = 0;
    if (!at(c, r, 1.0, v00) || !at(c + 1, r, fx, v10) || !at(c, r + 1, fy, v01) || !at(c + 1, r + 1, fx * fy, v11)) {
        return false;
    }
    // A tap of weight 0 contributes nothing: v + (w - v) * 0 = v.
    v10 = fx > 0.0 ? v10 : v00;
    v01 = fy > 0.0 ? v01 : v00;
    v11 = fx > 0.0 ? (fy > 0.0 ? v11 : v10) : v01;
    const double top = v00 + (v10 - v00) * fx;
    const double bottom = v01 + (v11 - v01) * fx;
    h = static_cast<float>(top + (bottom - top) * fy);
    return true;
}

TEST(DemInput, ResampledHeightsAreTheBilinearFormulaBitForBit) {
    test::TempDir dir;
    const int width = 23, height = 17; // N = 32: resampled, never exact
    std::vector<float> heights = test::syntheticHeights(width, height);
    const float nodata = -9999.0f;
    for (const bool withNodata : {false, true}) {
        if (withNodata) {
            // One hole: the grid rows that read its input row are interpolated tap by tap, the
            // window's other rows (input rows of heights only) separably.
            heights[static_cast<size_t>(9 + 9 * width)] = nodata;
        }
        test::writeFloatRaster(dir.file("dem.tif"), width, height, heights);
        const auto source = RasterSource::open(dir.file("dem.tif"));
        for (const bool stretch : {false, true}) {
            const DemGeometry g = makeDemGeometry(width, height, 32, stretch, "dem.tif");
            ASSERT_FALSE(g.exact());
            const DemSampler sampler(*source, g, 0, withNodata ? std::optional<double>(nodata) : std::nullopt);
            // The whole grid, a window of it (what a subtree footprint reads), and every other
            // sample of both (a coarser level's: the input samples picked at their crossings).
            for (const auto& [x0, y0, n, m, stride] :
                 {std::array<int64_t, 5>{0, 0, 33, 33, 1}, std::array<int64_t, 5>{5, 7, 13, 11, 1},
                  std::array<int64_t, 5>{0, 0, 17, 17, 2}, std::array<int64_t, 5>{5, 7, 7, 6, 2}}) {
                SourceGrid grid;
                grid.x0 = x0;
                grid.y0 = y0;
                grid.nx = n;
                grid.ny = m;
                grid.stride = stride;
                sampler.sample(grid);
                int64_t holes = 0;
                for (int64_t y = y0; y < y0 + m * stride; y += stride) {
                    for (int64_t x = x0; x < x0 + n * stride; x += stride) {
                        float expected = 0.0f;
                        const bool valid = referenceHeight(heights, width, height, 32, g.lx, g.ly, x, y, nodata, expected);
                        const size_t k = grid.index(x, y);
                        ASSERT_EQ(grid.valid[k], valid ? 1 : 0) << x << "," << y << " stretch " << stretch;
                        if (valid) {
                            ASSERT_EQ(grid.height[k], expected) << x << "," << y << " stretch " << stretch;
                        }
                        holes += valid ? 0 : 1;
                    }
                }
                // Without stretching the 23 x 17 input leaves the south of the quad empty.
                EXPECT_EQ(holes > 0, withNodata || !stretch) << x0 << "," << y0;
            }
        }
    }
}

TEST(DemInput, SixteenBitIntegerHeightsEncodeWithinHalfAStep) {
    test::TempDir dir;
    const int side = 65;
    const std::vector<float> smooth = test::syntheticHeights(side, side, 3000.0f);
    std::vector<int16_t> heights(smooth.size());
    for (size_t k = 0; k < smooth.size(); ++k) {
        heights[k] = static_cast<int16_t>(std::lround(smooth[k]) - 1500); // negative heights too
    }
    writeRaster(dir.file("i16.tif"), side, side, heights);
    DemEncodeOptions o;
    o.tileSize = 16;
    o.rootTileSize = 4;
    o.scale = 0.5;
    const DemReport report = encodeDem(dir.file("i16.tif"), dir.file("DEM.dat"), o);
    EXPECT_EQ(report.header.maxLevel, 4); // 4 << 4 = 64 intervals: exact
    const nlohmann::json json = toJson(report);
    EXPECT_EQ(json["input"]["type"], "int16");
    EXPECT_EQ(json["input"]["nodata"], nullptr);
    EXPECT_GT(report.levels.back().maxAbsResidual, 0);
    for (const ResidualLevelReport& l : report.levels) {
        EXPECT_LE(l.maxError, 0.25 + 1e-3) << "level " << l.level;
    }
    const DemVerifyReport verify = verifyDem(dir.file("DEM.dat"), dir.file("i16.tif"), {});
    EXPECT_TRUE(verify.ok());
    EXPECT_EQ(verify.levels.back().samples, side * side);
}

TEST(DemInput, NanIsAnErrorUnlessItIsTheNodataValue) {
    test::TempDir dir;
    const int side = 65;
    std::vector<float> heights = test::syntheticHeights(side, side);
    heights[static_cast<size_t>(9 + 30 * side)] = std::numeric_limits<float>::quiet_NaN();
    heights[static_cast<size_t>(10 + 30 * side)] = std::numeric_limits<float>::quiet_NaN();
    test::writeFloatRaster(dir.file("nan.tif"), side, side, heights);
    DemEncodeOptions o;
    o.tileSize = 16;
    o.rootTileSize = 4;
    try {
        encodeDem(dir.file("nan.tif"), dir.file("DEM.dat"), o);
        FAIL() << "NaN accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("nan.tif"), std::string::npos) << what;
        EXPECT_NE(what.find("NaN height at column"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    EXPECT_FALSE(test::fileExists(dir.file("DEM.dat")));
    o.nodata = std::numeric_limits<double>::quiet_NaN();
    const DemReport report = encodeDem(dir.file("nan.tif"), dir.file("DEM.dat"), o);
    EXPECT_EQ(report.nodataFilled, 2);
    EXPECT_EQ(toJson(report)["input"]["nodata"], "nan");
    EXPECT_EQ(report.levels.back().samples, side * side - 2);
}

// An int16 GeoTIFF as GDAL writes it with a declared nodata value (tag 42113, text).
void writeGeoTiffWithNodata(const std::string& path, int side, const std::vector<int16_t>& values, const char* nodata) {
    TIFF* tif = TIFFOpen(path.c_str(), "w");
    ASSERT_NE(tif, nullptr);
    if (!TIFFFindField(tif, TIFFTAG_GDAL_NODATA, TIFF_ANY)) {
        static const TIFFFieldInfo gdalNodata = {TIFFTAG_GDAL_NODATA, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0,
                                                 const_cast<char*>("GDALNoDataValue")};
        ASSERT_EQ(TIFFMergeFieldInfo(tif, &gdalNodata, 1), 0);
    }
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, side);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, side);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 16);
    TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_INT);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, side);
    TIFFSetField(tif, TIFFTAG_GDAL_NODATA, nodata);
    for (int y = 0; y < side; ++y) {
        ASSERT_EQ(TIFFWriteScanline(tif, const_cast<int16_t*>(values.data() + y * side), static_cast<uint32_t>(y), 0), 1);
    }
    TIFFClose(tif);
}

TEST(DemInput, GeoTiffNodataIsUsedUnlessIgnored) {
    test::TempDir dir;
    const int side = 33;
    std::vector<int16_t> heights(static_cast<size_t>(side * side));
    int holes = 0;
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            const bool hole = x >= 10 && x < 14 && y >= 20 && y < 23;
            heights[static_cast<size_t>(x + y * side)] = static_cast<int16_t>(hole ? -9999 : 300 + 2 * x - y);
            holes += hole;
        }
    }
    writeGeoTiffWithNodata(dir.file("nd.tif"), side, heights, "-9999");
    const auto source = RasterSource::open(dir.file("nd.tif"));
    ASSERT_TRUE(source->info().nodata.has_value());
    EXPECT_EQ(*source->info().nodata, -9999.0);
    DemEncodeOptions o;
    o.tileSize = 8;
    o.rootTileSize = 4;
    float low = std::numeric_limits<float>::max();
    o.reconstruction = [&](int, int, int, const std::vector<float>& z) {
        low = std::min(low, *std::min_element(z.begin(), z.end()));
    };
    const DemReport report = encodeDem(dir.file("nd.tif"), dir.file("DEM.dat"), o);
    EXPECT_EQ(report.nodataFilled, holes);
    EXPECT_EQ(report.levels.back().samples, side * side - holes);
    EXPECT_EQ(toJson(report)["input"]["nodata"], -9999.0);
    // A plane, lowest valid height 300 - 32, rebuilt within scale/2: the hole takes the
    // runtime's interpolation of the plane, nothing lower.
    EXPECT_GE(low, 267.5f);
    o.reconstruction = nullptr;
    o.ignoreDeclaredNodata = true;
    const DemReport raw = encodeDem(dir.file("nd.tif"), dir.file("RAW.dat"), o);
    EXPECT_EQ(raw.nodataFilled, 0);
    EXPECT_EQ(raw.levels.back().samples, side * side);
}

TEST(DemInput, HolesAreFilledWithinTheSurroundingHeights) {
    test::TempDir dir;
    const int side = 129;
    // A smooth bowl with a hole in its middle and another on the map's edge.
    std::vector<float> heights(static_cast<size_t>(side * side));
    int holes = 0;
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            const double dx = x - 64.0, dy = y - 64.0;
            float v = static_cast<float>(100.0 + 0.02 * (dx * dx + dy * dy) + 3.0 * std::sin(0.2 * x));
            if (dx * dx + dy * dy < 20.0 * 20.0 || (x > 100 && y < 30)) {
                v = -9999.0f;
                ++holes;
            }
            heights[static_cast<size_t>(x + y * side)] = v;
        }
    }
    test::writeFloatRaster(dir.file("holes.tif"), side, side, heights);
    DemEncodeOptions o;
    o.tileSize = 16;
    o.rootTileSize = 4;
    o.scale = 0.1;
    o.nodata = -9999.0;
    float low = std::numeric_limits<float>::max();
    o.reconstruction = [&](int, int, int, const std::vector<float>& z) {
        for (float v : z) {
            low = std::min(low, v);
        }
    };
    const DemReport report = encodeDem(dir.file("holes.tif"), dir.file("DEM.dat"), o);
    EXPECT_EQ(report.nodataFilled, holes);
    EXPECT_EQ(report.levels.back().samples, side * side - holes);
    // No -9999 cliff anywhere: the filled bowl stays above the lowest valid height (100 + the
    // ripple's -3, at the hole's rim 108 - 3).
    EXPECT_GT(low, 96.0f);
}

TEST(DemInput, OneValidHeightBetweenTheInMemoryGridsSamplesIsFound) {
    test::TempDir dir;
    // Nodata but for one height, at column 65, row 63: finest sample (65, 65) of the 128-interval
    // pyramid, which the in-memory grid of levels 0..C (every 4th sample here) does not hold.
    // The root starts from that height, so every level is rebuilt at it.
    const int side = 129;
    std::vector<float> heights(static_cast<size_t>(side * side), -9999.0f);
    heights[static_cast<size_t>(65 + 63 * side)] = 1234.5f;
    test::writeFloatRaster(dir.file("one.tif"), side, side, heights);
    DemEncodeOptions o;
    o.tileSize = 16;
    o.rootTileSize = 4;
    o.scale = 0.1;
    o.nodata = -9999.0;
    float low = std::numeric_limits<float>::max(), high = std::numeric_limits<float>::lowest();
    o.reconstruction = [&](int, int, int, const std::vector<float>& z) {
        low = std::min(low, *std::min_element(z.begin(), z.end()));
        high = std::max(high, *std::max_element(z.begin(), z.end()));
    };
    const DemReport report = encodeDem(dir.file("one.tif"), dir.file("DEM.dat"), o);
    EXPECT_EQ(report.header.maxLevel, 5);
    EXPECT_EQ(report.levels.back().samples, 1);
    EXPECT_EQ(report.nodataFilled, side * side - 1);
    EXPECT_LE(report.levels.back().maxError, 0.05 + 1e-3);
    EXPECT_NEAR(low, 1234.5f, 0.05f);
    EXPECT_NEAR(high, 1234.5f, 0.05f);
    // Without it, nothing is valid: the input fails, by name.
    heights[static_cast<size_t>(65 + 63 * side)] = -9999.0f;
    test::writeFloatRaster(dir.file("none.tif"), side, side, heights);
    o.reconstruction = nullptr;
    try {
        encodeDem(dir.file("none.tif"), dir.file("NONE.dat"), o);
        FAIL() << "an input without a valid height was accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("none.tif: no valid height anywhere"), std::string::npos) << what;
    }
    EXPECT_FALSE(test::fileExists(dir.file("NONE.dat")));
}

} // namespace
} // namespace pyramid
