// The EPSG codes of the few CRSs that raster headers name by their datum alone (ESRI's old
// `.prj` lines, ENVI's map info, ERDAS Imagine's projection parameters): geographic WGS 84, NAD83
// and NAD27, and their UTM zones where the EPSG database has them (NAD83's zones 1 to 23 north,
// NAD27's 1 to 22 north, WGS 84's 1 to 60 north and south).
#pragma once

namespace pyramid {

enum class NamedDatum { Wgs84, Nad83, Nad27, Other };

// `name` with case, spaces, hyphens and underscores ignored: WGS84 ("WGS 84", "wgs-84"), NAD83
// ("North America 1983", "North American 1983"), NAD27 (the same with 1927); Other for another.
NamedDatum namedDatum(const char* name);

// 4326, 4269 or 4267; 0 for Other.
int geographicEpsg(NamedDatum datum);

// The UTM zone's code (1 to 60, north or south); 0 where the database has none.
int utmEpsg(int zone, bool south, NamedDatum datum);

} // namespace pyramid
