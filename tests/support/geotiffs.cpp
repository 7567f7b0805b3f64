#include <algorithm>
#include "tests/support/geotiffs.hpp"

#include <geotiff/geotiff.h>
#include <geotiff/geovalues.h>
#include <geotiff/xtiffio.h>
#include <tiffio.h>

#include <stdexcept>

namespace pyramid::test {

GeoTiffTags geographicTags(int epsg, double west, double north, double step, bool pixelIsPoint) {
    GeoTiffTags t;
    t.shortKeys = {{GTModelTypeGeoKey, ModelTypeGeographic},
                   {GTRasterTypeGeoKey, pixelIsPoint ? RasterPixelIsPoint : RasterPixelIsArea},
                   {GeographicTypeGeoKey, epsg}};
    t.tiepoints = {0.0, 0.0, 0.0, west + (pixelIsPoint ? step / 2 : 0.0), north - (pixelIsPoint ? step / 2 : 0.0), 0.0};
    t.pixelScale = {step, step, 0.0};
    return t;
}

GeoTiffTags projectedTags(int epsg, double x0, double y0, double step) {
    GeoTiffTags t;
    t.shortKeys = {{GTModelTypeGeoKey, ModelTypeProjected},
                   {GTRasterTypeGeoKey, RasterPixelIsArea},
                   {ProjectedCSTypeGeoKey, epsg}};
    t.tiepoints = {0.0, 0.0, 0.0, x0, y0, 0.0};
    t.pixelScale = {step, step, 0.0};
    return t;
}

GeoTiffTags userProjectedTags(int geographicType, int coordTrans,
                              const std::vector<std::pair<int, double>>& parameters) {
    GeoTiffTags t;
    t.shortKeys = {{GTModelTypeGeoKey, ModelTypeProjected},   {GTRasterTypeGeoKey, RasterPixelIsArea},
                   {ProjectedCSTypeGeoKey, KvUserDefined},   {ProjectionGeoKey, KvUserDefined},
                   {ProjCoordTransGeoKey, coordTrans},       {ProjLinearUnitsGeoKey, Linear_Meter},
                   {GeographicTypeGeoKey, geographicType}};
    t.doubleKeys = parameters;
    return t;
}

void setTransformation(GeoTiffTags& tags, const std::array<double, 6>& t) {
    tags.tiepoints.clear();
    tags.pixelScale.clear();
    tags.transformation = {t[1], t[2], 0.0, t[0], t[4], t[5], 0.0, t[3], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
}

namespace {

// One of GDAL's ASCII tags (GDAL_NODATA, GDAL_METADATA), unless `text` is empty; libtiff builds
// without the tag's definition learn it here, as GDAL declares it.
void setGdalText(TIFF* tif, uint32_t tag, const char* name, const std::string& text) {
    if (text.empty()) {
        return;
    }
    if (!TIFFFindField(tif, tag, TIFF_ANY)) {
        const TIFFFieldInfo info = {tag, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0, const_cast<char*>(name)};
        TIFFMergeFieldInfo(tif, &info, 1);
    }
    TIFFSetField(tif, tag, text.c_str());
}

void write(const std::string& path, int width, int height, int channels, int bits, int format, const void* values,
           const GeoTiffTags& tags, uint16_t extraSample = EXTRASAMPLE_UNASSALPHA) {
    TIFF* tif = XTIFFOpen(path.c_str(), "w");
    if (!tif) {
        throw std::runtime_error("cannot write " + path);
    }
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(width));
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(height));
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, static_cast<uint16_t>(channels));
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, static_cast<uint16_t>(bits));
    TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, static_cast<uint16_t>(format));
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, channels >= 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
    if (channels == 2 || channels == 4) {
        TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, uint16_t{1}, &extraSample);
    }
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    if (tags.tileSize > 0) {
        TIFFSetField(tif, TIFFTAG_TILEWIDTH, static_cast<uint32_t>(tags.tileSize));
        TIFFSetField(tif, TIFFTAG_TILELENGTH, static_cast<uint32_t>(tags.tileSize));
    } else {
        TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, 16u);
    }
    setGdalText(tif, TIFFTAG_GDAL_NODATA, "GDALNoDataValue", tags.gdalNodata);
    setGdalText(tif, TIFFTAG_GDAL_METADATA, "GDALMetadata", tags.gdalMetadata);
    if (!tags.tiepoints.empty()) {
        TIFFSetField(tif, TIFFTAG_GEOTIEPOINTS, static_cast<uint16_t>(tags.tiepoints.size()), tags.tiepoints.data());
    }
    if (!tags.pixelScale.empty()) {
        TIFFSetField(tif, TIFFTAG_GEOPIXELSCALE, static_cast<uint16_t>(tags.pixelScale.size()), tags.pixelScale.data());
    }
    if (!tags.transformation.empty()) {
        TIFFSetField(tif, TIFFTAG_GEOTRANSMATRIX, static_cast<uint16_t>(tags.transformation.size()),
                     tags.transformation.data());
    }
    GTIF* gtif = GTIFNew(tif);
    for (const auto& [key, value] : tags.shortKeys) {
        GTIFKeySet(gtif, static_cast<geokey_t>(key), TYPE_SHORT, 1, value);
    }
    for (const auto& [key, value] : tags.doubleKeys) {
        GTIFKeySet(gtif, static_cast<geokey_t>(key), TYPE_DOUBLE, 1, value);
    }
    for (const auto& [key, text] : tags.asciiKeys) {
        GTIFKeySet(gtif, static_cast<geokey_t>(key), TYPE_ASCII, 0, text.c_str());
    }
    GTIFWriteKeys(gtif);
    GTIFFree(gtif);
    const size_t pixelBytes = static_cast<size_t>(channels * bits / 8);
    const size_t rowBytes = static_cast<size_t>(width) * pixelBytes;
    if (tags.tileSize > 0) {
        const auto T = static_cast<size_t>(tags.tileSize);
        std::vector<uint8_t> tile(T * T * pixelBytes);
        for (size_t y0 = 0; y0 < static_cast<size_t>(height); y0 += T) {
            for (size_t x0 = 0; x0 < static_cast<size_t>(width); x0 += T) {
                std::fill(tile.begin(), tile.end(), uint8_t{0});
                for (size_t y = y0; y < std::min(y0 + T, static_cast<size_t>(height)); ++y) {
                    const size_t n = std::min(T, static_cast<size_t>(width) - x0) * pixelBytes;
                    std::copy_n(static_cast<const uint8_t*>(values) + y * rowBytes + x0 * pixelBytes, n,
                                &tile[(y - y0) * T * pixelBytes]);
                }
                if (TIFFWriteTile(tif, tile.data(), static_cast<uint32_t>(x0), static_cast<uint32_t>(y0), 0, 0) < 0) {
                    XTIFFClose(tif);
                    throw std::runtime_error("cannot write " + path);
                }
            }
        }
        XTIFFClose(tif);
        return;
    }
    for (int j = 0; j < height; ++j) {
        const auto* row = static_cast<const uint8_t*>(values) + rowBytes * static_cast<size_t>(j);
        if (TIFFWriteScanline(tif, const_cast<uint8_t*>(row), static_cast<uint32_t>(j), 0) != 1) {
            XTIFFClose(tif);
            throw std::runtime_error("cannot write " + path);
        }
    }
    XTIFFClose(tif);
}

} // namespace

