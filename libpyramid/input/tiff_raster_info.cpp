#include "libpyramid/input/tiff_raster_info.hpp"

#include <tiffio.h>

#include <cstring>

#include "libpyramid/input/nodata_text.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"

namespace pyramid {

std::optional<RasterInfo> readPlainTiffInfo(const std::string& path) {
    TIFF* tif = openTiffQuietly(path, "r");
    if (!tif) {
        return std::nullopt;
    }
    uint32_t width = 0, height = 0;
    uint16_t compression = 0, bits = 0, format = 0, channels = 0, planar = 0, photometric = 0;
    const bool sized = TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &width) == 1 &&
                       TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &height) == 1 &&
                       TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &photometric) == 1;
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &compression);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &format);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &channels);
    TIFFGetFieldDefaulted(tif, TIFFTAG_PLANARCONFIG, &planar);
    TIFFClose(tif);

    const bool photometricOk = photometric == PHOTOMETRIC_MINISBLACK || (photometric == PHOTOMETRIC_RGB && channels >= 3);
    const bool layoutOk = planar == PLANARCONFIG_CONTIG || channels == 1;
    SampleType type = SampleType::Other;
    if (format == SAMPLEFORMAT_UINT || format == SAMPLEFORMAT_INT) {
        const bool s = format == SAMPLEFORMAT_INT;
        type = bits == 8    ? (s ? SampleType::Int8 : SampleType::UInt8)
               : bits == 16 ? (s ? SampleType::Int16 : SampleType::UInt16)
               : bits == 32 ? (s ? SampleType::Int32 : SampleType::UInt32)
                            : SampleType::Other;
    } else if (format == SAMPLEFORMAT_IEEEFP) {
        type = bits == 32 ? SampleType::Float32 : bits == 64 ? SampleType::Float64 : SampleType::Other;
    }
    if (!sized || width < 1 || height < 1 || width > 0x7fffffffu || height > 0x7fffffffu || channels < 1 ||
        !photometricOk || !layoutOk || type == SampleType::Other || !TIFFIsCODECConfigured(compression)) {
        return std::nullopt;
    }
    RasterInfo info;
    info.width = static_cast<int>(width);
    info.height = static_cast<int>(height);
    info.channels = channels;
    info.type = type;
    info.formatName = "tiff";
    info.nodata = geoTiffNodata(path);
    info.georeference = readGeoTiffGeoreference(path);
    return info;
}

// GDAL keeps a GeoTIFF's nodata value in its own ASCII tag (42113), which OpenImageIO does not
// expose: read it with libtiff. Its warnings (GeoTIFF tags it does not know) are not shown.
std::optional<double> geoTiffNodata(const std::string& path) {
    TIFF* tif = openTiffQuietly(path, "r");
    if (!tif) {
        return std::nullopt;
    }
    // libtiff builds without the tag's definition keep it as an anonymous field, read with a
    // count before the pointer.
    std::optional<double> nodata;
    const TIFFField* field = TIFFFindField(tif, TIFFTAG_GDAL_NODATA, TIFF_ANY);
    const char* text = nullptr;
    if (field && TIFFFieldDataType(field) == TIFF_ASCII) {
        int found = 0;
        size_t length = 0;
        if (!TIFFFieldPassCount(field)) {
            found = TIFFGetField(tif, TIFFTAG_GDAL_NODATA, &text);
            length = text ? std::strlen(text) : 0;
        } else if (TIFFFieldReadCount(field) == TIFF_VARIABLE2) {
            uint32_t count = 0;
            found = TIFFGetField(tif, TIFFTAG_GDAL_NODATA, &count, &text);
            length = count;
        } else {
            uint16_t count = 0;
            found = TIFFGetField(tif, TIFFTAG_GDAL_NODATA, &count, &text);
            length = count;
        }
        if (found == 1 && text) {
            nodata = parseNodataText(std::string(text, strnlen(text, length)));
        }
    }
    TIFFClose(tif);
    return nodata;
}

} // namespace pyramid
