// Heights in the unit their vertical GeoKeys name (input/height_unit.hpp): a DEM of NAVD88 heights
// in US survey feet (VerticalCSTypeGeoKey 6360, as GDAL writes EPSG:4326+6360, with no
// VerticalUnitsGeoKey) is read in metres, as is one whose VerticalUnitsGeoKey says feet; heights
// already in the ground's unit (metres, or the US survey feet of a State Plane CRS in them) are read
// as stored, and so are those of a code the EPSG database does not hold, which the description
// says. The nodata value stays as stored. A DEM pyramid of the feet is the pyramid of the metres,
// and its report and sidecar name the unit.
#include <gtest/gtest.h>

#include <geotiff/geokeys.h>

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"
#include "tests/support/small_dem.hpp"

namespace pyramid {
namespace {

constexpr double kUsFoot = 1200.0 / 3937.0;

struct Case {
    std::string name;
    int crs;          // EPSG code, geographic (4326) or projected
    int key;          // VerticalCSTypeGeoKey or VerticalUnitsGeoKey
    int code;         // its value
    double scale;     // what reading multiplies the stored heights by
    std::string unit; // the unit's name ("" when unknown)
};

test::GeoTiffTags tagsOf(const Case& c) {
    test::GeoTiffTags tags = c.crs == 4326 ? test::geographicTags(4326, -122.0, 47.0, 0.001)
                                           : test::projectedTags(c.crs, 500000.0, 5000000.0, 30.0);
    tags.shortKeys.emplace_back(c.key, c.code);
    tags.gdalNodata = "-9999";
    return tags;
}

TEST(HeightUnit, ReadsAreInTheGroundsUnit) {
    test::TempDir dir;
    const std::vector<Case> cases = {
        {"ftUS", 4326, VerticalCSTypeGeoKey, 6360, kUsFoot, "US survey foot"},
        {"foot", 4326, VerticalUnitsGeoKey, 9002, 0.3048, "foot"},
        {"ftUS-utm", 32610, VerticalCSTypeGeoKey, 6360, kUsFoot, "US survey foot"},
        {"metre", 4326, VerticalCSTypeGeoKey, 5703, 1.0, "metre"},
        {"ftUS-stateplane", 2286, VerticalCSTypeGeoKey, 6360, 1.0, "US survey foot"},
        {"unknown", 4326, VerticalCSTypeGeoKey, 1, 1.0, ""},
    };
    const std::vector<float> stored{100.0f, 250.5f, -9999.0f, 4392.7f};
    for (const Case& c : cases) {
        const std::string path = dir.file(c.name + ".tif");
        test::writeGeoTiff(path, 2, 2, stored, tagsOf(c));
        const auto source = RasterSource::open(path);
        ASSERT_TRUE(source->info().georeference) << c.name;
        const std::optional<HeightUnit>& unit = source->info().georeference->heightUnit;
        ASSERT_TRUE(unit) << c.name;
        EXPECT_EQ(unit->name, c.unit) << c.name;
        EXPECT_DOUBLE_EQ(source->info().georeference->heightsToGround(), c.scale) << c.name;
        if (c.name == "unknown") {
            EXPECT_NE(unit->source.find("does not hold"), std::string::npos) << unit->source;
        }
        std::vector<float> read(4);
        source->readFloat(0, 0, 2, 2, 0, read.data());
        for (size_t k = 0; k < stored.size(); ++k) {
            const float want = k == 2 ? -9999.0f : static_cast<float>(static_cast<double>(stored[k]) * c.scale);
            EXPECT_EQ(read[k], want) << c.name << " " << k;
        }
    }
    // A mosaic of a file in feet beside one in metres: each file's heights in metres.
    test::GeoTiffTags east = tagsOf(cases[3]);
    east.tiepoints[3] += 0.002;
    test::writeGeoTiff(dir.file("east.tif"), 2, 2, stored, east);
    const auto mosaic = RasterSource::openMosaic({dir.file("ftUS.tif"), dir.file("east.tif")}, 16);
    ASSERT_EQ(mosaic->info().width, 4);
    std::vector<float> row(4);
    mosaic->readFloat(0, 0, 4, 1, 0, row.data());
    EXPECT_EQ(row, (std::vector<float>{static_cast<float>(100.0 * kUsFoot), static_cast<float>(250.5 * kUsFoot), 100.0f,
                                       250.5f}));
    // No vertical key: no unit, heights as stored.
    test::writeGeoTiff(dir.file("none.tif"), 2, 2, stored, test::geographicTags(4326, -122.0, 47.0, 0.001));
    const auto none = RasterSource::open(dir.file("none.tif"));
    EXPECT_FALSE(none->info().georeference->heightUnit);
    std::vector<float> read(4);
    none->readFloat(0, 0, 2, 2, 0, read.data());
    EXPECT_EQ(read, stored);
}

TEST(HeightUnit, AFeetDemBuildsTheMetresPyramidAndSaysSo) {
    test::TempDir dir;
    const std::vector<float> metres = test::syntheticHeights(65, 65);
    std::vector<float> feet(metres.size()), converted(metres.size());
    for (size_t k = 0; k < metres.size(); ++k) {
        feet[k] = static_cast<float>(metres[k] / kUsFoot);
        converted[k] = static_cast<float>(static_cast<double>(feet[k]) * kUsFoot);
    }
    const Case ftUS{"ftUS", 32610, VerticalCSTypeGeoKey, 6360, kUsFoot, "US survey foot"};
    test::writeGeoTiff(dir.file("feet.tif"), 65, 65, feet, tagsOf(ftUS));
    test::GeoTiffTags plain = tagsOf(ftUS);
    plain.shortKeys.pop_back();
    test::writeGeoTiff(dir.file("metres.tif"), 65, 65, converted, plain);
    DemEncodeOptions o = test::smallDemOptions();
    const DemReport r = encodeDem(dir.file("feet.tif"), dir.file("feet.dat"), o);
    encodeDem(dir.file("metres.tif"), dir.file("metres.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("feet.dat")), test::readFile(dir.file("metres.dat")));
    const nlohmann::json heights = toJson(r)["input"]["heights"];
    EXPECT_EQ(heights["unit"], "US survey foot");
    EXPECT_EQ(heights["from"], "EPSG:6360 (NAVD88 height (ftUS))");
    EXPECT_DOUBLE_EQ(heights["scaled_by"].get<double>(), kUsFoot);
    const nlohmann::json sidecar = nlohmann::json::parse(test::readFile(dir.file("feet.dat.georef.json")));
    EXPECT_EQ(sidecar["crs"]["heights"], heights);
    EXPECT_TRUE(toJson(encodeDem(dir.file("metres.tif"), dir.file("m2.dat"), o))["input"]["heights"].is_null());
}

} // namespace
} // namespace pyramid
