// The EPSG codes that raster headers name by a datum's name and a UTM zone (input/datum_epsg.hpp):
// the spellings of ESRI's old .prj, ENVI's map info and ERDAS Imagine's Datum node, and the zones
// the EPSG database has for each datum.
#include <gtest/gtest.h>

#include "libpyramid/input/datum_epsg.hpp"

namespace pyramid {
namespace {

TEST(DatumEpsg, NamesAsHeadersSpellThem) {
    for (const char* name : {"WGS84", "WGS 84", "wgs-84", "Wgs_84"}) {
        EXPECT_EQ(namedDatum(name), NamedDatum::Wgs84) << name;
    }
    for (const char* name : {"NAD83", "North America 1983", "North American 1983"}) {
        EXPECT_EQ(namedDatum(name), NamedDatum::Nad83) << name;
    }
    for (const char* name : {"NAD27", "north america 1927", "North American 1927"}) {
        EXPECT_EQ(namedDatum(name), NamedDatum::Nad27) << name;
    }
    for (const char* name : {"", "WGS72", "NAD83(HARN)", "D_WGS_1984", "Airy"}) {
        EXPECT_EQ(namedDatum(name), NamedDatum::Other) << name;
    }
}

TEST(DatumEpsg, GeographicAndUtmCodes) {
    EXPECT_EQ(geographicEpsg(NamedDatum::Wgs84), 4326);
    EXPECT_EQ(geographicEpsg(NamedDatum::Nad83), 4269);
    EXPECT_EQ(geographicEpsg(NamedDatum::Nad27), 4267);
    EXPECT_EQ(geographicEpsg(NamedDatum::Other), 0);

    EXPECT_EQ(utmEpsg(10, false, NamedDatum::Wgs84), 32610);
    EXPECT_EQ(utmEpsg(33, true, NamedDatum::Wgs84), 32733);
    EXPECT_EQ(utmEpsg(60, false, NamedDatum::Wgs84), 32660);
    EXPECT_EQ(utmEpsg(0, false, NamedDatum::Wgs84), 0);
    EXPECT_EQ(utmEpsg(61, false, NamedDatum::Wgs84), 0);
    EXPECT_EQ(utmEpsg(23, false, NamedDatum::Nad83), 26923);
    EXPECT_EQ(utmEpsg(24, false, NamedDatum::Nad83), 0);
    EXPECT_EQ(utmEpsg(10, true, NamedDatum::Nad83), 0);
    EXPECT_EQ(utmEpsg(22, false, NamedDatum::Nad27), 26722);
    EXPECT_EQ(utmEpsg(23, false, NamedDatum::Nad27), 0);
    EXPECT_EQ(utmEpsg(10, false, NamedDatum::Other), 0);
}

} // namespace
} // namespace pyramid
