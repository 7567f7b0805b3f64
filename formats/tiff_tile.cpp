#include "formats/tiff_tile.hpp"

#include <tiffio.h>

#include <algorithm>
#include <cstring>
#include <functional>

#include "formats/error.hpp"
#include "formats/jpeg_markers.hpp"
#include "formats/tiff_memory.hpp"
#include "formats/tiff_plain_writer.hpp"
#include "formats/tiff_strip_bytes.hpp"
#include "formats/zlib_strip.hpp"

namespace pyramid {

namespace {

uint16_t compressionCode(TiffCompression c) {
    switch (c) {
    case TiffCompression::None:
        return COMPRESSION_NONE;
    case TiffCompression::Deflate:
        return COMPRESSION_ADOBE_DEFLATE;
    case TiffCompression::Lzw:
        return COMPRESSION_LZW;
    case TiffCompression::Jpeg:
    case TiffCompression::JpegYCbCr:
        return COMPRESSION_JPEG;
    }
    return COMPRESSION_NONE;
}

// Encodes an image tile's one strip of `bits`-bit samples. Deflate strips (with or without the
// predictor) are compressed here, with a compressor kept per thread, and may go to the faster
// coders of deflateStrip; their TIFF is written without libtiff (writePlainTiff), which would
// set up its field table and a compressor for every tile. Other codecs go through libtiff.
std::vector<uint8_t> encodeStrip(const void* pixels, size_t bytes, int width, int height, int channels, int bits,
                                 uint16_t photometric, bool extraSample, TiffCompression compression,
                                 int jpegQuality, int deflateLevel, bool horizontalPredictor) {
    const bool jpeg = isJpeg(compression);
    if (jpeg && (jpegQuality < 1 || jpegQuality > 100)) {
        fail("", "JPEG quality " + std::to_string(jpegQuality) + " is not 1..100");
    }
    if (jpeg && (bits != 8 || (channels != 1 && channels != 3))) {
        fail("", "JPEG tiles need 1 or 3 channels of 8 bits, not " + std::to_string(channels) + " x " +
                     std::to_string(bits) + " bits");
    }
    if (compression == TiffCompression::Deflate) {
        std::span<const uint8_t> samples(static_cast<const uint8_t*>(pixels), bytes);
        if (horizontalPredictor) {
            samples = horizontalDifferences(samples.data(), bytes, width, channels);
        }
        const PlainTiffShape shape{width, height, channels, bits, photometric, extraSample, horizontalPredictor};
        return writePlainTiff(deflateStrip(samples, deflateLevel, channels), shape);
    }
    std::vector<uint8_t> out;
    out.reserve(bytes / 2 + 256);
    MemoryStream stream;
    stream.out = &out;
    TiffHandle tif(stream, "w", 0);
    if (!tif.get()) {
        fail("", withCause("cannot create an in-memory TIFF", stream));
    }
    TIFF* t = tif.get();
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(width));
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(height));
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, static_cast<uint16_t>(bits));
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, static_cast<uint16_t>(channels));
    TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, photometric);
    TIFFSetField(t, TIFFTAG_ORIENTATION, ORIENTATION_BOTLEFT);
    TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, static_cast<uint32_t>(height));
    TIFFSetField(t, TIFFTAG_COMPRESSION, compressionCode(compression));
    if (extraSample) {
        // The channel beyond grey or RGB is unspecified data (coverage, alpha...).
        const uint16_t extra = EXTRASAMPLE_UNSPECIFIED;
        TIFFSetField(t, TIFFTAG_EXTRASAMPLES, 1, &extra);
    }
    if (jpeg) {
        TIFFSetField(t, TIFFTAG_JPEGQUALITY, jpegQuality);
    }
    if (photometric == PHOTOMETRIC_YCBCR) {
        // The pixels given are RGB; libjpeg converts them and subsamples the chroma 2 x 2.
        TIFFSetField(t, TIFFTAG_YCBCRSUBSAMPLING, uint16_t{2}, uint16_t{2});
        TIFFSetField(t, TIFFTAG_JPEGCOLORMODE, JPEGCOLORMODE_RGB);
    }
    const tmsize_t written = TIFFWriteEncodedStrip(t, 0, const_cast<void*>(pixels), static_cast<tmsize_t>(bytes));
    if (written < 0) {
        fail("", withCause("cannot encode a TIFF tile", stream));
    }
    if (!TIFFWriteDirectory(t)) {
        fail("", withCause("cannot finish a TIFF tile", stream));
    }
    tif.close();
    return out;
}

} // namespace


