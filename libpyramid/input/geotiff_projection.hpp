// What a GeoTIFF's keys say of its projection and its angles, for georeference.hpp: the
// projection's method and parameters as libgeotiff normalises them (GTIFDefn), and the size of
// the geographic CRS's angular unit, which libgeotiff leaves unread for a user-defined unit.
#pragma once
#include <string>

#include "libpyramid/input/geotiff_library.hpp"
#include "libpyramid/input/georeference.hpp"

namespace pyramid {

// The projection of `d`; its angular parameters are multiplied by `angleDegrees` (the degrees of
// the unit they are in). `byKeys`: the method is the file's ProjCoordTransGeoKey.
Projection projectionOf(const GTIFDefn& d, int pcs, bool byKeys, double angleDegrees);

// The degrees of the geographic CRS's angular unit (of its coordinates, its prime meridian's
// user-defined longitude and the projection parameters its keys give), or why there is none.
// libgeotiff knows the EPSG units, leaves a user-defined one at a degree (its size,
// GeogAngularUnitSizeGeoKey in radians, is read here), and takes a sexagesimal notation or an
// unknown code for a degree too.
double angularUnit(const GeoTiffLibrary& lib, GTIF* gtif, const GTIFDefn& d, std::string& why);

} // namespace pyramid