void writeGeoTiff(const std::string& path, int width, int height, const std::vector<float>& values,
                  const GeoTiffTags& tags) {
    write(path, width, height, 1, 32, SAMPLEFORMAT_IEEEFP, values.data(), tags);
}

void writeGeoTiffInt16(const std::string& path, int width, int height, const std::vector<int16_t>& values,
                       const GeoTiffTags& tags) {
    write(path, width, height, 1, 16, SAMPLEFORMAT_INT, values.data(), tags);
}

void writeGeoTiffHalf(const std::string& path, int width, int height, const std::vector<uint16_t>& values,
                      const GeoTiffTags& tags) {
    write(path, width, height, 1, 16, SAMPLEFORMAT_IEEEFP, values.data(), tags);
}

void writeGeoTiffRgb(const std::string& path, int width, int height, const std::vector<uint8_t>& values,
                     const GeoTiffTags& tags) {
    write(path, width, height, 3, 8, SAMPLEFORMAT_UINT, values.data(), tags);
}

void writeGeoTiffRgba(const std::string& path, int width, int height, const std::vector<uint8_t>& values,
                      const GeoTiffTags& tags, bool alpha) {
    write(path, width, height, 4, 8, SAMPLEFORMAT_UINT, values.data(), tags,
          alpha ? EXTRASAMPLE_UNASSALPHA : EXTRASAMPLE_UNSPECIFIED);
}

void appendTiffMask(const std::string& path, int width, int height, const std::vector<uint8_t>& valid,
                    int rowsPerStrip, int tileSize) {
    TIFF* tif = TIFFOpen(path.c_str(), "a");
    if (!tif) {
        throw std::runtime_error("cannot append to " + path);
    }
    TIFFSetField(tif, TIFFTAG_SUBFILETYPE, FILETYPE_MASK);
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(width));
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(height));
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 1);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MASK);
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
    const int blockWidth = tileSize > 0 ? tileSize : width;
    const int blockHeight = tileSize > 0 ? tileSize : rowsPerStrip;
    if (tileSize > 0) {
        TIFFSetField(tif, TIFFTAG_TILEWIDTH, static_cast<uint32_t>(tileSize));
        TIFFSetField(tif, TIFFTAG_TILELENGTH, static_cast<uint32_t>(tileSize));
    } else {
        TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, static_cast<uint32_t>(rowsPerStrip));
    }
    const size_t rowBytes = (static_cast<size_t>(blockWidth) + 7) / 8;
    uint32_t index = 0;
    for (int y0 = 0; y0 < height; y0 += blockHeight) {
        for (int x0 = 0; x0 < width; x0 += blockWidth, ++index) {
            const int rows = tileSize > 0 ? blockHeight : std::min(blockHeight, height - y0);
            std::vector<uint8_t> block(rowBytes * static_cast<size_t>(rows), 0);
            for (int y = y0; y < std::min(y0 + rows, height); ++y) {
                for (int x = x0; x < std::min(x0 + blockWidth, width); ++x) {
                    if (valid[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)]) {
                        block[static_cast<size_t>(y - y0) * rowBytes + static_cast<size_t>(x - x0) / 8] |=
                            static_cast<uint8_t>(0x80u >> ((x - x0) % 8));
                    }
                }
            }
            const tmsize_t written =
                tileSize > 0 ? TIFFWriteEncodedTile(tif, index, block.data(), static_cast<tmsize_t>(block.size()))
                             : TIFFWriteEncodedStrip(tif, index, block.data(), static_cast<tmsize_t>(block.size()));
            if (written < 0) {
                TIFFClose(tif);
                throw std::runtime_error("cannot write the mask of " + path);
            }
        }
    }
    TIFFClose(tif);
}

} // namespace pyramid::test