std::vector<uint8_t> encodeTiff8(std::span<const uint8_t> pixels, int width, int height, int channels,
                                 TiffCompression compression, int jpegQuality, int deflateLevel,
                                 bool horizontalPredictor) {
    if (channels < 1 || channels > 4 || width < 1 || height < 1 ||
        pixels.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(channels)) {
        fail("", "TIFF tile: pixel buffer does not match " + std::to_string(width) + "x" + std::to_string(height) +
                     "x" + std::to_string(channels));
    }
    const uint16_t photometric = compression == TiffCompression::JpegYCbCr && channels == 3 ? PHOTOMETRIC_YCBCR
                                 : channels >= 3                                           ? PHOTOMETRIC_RGB
                                                                                           : PHOTOMETRIC_MINISBLACK;
    return encodeStrip(pixels.data(), pixels.size(), width, height, channels, 8, photometric,
                       channels == 2 || channels == 4, compression, jpegQuality, deflateLevel, horizontalPredictor);
}

namespace {

// The largest ratio of decoded to stored bytes a codec can reach, with margin: Deflate stops
// at 1032:1, LZW (codes of 9 bits or more, strings of at most 4096 bytes) near 3641:1,
// PackBits at 64:1, baseline or progressive JPEG (one Huffman bit at least per 8x8 block
// and component, 4:2:0 subsampled) near 512:1.
uint64_t maxExpansion(uint16_t compression) {
    switch (compression) {
    case COMPRESSION_NONE:
        return 1;
    case COMPRESSION_PACKBITS:
        return 64;
    default:
        return 4096;
    }
}

// Checks an image's layout (size, samples) from its header fields, before any pixel is
// allocated or decoded: a few hostile bytes must not cost more memory than the expected tile.
using LayoutCheck = std::function<void(const TiffImage& header)>;

TiffImage decodeChecked(std::span<const uint8_t> blob, int maxWidth, int maxHeight, const std::string& where,
                        const LayoutCheck& checkLayout) {
    if (blob.size() < 8) {
        fail(where, "not a TIFF (" + std::to_string(blob.size()) + " bytes)");
    }
    MemoryStream stream;
    stream.data = blob.data();
    stream.size = blob.size();
    const size_t maxBytes = static_cast<size_t>(maxWidth) * static_cast<size_t>(maxHeight) * 8u;
    // 'm': no memory mapping. libtiff reads the directory only; strips are read on demand,
    // after the dimensions and the layout are checked.
    TiffHandle tif(stream, "rm", static_cast<tmsize_t>(std::max<size_t>(maxBytes, 1u << 20)));
    TIFF* t = tif.get();
    if (!t) {
        fail(where, withCause("not a readable TIFF", stream));
    }
    uint32_t width = 0, height = 0;
    uint16_t bits = 0, channels = 1, planar = PLANARCONFIG_CONTIG, format = SAMPLEFORMAT_UINT, compression = 0;
    TIFFGetField(t, TIFFTAG_IMAGEWIDTH, &width);
    TIFFGetField(t, TIFFTAG_IMAGELENGTH, &height);
    TIFFGetFieldDefaulted(t, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLESPERPIXEL, &channels);
    TIFFGetFieldDefaulted(t, TIFFTAG_PLANARCONFIG, &planar);
    TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLEFORMAT, &format);
    TIFFGetFieldDefaulted(t, TIFFTAG_COMPRESSION, &compression);
    if (width == 0 || height == 0 || width > static_cast<uint32_t>(maxWidth) ||
        height > static_cast<uint32_t>(maxHeight)) {
        fail(where, "TIFF of " + std::to_string(width) + "x" + std::to_string(height) + " pixels, expected at most " +
                        std::to_string(maxWidth) + "x" + std::to_string(maxHeight));
    }
    if (bits != 8 && bits != 16) {
        fail(where, "TIFF with " + std::to_string(bits) + " bits per sample (8 or 16 expected)");
    }
    if (channels < 1 || channels > 4) {
        fail(where, "TIFF with " + std::to_string(channels) + " samples per pixel (1 to 4 expected)");
    }
    if (planar != PLANARCONFIG_CONTIG && channels > 1) {
        fail(where, "TIFF with separate colour planes (contiguous samples expected)");
    }
    if (format != SAMPLEFORMAT_UINT && format != SAMPLEFORMAT_INT) {
        fail(where, "TIFF with floating-point or complex samples (integers expected)");
    }
    if (TIFFIsTiled(t)) {
        fail(where, "tiled TIFF (strips expected)");
    }
    if (compression != COMPRESSION_NONE && compression != COMPRESSION_ADOBE_DEFLATE &&
        compression != COMPRESSION_DEFLATE && compression != COMPRESSION_LZW &&
        compression != COMPRESSION_JPEG && compression != COMPRESSION_PACKBITS) {
        fail(where, "TIFF compression " + std::to_string(compression) + " is not supported");
    }
    if (compression == COMPRESSION_JPEG) {
        // Decode JPEG data as stored (YCbCr converted to RGB by the codec).
        uint16_t photometric = 0;
        TIFFGetFieldDefaulted(t, TIFFTAG_PHOTOMETRIC, &photometric);
        if (photometric == PHOTOMETRIC_YCBCR) {
            TIFFSetField(t, TIFFTAG_JPEGCOLORMODE, JPEGCOLORMODE_RGB);
        }
    }
    TiffImage image;
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    image.channels = channels;
    image.bitsPerSample = bits;
    image.signedSamples = (format == SAMPLEFORMAT_INT);
    if (checkLayout) {
        checkLayout(image);
    }
    const size_t rowBytes = static_cast<size_t>(width) * channels * (bits / 8);
    const uint32_t strips = TIFFNumberOfStrips(t);
    uint32_t rowsPerStrip = height;
    TIFFGetFieldDefaulted(t, TIFFTAG_ROWSPERSTRIP, &rowsPerStrip);
    rowsPerStrip = std::min(std::max<uint32_t>(rowsPerStrip, 1u), height);
    const uint32_t expectedStrips = (height + rowsPerStrip - 1) / rowsPerStrip;
    if (strips != expectedStrips) {
        fail(where, "TIFF strip count " + std::to_string(strips) + " does not match its size");
    }
    // The stored bytes bound what they can decode to: a blob of a few hundred bytes claiming
    // the largest tile is rejected before the pixels are allocated.
    uint64_t storedBytes = 0;
    for (uint32_t s = 0; s < strips; ++s) {
        storedBytes += std::min<uint64_t>(TIFFGetStrileByteCount(t, s), blob.size());
    }
    const uint64_t imageBytes = static_cast<uint64_t>(rowBytes) * height;
    if (storedBytes * maxExpansion(compression) < imageBytes) {
        fail(where, "truncated or corrupt TIFF data (" + std::to_string(storedBytes) + " stored bytes cannot hold " +
                        std::to_string(width) + "x" + std::to_string(height) + " pixels)");
    }
    image.pixels.assign(rowBytes * height, 0);
    // Deflate strips are inflated whole here (zlib_strip.hpp: libtiff never checks the
    // checksum of a stream that runs long), with libtiff's predictor and byte order after.
    const bool deflate = compression == COMPRESSION_ADOBE_DEFLATE || compression == COMPRESSION_DEFLATE;
    uint16_t predictor = PREDICTOR_NONE;
    if (deflate) {
        TIFFGetFieldDefaulted(t, TIFFTAG_PREDICTOR, &predictor); // a tag of the Deflate codec's
    }
    size_t filled = 0;
    for (uint32_t s = 0; s < strips; ++s) {
        // libtiff only warns when StripOffsets has fewer entries than the image has strips,
        // and would then read the missing strips from offset 0 (the TIFF header).
        if (TIFFGetStrileOffset(t, s) == 0) {
            fail(where, "TIFF strip " + std::to_string(s) + " has no data (StripOffsets too short)");
        }
        const uint32_t rows = std::min(rowsPerStrip, height - s * rowsPerStrip);
        const size_t want = rows * rowBytes;
        if (deflate) {
            const uint64_t offset = TIFFGetStrileOffset(t, s), count = TIFFGetStrileByteCount(t, s);
            if (offset <= blob.size() && count <= blob.size() - offset) {
                const std::span<uint8_t> strip(image.pixels.data() + filled, want);
                const StripInflate inflated = inflateStrip(blob.subspan(offset, count), strip);
                if (inflated == StripInflate::Damaged) {
                    fail(where, "truncated or corrupt TIFF data (strip " + std::to_string(s) +
                                    "): its Deflate data is corrupt or fails its checksum (Adler-32)");
                }
                if (inflated == StripInflate::Inflated && (predictor == PREDICTOR_NONE || predictor == PREDICTOR_HORIZONTAL)) {
                    undoTiffPredictor(strip, rowBytes, channels, bits, TIFFIsByteSwapped(t) != 0,
                                  predictor == PREDICTOR_HORIZONTAL);
                    filled += want;
                    continue;
                }
            }
        }
        const tmsize_t got = TIFFReadEncodedStrip(t, s, image.pixels.data() + filled, static_cast<tmsize_t>(want));
        if (got < 0 || static_cast<size_t>(got) != want) {
            fail(where, withCause("truncated or corrupt TIFF data (strip " + std::to_string(s) + ")", stream));
        }
        filled += want;
    }
    if (!stream.firstError.empty()) {
        fail(where, "corrupt TIFF (" + stream.firstError + ")");
    }
    return image;
}

} // namespace

