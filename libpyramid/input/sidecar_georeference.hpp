// What the files beside a raster say of it, where the raster itself does not (a GeoTIFF's own
// tags come first, as the file's):
//   - GDAL's PAM file, FILE.aux.xml, as GDAL writes it beside the PNG or JPEG it makes from a
//     GeoTIFF: <SRS> (WKT) and <GeoTransform> place the raster; a <PAMRasterBand>'s
//     <NoDataValue>, <Scale>, <Offset> and <UnitType> describe its values;
//   - a world file (ESRI's six numbers: pixel size, rotations and the centre of the top-left
//     pixel), FILE.wld or the one FILE's extension names (.tfw or .tifw for .tif, .pgw or .pngw
//     for .png, .jgw or .jpgw for .jpg: the first and last letters of the extension and a "w", or
//     the extension and a "w"), with the CRS of FILE.prj (ESRI or OGC WKT), else the PAM file's.
// The PAM file's transform comes before the world file's, as GDAL takes them.
#pragma once
#include <array>
#include <optional>
#include <string>

#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

// Fills what `info` (the description of the raster at `path`) lacks from its sidecars: its
// georeference (a transform and a CRS of the EPSG database, projected or geographic: without a
// CRS, or with another, the file stays unplaced, as it was without them), nodata value, channels'
// scaling and heights' unit. Throws (fail, naming the sidecar) on one that cannot be read: text
// that is not six numbers, XML that is not well-formed, a singular transform.
void addSidecarDescription(RasterInfo& info, const std::string& path);

// A raster whose own header places its pixels by `transform` (GDAL's order: x0, dx, rx, y0, ry,
// dy) but names no CRS (an ESRI grid): placed in the CRS of FILE.prj (WKT, or ESRI's old keyword
// lines: esri_prj.hpp), else of the PAM file's <SRS>; nothing without one of the EPSG database.
// Throws as addSidecarDescription.
std::optional<Georeference> sidecarCrsPlacement(const std::string& path, const std::array<double, 6>& transform);

// A raster placed by `transform` in the CRS that `wkt` names (WKT, or ESRI's old keyword lines), read
// from `where` (an ENVI header's coordinate system string); nothing as above. Throws naming `where`
// for a singular transform.
std::optional<Georeference> placedInWktCrs(const std::string& wkt, const std::array<double, 6>& transform,
                                           const std::string& where);

// The same in the CRS of EPSG code `epsg` (0: none).
std::optional<Georeference> placedInEpsgCrs(int epsg, const std::array<double, 6>& transform, const std::string& where);

// The EPSG code of a CRS written as WKT (WKT1, WKT2 or ESRI's): the code its root names
// (AUTHORITY["EPSG", N] or ID["EPSG", N]), else the one PROJ identifies it as with a confidence of
// at least 70 %; 0 when there is none.
int epsgOfWkt(const std::string& wkt);

} // namespace pyramid
