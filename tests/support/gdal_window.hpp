// The window of samples/dem.tif (its pixels 100..164, 65 x 65) that tests/data/gdal/'s files
// hold as GDAL wrote them (tests/data/gdal/README.md), and where they place it: (500000, 5200000)
// in EPSG:32610, 40 m cells.
#pragma once
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "libpyramid/input/raster_source.hpp"
#include "tests/support/paths.hpp"

namespace pyramid::test {

inline const std::array<double, 6> kGdalWindowPlace = {500000.0, 40.0, 0.0, 5200000.0, 0.0, -40.0};

// The window's heights, row 0 north; `rounded` to whole numbers, as GDAL's -ot Int16 and -ot
// UInt16 store them.
inline std::vector<float> gdalWindow(bool rounded = false) {
    const auto dem = RasterSource::open(samplePath("dem.tif"));
    std::vector<float> w(65 * 65);
    dem->readFloat(100, 100, 165, 165, 0, w.data());
    if (rounded) {
        for (float& v : w) {
            v = static_cast<float>(std::lround(v));
        }
    }
    return w;
}

// `source` holds the window's samples (`window`, as gdalWindow gives them), placed where
// tests/data/gdal/'s files place it (EPSG:32610, kGdalWindowPlace).
inline void expectGdalWindow(const RasterSource& source, const std::vector<float>& window) {
    std::vector<float> v(window.size());
    source.readFloat(0, 0, 65, 65, 0, v.data());
    EXPECT_EQ(v, window);
    ASSERT_TRUE(source.info().georeference);
    EXPECT_EQ(source.info().georeference->epsg, 32610);
    EXPECT_EQ(source.info().georeference->pixelToCrs, kGdalWindowPlace);
}

} // namespace pyramid::test
