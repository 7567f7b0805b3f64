// Small GeoTIFFs for tests, written with libtiff and libgeotiff (no GDAL): float32 or int16
// heights or 8-bit RGB(A), with the GeoKeys and placement tags a test chooses.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pyramid::test {

struct GeoTiffTags {
    std::vector<std::pair<int, int>> shortKeys;          // (GeoKey, value): GTModelTypeGeoKey, ProjectedCSTypeGeoKey...
    std::vector<std::pair<int, double>> doubleKeys;      // (GeoKey, value): projection parameters
    std::vector<std::pair<int, std::string>> asciiKeys;  // (GeoKey, text): citations
    std::vector<double> tiepoints;                       // ModelTiepoint: I, J, K, X, Y, Z (several for GCPs)
    std::vector<double> pixelScale;                      // ModelPixelScale: sx, sy, sz
    std::vector<double> transformation;                  // ModelTransformation: 16 values, row by row
    std::string gdalNodata;                              // GDAL_NODATA (tag 42113) text, if not empty
    std::string gdalMetadata;                            // GDAL_METADATA (tag 42112) XML, if not empty
    int tileSize = 0;                                    // square tiles of this side (a multiple of 16); 0: strips
};

// A geographic CRS by EPSG code, north-up, pixel (0, 0)'s top-left corner at (west, north),
// pixels of `step` degrees (PixelIsArea), or with `pixelIsPoint` the tiepoint on its centre.
GeoTiffTags geographicTags(int epsg, double west, double north, double step, bool pixelIsPoint = false);
// A projected CRS by EPSG code, north-up, top-left corner at (x0, y0), pixels of `step` CRS units.
GeoTiffTags projectedTags(int epsg, double x0, double y0, double step);

// A projected CRS defined by its keys alone: ProjectedCSTypeGeoKey and ProjectionGeoKey
// user-defined (32767), ProjCoordTransGeoKey `coordTrans` (CT_TransverseMercator...) with its
// parameters (GeoKey, value: angles in the geographic CRS's angular unit, lengths in metres),
// ProjLinearUnitsGeoKey metre, over the geographic CRS `geographicType` (an EPSG code, or 32767
// with the caller's datum keys). No tiepoint or pixel scale: the caller places the grid.
GeoTiffTags userProjectedTags(int geographicType, int coordTrans,
                              const std::vector<std::pair<int, double>>& parameters);
// The ModelTransformation of a pixel-to-CRS transform t (x = t0 + t1 col + t2 row, y = t3 + t4 col
// + t5 row; PixelIsArea), in place of any tiepoint and pixel scale.
void setTransformation(GeoTiffTags& tags, const std::array<double, 6>& t);

// Writes width x height float32 samples (row 0 first), one band.
void writeGeoTiff(const std::string& path, int width, int height, const std::vector<float>& values,
                  const GeoTiffTags& tags);
// Writes width x height int16 samples (row 0 first), one band.
void writeGeoTiffInt16(const std::string& path, int width, int height, const std::vector<int16_t>& values,
                       const GeoTiffTags& tags);
// Writes width x height half-float samples (IEEE binary16 bit patterns), one band: a layout only
// the OpenImageIO module reads.
void writeGeoTiffHalf(const std::string& path, int width, int height, const std::vector<uint16_t>& values,
                      const GeoTiffTags& tags);
// Writes width x height 8-bit RGB samples (interleaved, row 0 first).
void writeGeoTiffRgb(const std::string& path, int width, int height, const std::vector<uint8_t>& values,
                     const GeoTiffTags& tags);
// Writes width x height 8-bit RGBA samples (interleaved, row 0 first): the fourth an extra sample
// of unassociated alpha, or with `alpha` false of unspecified data (a near-infrared band).
void writeGeoTiffRgba(const std::string& path, int width, int height, const std::vector<uint8_t>& values,
                      const GeoTiffTags& tags, bool alpha = true);
// Appends to the TIFF at `path` an internal transparency mask of its first image, as GDAL writes
// one (GDAL_TIFF_INTERNAL_MASK): an image of NewSubfileType 4, Photometric Mask, 1-bit samples
// packed eight a byte, first pixel in the high bit, Deflate; valid[y * width + x] nonzero where
// the pixel has a value. Strips of `rowsPerStrip` rows, or with `tileSize` > 0 square tiles.
void appendTiffMask(const std::string& path, int width, int height, const std::vector<uint8_t>& valid,
                    int rowsPerStrip = 2, int tileSize = 0);

} // namespace pyramid::test
