// GDAL's band metadata (input/gdal_band_metadata.hpp): a GeoTIFF whose GDAL_METADATA tag gives a
// band a scale and offset (as `gdal_translate -a_scale 0.5 -a_offset -100` writes them) has its
// heights read as stored x scale + offset, the nodata value kept as stored; a UNITTYPE names the
// heights' unit where no vertical GeoKey does. A DEM pyramid of such a file is the pyramid of its
// heights written as float32, and says so in its report. A VRT band's <Scale>, <Offset> and
// <UnitType> must be what its sources declare. Tags that cannot be read are refused.
#include <gtest/gtest.h>

#include <geotiff/geokeys.h>

#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/gdal_band_metadata.hpp"
#include "libpyramid/input/input_list.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"
#include "tests/support/small_dem.hpp"

namespace pyramid {
namespace {

// The tag as GDAL 3.6 writes it for `-a_scale 0.5 -a_offset -100` (and a unit through a VRT).
std::string gdalMetadata(const std::string& scale, const std::string& offset, const std::string& unit = "") {
    std::string xml = "<GDALMetadata>\n";
    xml += "  <Item name=\"OFFSET\" sample=\"0\" role=\"offset\">" + offset + "</Item>\n";
    xml += "  <Item name=\"SCALE\" sample=\"0\" role=\"scale\">" + scale + "</Item>\n";
    if (!unit.empty()) {
        xml += "  <Item name=\"UNITTYPE\" sample=\"0\" role=\"unittype\">" + unit + "</Item>\n";
    }
    return xml + "</GDALMetadata>\n";
}

test::GeoTiffTags tagsWith(const std::string& metadata) {
    test::GeoTiffTags tags = test::geographicTags(4326, -122.0, 47.0, 0.001);
    tags.gdalNodata = "-32768";
    tags.gdalMetadata = metadata;
    return tags;
}

TEST(GdalBandMetadata, ReadsEachBandsScaleOffsetAndUnit) {
    const std::string xml = "<GDALMetadata>\n"
                            "  <Item name=\"AREA_OR_POINT\">Area</Item>\n"
                            "  <Item name=\"SCALE\" sample=\"1\" role=\"scale\">0.25</Item>\n"
                            "  <Item name=\"OFFSET\" sample=\"0\" role=\"offset\"> -100 </Item>\n"
                            "  <Item name=\"UNITTYPE\" sample=\"1\" role=\"unittype\">m</Item>\n"
                            "  <Item name=\"UNITTYPE\" sample=\"0\" role=\"unittype\">ft</Item>\n"
                            "  <Item name=\"SCALE\" sample=\"7\" role=\"scale\">9</Item>\n"
                            "</GDALMetadata>";
    const GdalBandMetadata m = parseGdalMetadata(xml, 2, "a.tif");
    ASSERT_EQ(m.scaling.size(), 2u);
    EXPECT_EQ(m.scaling[0], (ValueScaling{1.0, -100.0}));
    EXPECT_EQ(m.scaling[1], (ValueScaling{0.25, 0.0}));
    EXPECT_EQ(m.unitType, "ft"); // band 1's, though band 2's comes first
    // No scale or offset: every band as stored.
    EXPECT_TRUE(parseGdalMetadata("<GDALMetadata><Item name=\"A\">1</Item></GDALMetadata>", 1, "a.tif").scaling.empty());

    EXPECT_EQ(heightUnitOfUnitType("ft").metres, 0.3048);
    EXPECT_EQ(heightUnitOfUnitType("US survey foot").metres, 1200.0 / 3937.0);
    EXPECT_EQ(heightUnitOfUnitType("ftUS").name, "US survey foot");
    EXPECT_EQ(heightUnitOfUnitType("metre").metres, 1.0);
    EXPECT_EQ(heightUnitOfUnitType("cm").metres, 0.01);
    const HeightUnit unknown = heightUnitOfUnitType("furlong");
    EXPECT_EQ(unknown.metres, 0.0);
    EXPECT_EQ(unknown.name, "");
    EXPECT_NE(unknown.source.find("furlong"), std::string::npos);
}

TEST(GdalBandMetadata, TagsThatCannotBeReadAreRefusedNamingTheFile) {
    const auto refusal = [](const std::string& xml) {
        return test::errorMessage([&] { parseGdalMetadata(xml, 1, "dem.tif"); });
    };
    EXPECT_NE(refusal("<GDALMetadata><Item sample=\"0\" role=\"scale\">0.5</GDALMetadata>").find("dem.tif: GDAL metadata (TIFF tag 42112): malformed XML"), std::string::npos);
    EXPECT_EQ(refusal(gdalMetadata("0", "0")), "dem.tif: GDAL metadata (TIFF tag 42112): band 1's scale '0' is not a finite non-zero number");
    EXPECT_EQ(refusal(gdalMetadata("1", "abc")), "dem.tif: GDAL metadata (TIFF tag 42112): band 1's offset 'abc' is not a finite number");
    EXPECT_NE(refusal(gdalMetadata("nan", "0")).find("scale 'nan'"), std::string::npos);

    // A file's tag is refused as the file is described.
    test::TempDir dir;
    test::writeGeoTiffInt16(dir.file("bad.tif"), 2, 2, {1, 2, 3, 4}, tagsWith(gdalMetadata("x", "0")));
    EXPECT_NE(test::errorMessage([&] { RasterSource::describe(dir.file("bad.tif")); }).find("bad.tif: GDAL metadata"), std::string::npos);
}

TEST(GdalBandMetadata, HeightsAreTheStoredSamplesScaledAndOffset) {
    test::TempDir dir;
    const std::vector<int16_t> stored{8000, -32768, 1, -3};
    const std::string path = dir.file("half-metres.tif");
    test::writeGeoTiffInt16(path, 2, 2, stored, tagsWith(gdalMetadata("0.5", "-100")));
    const auto source = RasterSource::open(path);
    ASSERT_EQ(source->info().scaling, (std::vector<ValueScaling>{{0.5, -100.0}}));
    std::vector<float> read(4);
    source->readFloat(0, 0, 2, 2, 0, read.data());
    EXPECT_EQ(read, (std::vector<float>{3900.0f, -32768.0f, -99.5f, -101.5f})); // the nodata as stored
    std::vector<float> at(2);
    source->readFloatAt({1}, {0, 1}, 0, at.data());
    EXPECT_EQ(at, (std::vector<float>{-32768.0f, -101.5f}));

    // A unit by UNITTYPE alone: (stored x scale + offset) in feet, read in metres.
    test::writeGeoTiffInt16(dir.file("feet.tif"), 2, 2, stored, tagsWith(gdalMetadata("2", "10", "ft")));
    const auto feet = RasterSource::open(dir.file("feet.tif"));
    ASSERT_TRUE(feet->info().georeference->heightUnit);
    EXPECT_EQ(feet->info().georeference->heightUnit->name, "foot");
    feet->readFloat(0, 0, 2, 2, 0, read.data());
    EXPECT_EQ(read[0], static_cast<float>((8000.0 * 2.0 + 10.0) * 0.3048));
    EXPECT_EQ(read[3], static_cast<float>((-3.0 * 2.0 + 10.0) * 0.3048));
    // A vertical GeoKey names the unit before UNITTYPE does.
    test::GeoTiffTags keyed = tagsWith(gdalMetadata("1", "0", "ft"));
    keyed.shortKeys.emplace_back(VerticalUnitsGeoKey, 9001); // metre
    test::writeGeoTiffInt16(dir.file("keyed.tif"), 2, 2, stored, keyed);
    EXPECT_EQ(RasterSource::describe(dir.file("keyed.tif")).georeference->heightUnit->name, "metre");

    // A value the scaling lands on the nodata value is refused, not taken for a gap.
    test::writeGeoTiffInt16(dir.file("lands.tif"), 2, 2, {0, 1, 2, 3}, tagsWith(gdalMetadata("1", "-32770")));
    const auto lands = RasterSource::open(dir.file("lands.tif"));
    EXPECT_NE(test::errorMessage([&] { lands->readFloat(0, 0, 2, 2, 0, read.data()); })
                  .find("lands.tif: the sample 2 at pixel (0, 1) is the height -32768, the nodata value"),
              std::string::npos);

    // A mosaic reads each file by its own scaling.
    test::GeoTiffTags east = tagsWith(gdalMetadata("0.1", "0"));
    east.tiepoints[3] += 0.002;
    test::writeGeoTiffInt16(dir.file("east.tif"), 2, 2, {10, 20, 30, 40}, east);
    const auto mosaic = RasterSource::openMosaic({path, dir.file("east.tif")}, 16);
    EXPECT_TRUE(mosaic->info().scaling.empty()); // the files disagree
    std::vector<float> row(4);
    mosaic->readFloat(0, 0, 4, 1, 0, row.data());
    EXPECT_EQ(row, (std::vector<float>{3900.0f, -32768.0f, 1.0f, 2.0f}));
}

// GDAL's own file (tests/data/gdal/README.md): samples/dem.tif's heights stored as h x 2 + 200,
// scale 0.5 and offset -100; read back within the half step of its rounding.
TEST(GdalBandMetadata, GdalsOwnScaledFileReadsAsTheHeights) {
    const auto scaled = RasterSource::open(test::dataPath("gdal/scaled-dem.tif"));
    ASSERT_EQ(scaled->info().type, SampleType::Int16);
    ASSERT_EQ(scaled->info().scaling, (std::vector<ValueScaling>{{0.5, -100.0}}));
    const auto heights = RasterSource::open(test::samplePath("dem.tif"));
    std::vector<float> read(65 * 65), want(65 * 65);
    scaled->readFloat(0, 0, 65, 65, 0, read.data());
    heights->readFloat(100, 100, 165, 165, 0, want.data());
    for (size_t k = 0; k < read.size(); ++k) {
        ASSERT_LE(std::fabs(read[k] - want[k]), 0.25f) << k;
    }
}

TEST(GdalBandMetadata, AScaledDemBuildsThePyramidOfItsHeightsAndSaysSo) {
    test::TempDir dir;
    const std::vector<float> heights = test::syntheticHeights(65, 65);
    std::vector<int16_t> stored(heights.size());
    std::vector<float> values(heights.size());
    for (size_t k = 0; k < heights.size(); ++k) {
        stored[k] = static_cast<int16_t>(std::lround((heights[k] + 100.0f) * 2.0f));
        values[k] = static_cast<float>(stored[k] * 0.5 - 100.0);
    }
    test::writeGeoTiffInt16(dir.file("scaled.tif"), 65, 65, stored, tagsWith(gdalMetadata("0.5", "-100")));
    test::writeGeoTiff(dir.file("heights.tif"), 65, 65, values, tagsWith(""));
    DemEncodeOptions o = test::smallDemOptions();
    const DemReport r = encodeDem(dir.file("scaled.tif"), dir.file("scaled.dat"), o);
    encodeDem(dir.file("heights.tif"), dir.file("heights.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("scaled.dat")), test::readFile(dir.file("heights.dat")));
    const nlohmann::json input = toJson(r)["input"];
    EXPECT_EQ(input["values"], (nlohmann::json{{"scale", 0.5}, {"offset", -100.0}, {"from", "GDAL metadata"}}));
    EXPECT_TRUE(toJson(encodeDem(dir.file("heights.tif"), dir.file("h2.dat"), o))["input"]["values"].is_null());

    // Another nodata value than the file's own would be compared with converted heights: refused.
    DemEncodeOptions other = o;
    other.nodata = -9999.0;
    const auto refusal = [&](const DemEncodeOptions& with) {
        try {
            encodeDem(dir.file("scaled.tif"), dir.file("other.dat"), with);
        } catch (const OptionError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(refusal(other).find("scaled.tif's heights are read converted (a scale, an offset or another unit)"), std::string::npos);
    other.nodata.reset();
    other.ignoreDeclaredNodata = true;
    EXPECT_NE(refusal(other).find("scaled.tif's heights"), std::string::npos);
    other.nodata = -32768.0; // the file's own
    other.ignoreDeclaredNodata = false;
    EXPECT_EQ(refusal(other), "");
    EXPECT_EQ(test::readFile(dir.file("other.dat")), test::readFile(dir.file("scaled.dat")));
}

TEST(GdalBandMetadata, AVrtBandDeclaresWhatItsSourcesDeclare) {
    test::TempDir dir;
    test::writeGeoTiffInt16(dir.file("a.tif"), 2, 2, {1, 2, 3, 4}, tagsWith(gdalMetadata("0.5", "-100")));
    const auto vrt = [&](const std::string& name, const std::string& band) {
        std::ofstream(dir.file(name)) << ("<VRTDataset rasterXSize=\"2\" rasterYSize=\"2\">\n"
                                        "  <VRTRasterBand dataType=\"Int16\" band=\"1\">\n" +
                                            band +
                                            "    <SimpleSource><SourceFilename relativeToVRT=\"1\">a.tif</SourceFilename>"
                                            "<SourceBand>1</SourceBand></SimpleSource>\n"
                                            "  </VRTRasterBand>\n</VRTDataset>\n");
        return std::vector<std::string>{dir.file(name)};
    };
    // As gdalbuildvrt writes it: the source's scale and offset copied to the band.
    const InputList list = expandInputs(vrt("same.vrt", "<Offset>-100</Offset><Scale>0.5</Scale>"));
    ASSERT_EQ(list.paths, (std::vector<std::string>{dir.file("a.tif")}));
    const auto same = RasterSource::open(list.paths[0]);
    std::vector<float> read(4);
    same->readFloat(0, 0, 2, 2, 0, read.data());
    EXPECT_EQ(read, (std::vector<float>{-99.5f, -99.0f, -98.5f, -98.0f}));
    EXPECT_NE(test::errorMessage([&] { expandInputs(vrt("other.vrt", "<Scale>2</Scale>")); })
                  .find("other.vrt: band 1 declares scale 2 and offset 0 (<Scale>, <Offset>), but "),
              std::string::npos);
    EXPECT_NE(test::errorMessage([&] {
                  expandInputs(vrt("feet.vrt", "<Offset>-100</Offset><Scale>0.5</Scale><UnitType>ft</UnitType>"));
              }).find("feet.vrt: band 1 declares heights in foot (<UnitType>ft</UnitType>), but "),
              std::string::npos);
}

} // namespace
} // namespace pyramid
