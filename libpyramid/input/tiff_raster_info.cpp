#include "libpyramid/input/tiff_raster_info.hpp"

#include <tiffio.h>

#include <cstring>

#include "libpyramid/input/gdal_band_metadata.hpp"
#include "libpyramid/input/nodata_text.hpp"
#include "libpyramid/input/tiff_mask_reader.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"

namespace pyramid {

std::optional<RasterInfo> readPlainTiffInfo(const std::string& path) {
    TIFF* tif = openTiffQuietly(path, "rm");
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
    // The last channel is alpha when its extra sample says so (associated or unassociated).
    uint16_t extras = 0;
    uint16_t* extraTypes = nullptr;
    const bool alpha = TIFFGetField(tif, TIFFTAG_EXTRASAMPLES, &extras, &extraTypes) == 1 && extras > 0 && extraTypes &&
                       (extraTypes[extras - 1] == EXTRASAMPLE_ASSOCALPHA || extraTypes[extras - 1] == EXTRASAMPLE_UNASSALPHA);
    // GDAL's band metadata, read while the first directory is current; used only for an image
    // this reader describes (decided below), but a tag that cannot be read is refused either way.
    GdalBandMetadata metadata;
    if (sized && channels >= 1) {
        try {
            metadata = readGdalBandMetadata(tif, channels, path);
        } catch (...) {
            TIFFClose(tif);
            throw;
        }
    }
    bool mask = false;
    for (int d = 1; d < kMaskDirectoriesSearched && !mask && sized && TIFFReadDirectory(tif) == 1; ++d) {
        mask = isTiffMaskOf(tif, width, height);
    }
    TIFFClose(tif);

    // YCbCr only as JPEG stores it, which libjpeg decodes to RGB; 8-bit palette indices, widened
    // to RGB; bands in separate planes, but not as JPEG (tiff_block_reader.hpp).
    const bool palette = photometric == PHOTOMETRIC_PALETTE && channels == 1 && bits == 8 &&
                         format == SAMPLEFORMAT_UINT && compression != COMPRESSION_JPEG;
    const bool photometricOk = photometric == PHOTOMETRIC_MINISBLACK || (photometric == PHOTOMETRIC_RGB && channels >= 3) ||
                               (photometric == PHOTOMETRIC_YCBCR && compression == COMPRESSION_JPEG && channels == 3 &&
                                bits == 8 && format == SAMPLEFORMAT_UINT) ||
                               palette;
    const bool layoutOk = planar == PLANARCONFIG_CONTIG || channels == 1 ||
                          (planar == PLANARCONFIG_SEPARATE && compression != COMPRESSION_JPEG);
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
    info.channels = palette ? 3 : channels;
    info.alpha = alpha;
    info.mask = mask;
    info.type = type;
    info.formatName = "tiff";
    info.nodata = geoTiffNodata(path);
    info.scaling = palette ? std::vector<ValueScaling>{} : std::move(metadata.scaling);
    info.georeference = readGeoTiffGeoreference(path);
    addUnitType(info, metadata.unitType);
    return info;
}

namespace {

// A tag's values and their count, whichever count type the field was registered with.
template <class T>
std::vector<T> arrayTag(TIFF* tif, uint32_t tag) {
    const TIFFField* field = TIFFFindField(tif, tag, TIFF_ANY);
    if (!field || !TIFFFieldPassCount(field)) {
        return {};
    }
    T* values = nullptr;
    uint32_t count = 0;
    int found = 0;
    if (TIFFFieldReadCount(field) == TIFF_VARIABLE2) {
        found = TIFFGetField(tif, tag, &count, &values);
    } else {
        uint16_t count16 = 0;
        found = TIFFGetField(tif, tag, &count16, &values);
        count = count16;
    }
    return found == 1 && values ? std::vector<T>(values, values + count) : std::vector<T>{};
}

} // namespace

std::vector<double> tiffDoubles(void* tif, uint32_t tag) {
    const TIFFField* field = TIFFFindField(static_cast<TIFF*>(tif), tag, TIFF_ANY);
    return field && TIFFFieldDataType(field) == TIFF_DOUBLE ? arrayTag<double>(static_cast<TIFF*>(tif), tag)
                                                            : std::vector<double>{};
}

std::vector<uint16_t> tiffShorts(void* tif, uint32_t tag) {
    const TIFFField* field = TIFFFindField(static_cast<TIFF*>(tif), tag, TIFF_ANY);
    return field && TIFFFieldDataType(field) == TIFF_SHORT ? arrayTag<uint16_t>(static_cast<TIFF*>(tif), tag)
                                                           : std::vector<uint16_t>{};
}

std::optional<std::string> tiffText(void* handle, uint32_t tag) {
    TIFF* tif = static_cast<TIFF*>(handle);
    const TIFFField* field = TIFFFindField(tif, tag, TIFF_ANY);
    if (!field || TIFFFieldDataType(field) != TIFF_ASCII) {
        return std::nullopt;
    }
    if (TIFFFieldPassCount(field)) {
        const std::vector<char> text = arrayTag<char>(tif, tag);
        return text.empty() ? std::nullopt : std::optional<std::string>(std::string(text.data(), strnlen(text.data(), text.size())));
    }
    const char* text = nullptr;
    return TIFFGetField(tif, tag, &text) == 1 && text ? std::optional<std::string>(text) : std::nullopt;
}

void addUnitType(RasterInfo& info, const std::string& unitType) {
    if (info.georeference && !info.georeference->heightUnit && !unitType.empty()) {
        info.georeference->heightUnit = heightUnitOfUnitType(unitType);
    }
}

void addGdalBandMetadata(RasterInfo& info, const std::string& path) {
    TIFF* tif = openTiffQuietly(path, "rm");
    if (!tif) {
        return;
    }
    GdalBandMetadata metadata;
    try {
        metadata = readGdalBandMetadata(tif, info.channels, path);
    } catch (...) {
        TIFFClose(tif);
        throw;
    }
    TIFFClose(tif);
    info.scaling = std::move(metadata.scaling);
    addUnitType(info, metadata.unitType);
}

// GDAL keeps a GeoTIFF's nodata value in its own ASCII tag (42113), which OpenImageIO does not
// expose: read it with libtiff. Its warnings (GeoTIFF tags it does not know) are not shown.
std::optional<double> geoTiffNodata(const std::string& path) {
    TIFF* tif = openTiffQuietly(path, "rm");
    if (!tif) {
        return std::nullopt;
    }
    // libtiff builds without the tag's definition keep it as an anonymous field.
    const std::optional<std::string> text = tiffText(tif, TIFFTAG_GDAL_NODATA);
    TIFFClose(tif);
    return text ? std::optional<double>(parseDeclaredNodata(*text, path, "GDAL_NODATA")) : std::nullopt;
}

} // namespace pyramid