TiffImage decodeTiff(std::span<const uint8_t> blob, int maxWidth, int maxHeight, const std::string& where) {
    return decodeChecked(blob, maxWidth, maxHeight, where, {});
}


std::vector<int16_t> decodeResidualTiff(std::span<const uint8_t> blob, int size, const std::string& where) {
    const TiffImage image = decodeChecked(blob, size, size, where, [&](const TiffImage& header) {
        if (header.width != size || header.height != size) {
            fail(where, "residual tile of " + std::to_string(header.width) + "x" + std::to_string(header.height) +
                            " samples, expected " + std::to_string(size) + "x" + std::to_string(size));
        }
        const bool twoBytes = header.bitsPerSample == 8 && header.channels == 2;
        const bool oneShort = header.bitsPerSample == 16 && header.channels == 1;
        if (!twoBytes && !oneShort) {
            fail(where, "residual tile with " + std::to_string(header.channels) + " x " +
                            std::to_string(header.bitsPerSample) + "-bit samples (2 x 8 or 1 x 16 expected)");
        }
    });
    std::vector<int16_t> out(static_cast<size_t>(size) * static_cast<size_t>(size));
    if (image.bitsPerSample == 8) {
        for (size_t k = 0; k < out.size(); ++k) {
            const auto v = static_cast<uint16_t>(image.pixels[2 * k] | (image.pixels[2 * k + 1] << 8));
            out[k] = static_cast<int16_t>(v);
        }
    } else {
        std::memcpy(out.data(), image.pixels.data(), out.size() * sizeof(int16_t));
    }
    return out;
}

