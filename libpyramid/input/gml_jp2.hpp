// GMLJP2 (OGC 05-047): the GML document a JPEG 2000 file carries in an `asoc` box labelled
// "gml.root-instance" (jpeg2000_boxes.hpp), whose RectifiedGrid places the image: the origin
// (the centre of the first pixel) and two offset vectors (one column, one row) in the CRS its
// srsName names. Sentinel-2's granules, and GDAL's JP2 files beside their GeoJP2 box, carry one.
// A CRS named as a URN or URL (`urn:ogc:def:crs:EPSG::32633`, `http://www.opengis.net/def/crs/
// EPSG/0/4326`) gives its coordinates in the EPSG database's axis order: latitude first for
// EPSG:4326, so those are swapped (PROJ says which CRSs put north first); `EPSG:32633` gives x
// first.
#pragma once
#include <optional>
#include <string>

#include "libpyramid/input/georeference.hpp"

namespace pyramid {

// The placement `gml` gives; nothing when it holds no RectifiedGrid or its CRS is no EPSG code
// (as any file without a CRS). Throws Error naming `path` for XML that is not well-formed, or a
// RectifiedGrid without an origin and two offset vectors of two numbers each.
std::optional<Georeference> gmlJp2Placement(const std::string& gml, const std::string& path);

} // namespace pyramid
