// JPEG 2000 files (decoded by OpenImageIO; input/jpeg2000_boxes.hpp reads their boxes): GDAL's
// lossless JP2 of a window of samples/dem.tif reads back its samples, placed by its GeoJP2 box,
// and builds the pyramid and placement of a GeoTIFF of them; signed samples, which OpenImageIO
// reads shifted, are refused in a JP2 file and in a bare codestream; without its GeoJP2 box a JP2
// is placed alike by its GMLJP2 document (latitude first for EPSG:4326's URN), without either it
// is unplaced; a GeoJP2 box that holds no GeoTIFF, or a GML document that is no XML, is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/gdal_window.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sidecar_files.hpp"
#include "tests/support/small_dem.hpp"

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

TEST(Jpeg2000, GdalsLosslessJp2ReadsAsItsTiff) {
    const std::vector<float> window = test::gdalWindow(true); // GDAL's -ot UInt16
    const std::string path = test::dataPath("gdal/window-u16.jp2");
    const auto jp2 = RasterSource::open(path);
    EXPECT_EQ(jp2->info().formatName, "jpeg2000");
    test::expectGdalWindow(*jp2, window);
    EXPECT_EQ(RasterSource::describe(path).georeference->pixelToCrs, test::kGdalWindowPlace);

    // The pyramid and placement of a GeoTIFF of the same samples, byte for byte.
    test::TempDir dir;
    test::writeGeoTiff(dir.file("window.tif"), 65, 65, window, test::projectedTags(32610, 500000.0, 5200000.0, 40.0));
    DemEncodeOptions o = test::smallDemOptions();
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

// `bytes` with the box whose contents begin with `contents` made a free box, which readers skip.
std::vector<uint8_t> freed(std::vector<uint8_t> bytes, const std::vector<uint8_t>& contents) {
    const auto it = std::search(bytes.begin(), bytes.end(), contents.begin(), contents.end());
    EXPECT_NE(it, bytes.end());
    std::copy_n("free", 4, it - 4);
    return bytes;
}

std::vector<uint8_t> fileBytes(const std::string& path) {
    const std::string text = test::readFile(path);
    return std::vector<uint8_t>(text.begin(), text.end());
}

const std::vector<uint8_t> kGeoJp2Uuid = {0xb1, 0x4b, 0xf8, 0xbd, 0x08, 0x3d, 0x4b, 0x43,
                                          0xa5, 0xae, 0x8c, 0xd7, 0xd5, 0xa6, 0xce, 0x03};

TEST(Jpeg2000, GeoJp2AndGmlJp2Boxes) {
    test::TempDir dir;
    // Without the GeoJP2 box, the GMLJP2 document places the file alike: in EPSG:32610 (x first),
    // and in EPSG:4326, whose URN gives latitude first (GDAL's 121 x 121 JP2 of Mt Rainier's
    // cell, n46-u16.jp2).
    for (const char* name : {"gdal/window-u16.jp2", "gdal/n46-u16.jp2"}) {
        const std::string path = test::dataPath(name);
        const std::string gml = dir.file("gml.jp2");
        test::writeBytes(gml, freed(fileBytes(path), kGeoJp2Uuid));
        const Georeference geoJp2 = *RasterSource::open(path)->info().georeference;
        const std::optional<Georeference> g = RasterSource::open(gml)->info().georeference;
        ASSERT_TRUE(g) << name;
        EXPECT_EQ(g->epsg, geoJp2.epsg) << name;
        for (size_t k = 0; k < 6; ++k) {
            EXPECT_NEAR(g->pixelToCrs[k], geoJp2.pixelToCrs[k], 1e-9 * std::max(1.0, std::abs(geoJp2.pixelToCrs[k])))
                << name << " " << k;
        }
    }
    EXPECT_NEAR(RasterSource::open(test::dataPath("gdal/n46-u16.jp2"))->info().georeference->pixelToCrs[0],
                -122.0 - 1.0 / 240, 1e-12);

    // Without either: unplaced.
    const std::vector<uint8_t> bytes = fileBytes(test::dataPath("gdal/window-u16.jp2"));
    std::vector<uint8_t> none = freed(bytes, kGeoJp2Uuid);
    const std::string asoc = "asoc"; // GMLJP2's box
    std::copy_n("free", 4, std::search(none.begin(), none.end(), asoc.begin(), asoc.end()));
    test::writeBytes(dir.file("none.jp2"), none);
    const auto unplaced = RasterSource::open(dir.file("none.jp2"));
    EXPECT_EQ(unplaced->info().width, 65);
    EXPECT_FALSE(unplaced->info().georeference);

    // A GeoJP2 box whose TIFF is damaged (its byte order mark) is refused.
    std::vector<uint8_t> damaged = bytes;
    damaged[static_cast<size_t>(std::search(bytes.begin(), bytes.end(), kGeoJp2Uuid.begin(), kGeoJp2Uuid.end()) -
                                bytes.begin()) +
            16] = 'X';
    test::writeBytes(dir.file("damaged.jp2"), damaged);
    EXPECT_EQ(errorOf(dir.file("damaged.jp2")), dir.file("damaged.jp2") + ": its GeoJP2 box holds no GeoTIFF with GeoKeys");
    // So is a GMLJP2 document that is not XML.
    std::vector<uint8_t> notXml = freed(bytes, kGeoJp2Uuid);
    const std::string collection = "<gml:FeatureCollection";
    *std::search(notXml.begin(), notXml.end(), collection.begin(), collection.end()) = '!';
    test::writeBytes(dir.file("gml.jp2"), notXml);
    EXPECT_NE(errorOf(dir.file("gml.jp2")).find(dir.file("gml.jp2") + ": its GMLJP2 document is not well-formed XML"),
              std::string::npos);
}

} // namespace
} // namespace pyramid