std::vector<uint8_t> decodeOrthoTiff(std::span<const uint8_t> blob, int size, int channels, const std::string& where) {
    TiffImage image = decodeChecked(blob, size, size, where, [&](const TiffImage& header) {
        if (header.width != size || header.height != size) {
            fail(where, "ortho tile of " + std::to_string(header.width) + "x" + std::to_string(header.height) +
                            " pixels, expected " + std::to_string(size) + "x" + std::to_string(size));
        }
        if (header.bitsPerSample != 8 || header.channels != channels) {
            fail(where, "ortho tile with " + std::to_string(header.channels) + " x " +
                            std::to_string(header.bitsPerSample) + "-bit samples, expected " +
                            std::to_string(channels) + " x 8");
        }
    });
    return std::move(image.pixels);
}

std::optional<JpegTileTables> jpegTileTables(std::span<const uint8_t> blob, const std::string& where) {
    MemoryStream stream;
    stream.data = blob.data();
    stream.size = blob.size();
    TiffHandle tif(stream, "rm", 1 << 20);
    if (!tif.get()) {
        fail(where, withCause("not a TIFF", stream));
    }
    uint16_t compression = 0, photometric = 0;
    TIFFGetFieldDefaulted(tif.get(), TIFFTAG_COMPRESSION, &compression);
    if (compression != COMPRESSION_JPEG) {
        return std::nullopt;
    }
    TIFFGetFieldDefaulted(tif.get(), TIFFTAG_PHOTOMETRIC, &photometric);
    JpegMarkers markers;
    uint32_t tablesSize = 0;
    const void* tables = nullptr;
    if (TIFFGetField(tif.get(), TIFFTAG_JPEGTABLES, &tablesSize, &tables) && tables && tablesSize > 0) {
        readJpegMarkers({static_cast<const uint8_t*>(tables), tablesSize}, markers, where + ": JPEGTables");
    }
    const tmsize_t stripSize = TIFFNumberOfStrips(tif.get()) > 0 ? TIFFRawStripSize(tif.get(), 0) : -1;
    if (stripSize <= 0 || static_cast<uint64_t>(stripSize) > blob.size()) {
        fail(where, "JPEG tile without a strip");
    }
    std::vector<uint8_t> strip(static_cast<size_t>(stripSize));
    if (TIFFReadRawStrip(tif.get(), 0, strip.data(), stripSize) != stripSize) {
        fail(where, withCause("cannot read the JPEG strip", stream));
    }
    readJpegMarkers(strip, markers, where);
    if (!markers.frame || markers.componentTables.empty()) {
        fail(where, "damaged JPEG stream: no frame header");
    }
    JpegTileTables out;
    out.ycbcr = photometric == PHOTOMETRIC_YCBCR;
    for (const int id : markers.componentTables) {
        if (id > 3 || !markers.tables[static_cast<size_t>(id)]) {
            fail(where, "damaged JPEG stream: a component's quantisation table " + std::to_string(id) + " is missing");
        }
        out.components.push_back(*markers.tables[static_cast<size_t>(id)]);
    }
    return out;
}

std::string describeTiff(std::span<const uint8_t> blob) {
    MemoryStream stream;
    stream.data = blob.data();
    stream.size = blob.size();
    TiffHandle tif(stream, "rm", 1 << 20);
    if (!tif.get()) {
        return "invalid";
    }
    uint16_t compression = 0;
    TIFFGetFieldDefaulted(tif.get(), TIFFTAG_COMPRESSION, &compression);
    switch (compression) {
    case COMPRESSION_NONE:
        return "none";
    case COMPRESSION_ADOBE_DEFLATE:
        return "deflate";
    case COMPRESSION_DEFLATE: // 32946, the legacy code of the original tools
        return "deflate-legacy";
    case COMPRESSION_LZW:
        return "lzw";
    case COMPRESSION_JPEG: {
        uint16_t photometric = 0;
        TIFFGetFieldDefaulted(tif.get(), TIFFTAG_PHOTOMETRIC, &photometric);
        return photometric == PHOTOMETRIC_YCBCR ? "jpeg-ycbcr" : "jpeg";
    }
    case COMPRESSION_PACKBITS:
        return "packbits";
    default:
        return "compression-" + std::to_string(compression);
    }
}

} // namespace pyramid
