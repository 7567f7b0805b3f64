// The unit a GeoTIFF's heights are stored in, as its vertical GeoKeys say, and what reading them
// in the unit of the ground takes. GDAL writes a compound CRS (EPSG:26910+6360, a DEM of NAVD88
// heights in US survey feet) as VerticalCSTypeGeoKey alone, without VerticalUnitsGeoKey: the unit
// is the vertical CRS's axis unit in the EPSG database, which PROJ gives (libgeotiff has no call
// for it). VerticalUnitsGeoKey, where a file has it, says the unit outright and comes first.
//
// The ground's unit for heights: the projected CRS's linear unit (a State Plane CRS in US survey
// feet keeps heights in US survey feet), and metres for a geographic CRS (and so for a planet).
#pragma once
#include <optional>

#include "libpyramid/input/georeference.hpp"

typedef struct gtiff GTIF;

namespace pyramid {

struct GeoTiffLibrary;

// The heights' unit by the GeoKeys, if they name one (a user-defined vertical CRS without a unit
// names none). A code the EPSG database does not hold as a vertical CRS or a unit of length
// gives a unit of 0 metres, its source saying so. Never throws.
std::optional<HeightUnit> readHeightUnit(const GeoTiffLibrary& lib, GTIF* gtif);

} // namespace pyramid
