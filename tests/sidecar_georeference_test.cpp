// Georeferencing beside a raster (input/sidecar_georeference.hpp): GDAL's PAM file (FILE.aux.xml,
// as GDAL writes it beside a PNG it makes from a GeoTIFF) and a world file with a .prj place a PNG
// exactly where the GeoTIFF of the same heights lies: the same pyramid and the same placement. A
// world file without a CRS of the EPSG database leaves the file unplaced, as before; a sidecar that
// cannot be read is refused, naming it; a GeoTIFF's own tags come before its sidecars.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sidecar_files.hpp"
#include "tests/support/rasters.hpp"
#include "tests/support/small_dem.hpp"

namespace pyramid {
namespace {

// EPSG:32610 as `gdalsrsinfo` writes it: OGC WKT1 (the root's AUTHORITY last, after the nested
// ones), ESRI's WKT (no authority: PROJ identifies it) and the end of WKT2.
const char* const kUtmWkt1 =
    "PROJCS[\"WGS 84 / UTM zone 10N\", GEOGCS[\"WGS 84\", DATUM[\"WGS_1984\", SPHEROID[\"WGS 84\",6378137,"
    "298.257223563, AUTHORITY[\"EPSG\",\"7030\"]], AUTHORITY[\"EPSG\",\"6326\"]], PRIMEM[\"Greenwich\",0, "
    "AUTHORITY[\"EPSG\",\"8901\"]], UNIT[\"degree\",0.0174532925199433, AUTHORITY[\"EPSG\",\"9122\"]], "
    "AUTHORITY[\"EPSG\",\"4326\"]], PROJECTION[\"Transverse_Mercator\"], PARAMETER[\"latitude_of_origin\",0], "
    "PARAMETER[\"central_meridian\",-123], PARAMETER[\"scale_factor\",0.9996], PARAMETER[\"false_easting\",500000], "
    "PARAMETER[\"false_northing\",0], UNIT[\"metre\",1, AUTHORITY[\"EPSG\",\"9001\"]], AXIS[\"Easting\",EAST], "
    "AXIS[\"Northing\",NORTH], AUTHORITY[\"EPSG\",\"32610\"]]";
const char* const kUtmEsri =
    "PROJCS[\"WGS_1984_UTM_Zone_10N\", GEOGCS[\"GCS_WGS_1984\", DATUM[\"D_WGS_1984\", SPHEROID[\"WGS_1984\","
    "6378137.0,298.257223563]], PRIMEM[\"Greenwich\",0.0], UNIT[\"Degree\",0.0174532925199433]], "
    "PROJECTION[\"Transverse_Mercator\"], PARAMETER[\"False_Easting\",500000.0], PARAMETER[\"False_Northing\",0.0], "
    "PARAMETER[\"Central_Meridian\",-123.0], PARAMETER[\"Scale_Factor\",0.9996], PARAMETER[\"Latitude_Of_Origin\",0.0], "
    "UNIT[\"Meter\",1.0]]";
const char* const kGeographicWkt1 =
    "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563,AUTHORITY[\"EPSG\",\"7030\"]],"
    "AUTHORITY[\"EPSG\",\"6326\"]],PRIMEM[\"Greenwich\",0,AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\","
    "0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],AXIS[\"Latitude\",NORTH],AXIS[\"Longitude\",EAST],"
    "AUTHORITY[\"EPSG\",\"4326\"]]";

// Heights 100..1100 as 16-bit samples, a 65 x 65 grid.
std::vector<uint16_t> heights() {
    const std::vector<float> h = test::syntheticHeights(65, 65, 500.0f);
    std::vector<uint16_t> v(h.size());
    for (size_t k = 0; k < h.size(); ++k) {
        v[k] = static_cast<uint16_t>(std::lround(h[k] + 600.0f));
    }
    return v;
}

TEST(SidecarGeoreference, EpsgCodesOfWkt) {
    EXPECT_EQ(epsgOfWkt(kUtmWkt1), 32610); // the root's, not the nested GEOGCS's 4326
    EXPECT_EQ(epsgOfWkt(kGeographicWkt1), 4326);
    EXPECT_EQ(epsgOfWkt("PROJCRS[\"WGS 84 / UTM zone 10N\",BASEGEOGCRS[\"WGS 84\",ID[\"EPSG\",4326]],"
                        "CONVERSION[\"UTM zone 10N\",ID[\"EPSG\",16010]],ID[\"EPSG\",32610]]"),
              32610);
    EXPECT_EQ(epsgOfWkt("GEOGCRS[\"WGS 84\",ID[\"EPSG\",4326,URI[\"urn:ogc:def:crs:EPSG::4326\"]]]"), 4326);
    EXPECT_EQ(epsgOfWkt(kUtmEsri), 32610); // identified by PROJ
    EXPECT_EQ(epsgOfWkt("LOCAL_CS[\"a plan\"]"), 0);
    EXPECT_EQ(epsgOfWkt("not a CRS"), 0);
}

TEST(SidecarGeoreference, AWorldFileAndPrjPlaceAPngAsItsGeoTiff) {
    test::TempDir dir;
    const std::vector<uint16_t> v = heights();
    // The PNG: a world file (the top-left pixel's centre) and ESRI's .prj.
    test::writeImage(dir.file("dem.png"), 65, 65, 1, v, true);
    test::writeText(dir.file("dem.pgw"), "30.0\n0.0\n0.0\n-30.0\n500015.0\n4999985.0\n");
    test::writeText(dir.file("dem.prj"), kUtmEsri);
    // The GeoTIFF: the same samples, its corner at (500000, 5000000).
    test::writeGeoTiffInt16(dir.file("dem.tif"), 65, 65, std::vector<int16_t>(v.begin(), v.end()),
                            test::projectedTags(32610, 500000.0, 5000000.0, 30.0));
    const RasterInfo png = RasterSource::describe(dir.file("dem.png"));
    ASSERT_TRUE(png.georeference);
    EXPECT_EQ(png.georeference->epsg, 32610);
    EXPECT_TRUE(png.georeference->problem.empty());
    EXPECT_EQ(png.georeference->pixelToCrs, (std::array<double, 6>{500000.0, 30.0, 0.0, 5000000.0, 0.0, -30.0}));

    DemEncodeOptions o = test::smallDemOptions();
    encodeDem(dir.file("dem.png"), dir.file("png.dat"), o);
    encodeDem(dir.file("dem.tif"), dir.file("tif.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("png.dat")), test::readFile(dir.file("tif.dat")));
    EXPECT_EQ(test::placementOf(dir.file("png.dat")), test::placementOf(dir.file("tif.dat")));

    // A GeoTIFF's own tags come first: a world file beside it changes nothing.
    test::writeText(dir.file("dem.tfw"), "1\n0\n0\n-1\n0.5\n-0.5\n");
    EXPECT_EQ(RasterSource::describe(dir.file("dem.tif")).georeference->pixelToCrs[0], 500000.0);
}

TEST(SidecarGeoreference, GdalsPamFilePlacesAndDescribesAPng) {
    test::TempDir dir;
    test::writeImage(dir.file("dem.png"), 65, 65, 1, heights(), true);
    test::writeText(dir.file("dem.png.aux.xml"),
              std::string("<PAMDataset>\n  <SRS dataAxisToSRSAxisMapping=\"2,1\">") + kGeographicWkt1 +
                  "</SRS>\n  <GeoTransform> -1.2200041666666667e+02,  8.3333333333333339e-04,  "
                  "0.0000000000000000e+00,  4.7000416666666666e+01,  0.0000000000000000e+00, "
                  "-8.3333333333333339e-04</GeoTransform>\n"
                  "  <Metadata>\n    <MDI key=\"AREA_OR_POINT\">Area</MDI>\n  </Metadata>\n"
                  "  <PAMRasterBand band=\"1\">\n    <NoDataValue>0</NoDataValue>\n    <Offset>-100</Offset>\n"
                  "    <Scale>0.5</Scale>\n    <UnitType>ft</UnitType>\n  </PAMRasterBand>\n</PAMDataset>\n");
    const auto source = RasterSource::open(dir.file("dem.png"));
    const RasterInfo& info = source->info();
    ASSERT_TRUE(info.georeference);
    EXPECT_EQ(info.georeference->epsg, 4326);
    EXPECT_EQ(info.georeference->pixelToCrs[0], -1.2200041666666667e+02);
    EXPECT_EQ(info.georeference->pixelToCrs[5], -8.3333333333333339e-04);
    EXPECT_EQ(info.nodata, 0.0);
    EXPECT_EQ(info.scaling, (std::vector<ValueScaling>{{0.5, -100.0}}));
    ASSERT_TRUE(info.georeference->heightUnit);
    EXPECT_EQ(info.georeference->heightUnit->name, "foot");
    std::vector<uint16_t> stored(1);
    source->readUInt16(0, 0, 1, 1, 0, 1, stored.data());
    float height = 0.0f;
    source->readFloat(0, 0, 1, 1, 0, &height);
    EXPECT_EQ(height, static_cast<float>((stored[0] * 0.5 - 100.0) * 0.3048));
}

TEST(SidecarGeoreference, SidecarsThatPlaceNothingOrCannotBeReadAreNamed) {
    test::TempDir dir;
    const std::vector<uint16_t> v = heights();
    test::writeImage(dir.file("a.png"), 65, 65, 1, v, true);
    test::writeImage(dir.file("b.png"), 65, 65, 1, v, true);
    test::writeText(dir.file("a.wld"), "30 0 0 -30 500015 4999985");
    test::writeText(dir.file("b.wld"), "30 0 0 -30 501965 4999985");
    // No CRS: the file stays unplaced, as without its world file; a mosaic of such is refused.
    EXPECT_FALSE(RasterSource::describe(dir.file("a.png")).georeference);
    EXPECT_NE(test::errorMessage([&] { RasterSource::openMosaic({dir.file("a.png"), dir.file("b.png")}); })
                  .find("a.png: has no georeferencing (no GeoTIFF tags, nor a world file with a CRS"),
              std::string::npos);
    // With a CRS each, the two join side by side.
    test::writeText(dir.file("a.prj"), kUtmWkt1);
    test::writeText(dir.file("b.prj"), kUtmWkt1);
    EXPECT_EQ(RasterSource::openMosaic({dir.file("a.png"), dir.file("b.png")})->info().width, 130);

    test::writeText(dir.file("a.wld"), "30 0 0 -30 500015");
    EXPECT_EQ(test::errorMessage([&] { RasterSource::describe(dir.file("a.png")); }),
              dir.file("a.wld") + ": a world file holds 6 numbers, not 5");
    test::writeText(dir.file("a.wld"), "30 0 0 0 500015 4999985");
    EXPECT_EQ(test::errorMessage([&] { RasterSource::describe(dir.file("a.png")); }),
              dir.file("a.wld") + ": its transform is singular: it places no pixel");
    // A CRS of no EPSG code (a local plan, a body of the IAU's): unplaced, as before.
    test::writeText(dir.file("a.wld"), "30 0 0 -30 500015 4999985");
    test::writeText(dir.file("a.prj"), "LOCAL_CS[\"a plan\"]");
    EXPECT_FALSE(RasterSource::describe(dir.file("a.png")).georeference);
    test::writeText(dir.file("b.png.aux.xml"), "<PAMDataset><GeoTransform>1,2</PAMDataset>");
    EXPECT_NE(test::errorMessage([&] { RasterSource::describe(dir.file("b.png")); }).find(dir.file("b.png.aux.xml") + ": malformed XML"),
              std::string::npos);
}

} // namespace
} // namespace pyramid
