// What GDAL's metadata tag (TIFF tag 42112, GDAL_METADATA, an XML text) says of a GeoTIFF's
// bands: the scale and offset of their values (an <Item role="scale"> and <Item role="offset">
// per band, as `gdal_translate -a_scale -a_offset` writes them and as GDAL carries them over from
// netCDF or HDF sources: a band's value is its stored sample x scale + offset, so a DEM of int16
// half metres declares a scale of 0.5) and their unit (<Item role="unittype">: "m", "ft", "US
// survey foot"), which GDAL writes where it has no vertical GeoKey for it.
//
// GDAL reads an item as a band's when it has a role and a sample (the band's number from 0);
// items of the dataset and of other roles are not read here.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "libpyramid/input/georeference.hpp"
#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

struct GdalBandMetadata {
    std::vector<ValueScaling> scaling; // one per band when any band declares a scale or offset, else empty
    std::string unitType;              // band 1's UNITTYPE (else the first band's that has one); "" without
};

// A band's scale, offset and unit as text, each "" where the band has none (GDAL's metadata tag,
// or a PAM file's <PAMRasterBand>: sidecar_georeference.hpp).
struct BandValueTexts {
    std::string scale, offset, unit;
};

// The band metadata of those texts (band 1 first). Throws (fail, naming `path` and `source`, the
// part of it they come from) on a scale that is not a finite non-zero number or an offset that is
// not finite: values read with a scale that cannot be known would be wrong heights.
GdalBandMetadata bandMetadataOf(const std::vector<BandValueTexts>& bands, const std::string& path,
                                const std::string& source);

// The band metadata of the tag's text, for a raster of `bands` bands (items of other bands are
// ignored, as GDAL ignores them). Throws (fail, naming `path`) on XML that is not well-formed, a
// scale that is not a finite non-zero number or an offset that is not finite: values read with a
// scale that cannot be known would be wrong heights.
GdalBandMetadata parseGdalMetadata(std::string_view xml, int bands, const std::string& path);

// The band metadata of an open TIFF's current directory (libtiff's TIFF*); none without the tag.
GdalBandMetadata readGdalBandMetadata(void* tif, int bands, const std::string& path);

// The unit of heights that a UNITTYPE names: the metre and its multiples (m, km, dm, cm, mm), the
// foot (ft) and the US survey foot (ftUS), by GDAL's and PROJ's spellings; any other text gives a
// unit without a name of 0 metres (unknown: heights read as stored), its source quoting the text.
HeightUnit heightUnitOfUnitType(const std::string& text);

} // namespace pyramid
