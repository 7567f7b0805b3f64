// Reading samples where columns and rows cross (RasterSource::readFloatAt, readUInt16At): the
// samples of the windows across them, picked, for a file and for a planar mosaic of two
// resolutions resampled onto one grid, which computes only the samples asked for.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

void writeRgb(const std::string& path, int n, double west, double north, double step, int seed) {
    std::vector<uint8_t> rgb(static_cast<size_t>(n) * n * 3);
    for (size_t k = 0; k < rgb.size(); ++k) {
        rgb[k] = static_cast<uint8_t>((k * 37 + static_cast<size_t>(seed) * 11 + k / 7) % 251);
    }
    test::writeGeoTiffRgb(path, n, n, rgb, test::projectedTags(32610, west, north, step));
}

// Every crossing of `columns` and `rows` against windows read whole.
void expectCrossings(const RasterSource& s, const std::vector<int>& columns, const std::vector<int>& rows) {
    const int w = columns.back() - columns.front() + 1, h = rows.back() - rows.front() + 1;
    const int c = s.info().channels;
    std::vector<uint16_t> window(static_cast<size_t>(w) * h * c);
    s.readUInt16(columns.front(), rows.front(), columns.back() + 1, rows.back() + 1, 0, c, window.data());
    std::vector<uint16_t> at(columns.size() * rows.size() * c);
    s.readUInt16At(columns, rows, 0, c, at.data());
    std::vector<float> windowF(static_cast<size_t>(w) * h), atF(columns.size() * rows.size());
    s.readFloat(columns.front(), rows.front(), columns.back() + 1, rows.back() + 1, 1, windowF.data());
    s.readFloatAt(columns, rows, 1, atF.data());
    int64_t differ = 0;
    for (size_t j = 0; j < rows.size(); ++j) {
        for (size_t i = 0; i < columns.size(); ++i) {
            const size_t x = static_cast<size_t>(columns[i] - columns.front()), y = static_cast<size_t>(rows[j] - rows.front());
            for (int k = 0; k < c; ++k) {
                differ += at[(j * columns.size() + i) * c + k] != window[(y * w + x) * c + k];
            }
            differ += atF[j * columns.size() + i] != windowF[y * w + x];
        }
    }
    EXPECT_EQ(differ, 0);
}

TEST(RasterReadAt, CrossingsAreTheWindowsSamples) {
    test::TempDir dir;
    writeRgb(dir.file("base.tif"), 60, 500000.0, 5200000.0, 20.0, 1);
    writeRgb(dir.file("inset.tif"), 100, 500300.0, 5199700.0, 1.0, 2);
    const std::vector<int> columns{0, 1, 7, 8, 30, 290, 291, 350, 399, 1199};
    const std::vector<int> rows{0, 5, 6, 299, 300, 301, 333, 398, 1100};
    // A file (its own samples) and the mosaic of both (the base resampled onto the inset's 1 m grid).
    const auto file = RasterSource::open(dir.file("base.tif"));
    expectCrossings(*file, {0, 3, 4, 20, 59}, {0, 1, 30, 58, 59});
    const auto mosaic = openPlanarMosaic({dir.file("base.tif"), dir.file("inset.tif")}, 16);
    ASSERT_EQ(mosaic->info().width, 1200);
    expectCrossings(*mosaic, columns, rows);
}

} // namespace
} // namespace pyramid
