// What every raster reader reports of its input, and the sample types they read: the
// vocabulary shared by the readers (TIFF, PNG, the image I/O module) and the dispatcher
// (raster_source.hpp) that stands above them.
#pragma once
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "libpyramid/input/georeference.hpp"

namespace pyramid {

enum class SampleType { UInt8, Int8, UInt16, Int16, UInt32, Int32, Float16, Float32, Float64, Other };

// "uint8", "int16", "float32", ...: for reports.
const char* sampleTypeName(SampleType type);

// A part of a raster made of parts of several resolutions (a planar mosaic of a coarse base and
// fine insets: sphere/planar_mosaic.hpp): the box of the raster's pixels [x0, x1) x [y0, y1) its
// samples may reach (its footprint, with the pixel its interpolation reaches beyond), and how
// many of the raster's pixels one of its own samples spans across (1 for the finest; 30 for a
// 30 m part on a 1 m grid).
struct RasterPart {
    int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    double pixelsPerSample = 1.0;
};

// What a channel's stored samples stand for, as the file declares it: value = stored x scale +
// offset (GDAL's band SCALE and OFFSET: input/gdal_band_metadata.hpp). Heights are read as the
// values (RasterSource::readFloat); imagery's colours are read as stored.
struct ValueScaling {
    double scale = 1.0;
    double offset = 0.0;
    bool identity() const { return scale == 1.0 && offset == 0.0; }
    bool operator==(const ValueScaling&) const = default;
};

struct RasterInfo {
    int width = 0;
    int height = 0;
    int channels = 0;
    // The last channel is alpha, as the file declares it: TIFF's ExtraSamples (associated or
    // unassociated alpha; GDAL writes a band of ColorInterp Alpha so, and an unspecified extra
    // sample, a near-infrared band, is not alpha), PNG's alpha or transparency, an image I/O
    // module's alpha channel.
    bool alpha = false;
    // The file carries a transparency mask beside its channels: a TIFF's internal mask
    // (tiff_mask_reader.hpp), which marks the pixels without a value. It is not one of the
    // image's channels: RasterSource's 16-bit reads give it as channel `channels` (0 where
    // masked, 255 elsewhere) to a read that asks for it, and the rule of imagery pixels with a
    // value (colour_coverage.hpp) counts it.
    bool mask = false;
    SampleType type = SampleType::Other;
    std::optional<double> nodata; // declared by the file (GDAL_NODATA, ...), if any; as stored
    // One per channel where the file declares a scale or offset of its values (ValueScaling); empty
    // where every channel's values are as stored.
    std::vector<ValueScaling> scaling;
    std::string formatName;       // "tiff", "png", ...
    std::optional<Georeference> georeference; // a GeoTIFF's CRS and pixel-to-CRS transform, if any
    // Empty: one resolution wherever the raster has samples. Else its parts, the only places it
    // may have samples (a mosaic of several resolutions).
    std::vector<RasterPart> parts;
};

// Whether a sample, read as float32, is the declared nodata: equal to it in float32 (the value
// as the readers deliver it), or NaN when the nodata is NaN.
inline bool isNodata(float v, const std::optional<double>& nodata) {
    return nodata && (v == static_cast<float>(*nodata) || (std::isnan(*nodata) && std::isnan(v)));
}

// Whether two declared nodata values are one: both none, both NaN, or equal.
inline bool sameNodata(const std::optional<double>& a, const std::optional<double>& b) {
    if (a.has_value() != b.has_value()) {
        return false;
    }
    return !a || (*a == *b || (std::isnan(*a) && std::isnan(*b)));
}

// Whether channel `channel`'s heights are read as other values than the file stores: scaled or
// offset (scaling), or converted to the ground's unit (Georeference::heightsToGround), as
// RasterSource::readFloat reads them.
inline bool heightsConverted(const RasterInfo& info, int channel) {
    const auto c = static_cast<size_t>(channel);
    return (c < info.scaling.size() && !info.scaling[c].identity()) ||
           (info.georeference && info.georeference->heightsToGround() != 1.0);
}

} // namespace pyramid
