// JPEG 2000 files (decoded by OpenImageIO; input/jpeg2000_boxes.hpp reads their boxes): GDAL's
// lossless JP2 of a window of samples/dem.tif reads back its samples, placed by its GeoJP2 box,
// and builds the pyramid and placement of a GeoTIFF of them; signed samples, which OpenImageIO
// reads shifted, are refused in a JP2 file and in a bare codestream; a JP2 without a GeoJP2 box
// is unplaced, and one whose GeoJP2 box holds no GeoTIFF is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sidecar_files.hpp"

namespace pyramid {
namespace {

std::string errorOf(const std::string& path) {
    try {
        RasterSource::open(path);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// The GeoJP2 box's UUID, where it lies in `bytes` (the box's type is 4 bytes before it).
size_t geoJp2At(const std::vector<uint8_t>& bytes) {
    const std::array<uint8_t, 16> uuid = {0xb1, 0x4b, 0xf8, 0xbd, 0x08, 0x3d, 0x4b, 0x43,
                                          0xa5, 0xae, 0x8c, 0xd7, 0xd5, 0xa6, 0xce, 0x03};
    const auto it = std::search(bytes.begin(), bytes.end(), uuid.begin(), uuid.end());
    return static_cast<size_t>(it - bytes.begin());
}

TEST(Jpeg2000, GdalsLosslessJp2ReadsAsItsTiff) {
    const auto dem = RasterSource::open(test::samplePath("dem.tif"));
    std::vector<float> window(65 * 65);
    dem->readFloat(100, 100, 165, 165, 0, window.data());
    for (float& v : window) {
        v = static_cast<float>(std::lround(v)); // GDAL's -ot UInt16
    }
    const std::string path = test::dataPath("gdal/window-u16.jp2");
    const auto jp2 = RasterSource::open(path);
    EXPECT_EQ(jp2->info().formatName, "jpeg2000");
    std::vector<float> v(window.size());
    jp2->readFloat(0, 0, 65, 65, 0, v.data());
    EXPECT_EQ(v, window);
    ASSERT_TRUE(jp2->info().georeference);
    EXPECT_EQ(jp2->info().georeference->epsg, 32610);
    const std::array<double, 6> place = {500000.0, 40.0, 0.0, 5200000.0, 0.0, -40.0};
    EXPECT_EQ(jp2->info().georeference->pixelToCrs, place);
    EXPECT_EQ(RasterSource::describe(path).georeference->pixelToCrs, place);

    // The pyramid and placement of a GeoTIFF of the same samples, byte for byte.
    test::TempDir dir;
    test::writeGeoTiff(dir.file("window.tif"), 65, 65, window, test::projectedTags(32610, 500000.0, 5200000.0, 40.0));
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 8;
    o.maxLevel = 3;
    encodeDem(path, dir.file("jp2.dat"), o);
    encodeDem(dir.file("window.tif"), dir.file("tif.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("jp2.dat")), test::readFile(dir.file("tif.dat")));
    EXPECT_EQ(test::placementOf(dir.file("jp2.dat")), test::placementOf(dir.file("tif.dat")));
}

TEST(Jpeg2000, SignedSamplesAreRefused) {
    for (const char* name : {"gdal/window-i16.jp2", "gdal/window-i16.j2k"}) {
        const std::string path = test::dataPath(name);
        EXPECT_EQ(errorOf(path), path + ": holds signed 16-bit JPEG 2000 samples, which OpenImageIO reads shifted: "
                                        "convert it to a GeoTIFF first");
        EXPECT_THROW(RasterSource::describe(path), Error);
    }
}

TEST(Jpeg2000, GeoJp2Boxes) {
    test::TempDir dir;
    const std::string original = test::readFile(test::dataPath("gdal/window-u16.jp2"));
    std::vector<uint8_t> bytes(original.begin(), original.end());
    const size_t uuid = geoJp2At(bytes);
    ASSERT_LT(uuid, bytes.size());

    // Without it (the box made a free box, which readers skip): unplaced.
    std::vector<uint8_t> free = bytes;
    std::copy_n("free", 4, free.begin() + static_cast<std::ptrdiff_t>(uuid) - 4);
    test::writeBytes(dir.file("free.jp2"), free);
    const auto unplaced = RasterSource::open(dir.file("free.jp2"));
    EXPECT_EQ(unplaced->info().width, 65);
    EXPECT_FALSE(unplaced->info().georeference);

    // A GeoJP2 box whose TIFF is damaged (its byte order mark) is refused.
    std::vector<uint8_t> damaged = bytes;
    damaged[uuid + 16] = 'X';
    test::writeBytes(dir.file("damaged.jp2"), damaged);
    EXPECT_EQ(errorOf(dir.file("damaged.jp2")), dir.file("damaged.jp2") + ": its GeoJP2 box holds no GeoTIFF with GeoKeys");
}

} // namespace
} // namespace pyramid
