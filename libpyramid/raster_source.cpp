#include "libpyramid/raster_source.hpp"

#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <tiffio.h>

#include <bit>
#include <cerrno>
#include <cstdarg>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/tiff_pixel_reader.hpp"

namespace pyramid {

namespace {

SampleType sampleTypeOf(OIIO::TypeDesc t) {
    switch (t.basetype) {
    case OIIO::TypeDesc::UINT8:
        return SampleType::UInt8;
    case OIIO::TypeDesc::INT8:
        return SampleType::Int8;
    case OIIO::TypeDesc::UINT16:
        return SampleType::UInt16;
    case OIIO::TypeDesc::INT16:
        return SampleType::Int16;
    case OIIO::TypeDesc::UINT32:
        return SampleType::UInt32;
    case OIIO::TypeDesc::INT32:
        return SampleType::Int32;
    case OIIO::TypeDesc::HALF:
        return SampleType::Float16;
    case OIIO::TypeDesc::FLOAT:
        return SampleType::Float32;
    case OIIO::TypeDesc::DOUBLE:
        return SampleType::Float64;
    default:
        return SampleType::Other;
    }
}

} // namespace

const char* sampleTypeName(SampleType type) {
    switch (type) {
    case SampleType::UInt8:
        return "uint8";
    case SampleType::Int8:
        return "int8";
    case SampleType::UInt16:
        return "uint16";
    case SampleType::Int16:
        return "int16";
    case SampleType::UInt32:
        return "uint32";
    case SampleType::Int32:
        return "int32";
    case SampleType::Float16:
        return "float16";
    case SampleType::Float32:
        return "float32";
    case SampleType::Float64:
        return "float64";
    case SampleType::Other:
        break;
    }
    return "other";
}

namespace {

// A nodata value written as text ("-9999", "nan"), as GDAL writes it.
std::optional<double> parseNodata(const std::string& text) {
    if (text == "nan" || text == "NaN" || text == "-nan") {
        return std::numeric_limits<double>::quiet_NaN();
    }
    try {
        return std::stod(text);
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

// The nodata value a file declares through OpenImageIO's attributes, if any.
std::optional<double> declaredNodata(const OIIO::ImageSpec& spec) {
    for (const char* name : {"GDAL_NODATA", "tiff:GDAL_NODATA", "oiio:nodata", "nodata"}) {
        const OIIO::ParamValue* p = spec.find_attribute(name);
        if (!p) {
            continue;
        }
        if (p->type() == OIIO::TypeString) {
            if (const std::optional<double> v = parseNodata(p->get_string())) {
                return v;
            }
            continue;
        }
        return static_cast<double>(p->get_float());
    }
    return std::nullopt;
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
            nodata = parseNodata(std::string(text, strnlen(text, length)));
        }
    }
    TIFFClose(tif);
    return nodata;
}

// One cache for the whole process, never destroyed: OIIO keeps per-thread state keyed by the
// cache, which a destroyed-and-recreated cache would find stale in long-lived worker threads.
OIIO::ImageCache* processCache(int cacheMegabytes) {
    static OIIO::ImageCache* cache = [] {
        OIIO::ImageCache* c = OIIO::ImageCache::create(true);
        // Scanline files are read in bands of rows (autotile) rather than whole, so that
        // inputs larger than memory stream through.
        c->attribute("autotile", 256);
        c->attribute("autoscanline", 1);
        c->attribute("forcefloat", 0);
        c->attribute("max_open_files", 64);
        return c;
    }();
    static std::mutex mutex;
    static int budget = 0;
    std::lock_guard<std::mutex> lock(mutex);
    if (cacheMegabytes > budget) {
        budget = cacheMegabytes;
        cache->attribute("max_memory_MB", static_cast<float>(budget));
    }
    return cache;
}

// Other single-band TIFF files of 8, 16 or 32-bit integers or float32 (compressed, tiled,
// predicted, byte-swapped: whatever libtiff decodes losslessly) are decoded by libtiff one
// whole strip or tile at a time, in parallel (one TIFF handle per reading thread), into a
// cache of decoded blocks bounded like the ImageCache (--cache-mb). The ImageCache decodes such
// files one scanline at a time under one lock per file, through zlib rather than libdeflate:
// several times slower, and serial. Integer values are converted to float32 by value, as
// readIntegersAsFloat does.
class BlockTiff {
public:
    static std::unique_ptr<BlockTiff> open(const std::string& path, const RasterInfo& info, int cacheMegabytes) {
        if (info.formatName != "tiff" || info.channels != 1) {
            return nullptr;
        }
        std::unique_ptr<BlockTiff> b(new BlockTiff());
        b->path_ = path;
        TIFF* tif = b->openHandle();
        if (!tif) {
            return nullptr;
        }
        uint32_t width = 0, height = 0;
        uint16_t compression = 0, channels = 0, photometric = 0;
        TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &width);
        TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &height);
        TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &compression);
        TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &b->bits_);
        TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &b->format_);
        TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &channels);
        TIFFGetFieldDefaulted(tif, TIFFTAG_PHOTOMETRIC, &photometric);
        b->tiled_ = TIFFIsTiled(tif) != 0;
        if (b->tiled_) {
            TIFFGetField(tif, TIFFTAG_TILEWIDTH, &b->blockWidth_);
            TIFFGetField(tif, TIFFTAG_TILELENGTH, &b->blockHeight_);
        } else {
            b->blockWidth_ = width;
            TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &b->blockHeight_);
            b->blockHeight_ = std::min(b->blockHeight_, height);
        }
        b->width_ = width;
        b->height_ = height;
        const bool lossless = compression == COMPRESSION_NONE || compression == COMPRESSION_LZW ||
                              compression == COMPRESSION_ADOBE_DEFLATE || compression == COMPRESSION_DEFLATE ||
                              compression == COMPRESSION_PACKBITS || compression == COMPRESSION_ZSTD ||
                              compression == COMPRESSION_LZMA;
        const bool integer = (b->format_ == SAMPLEFORMAT_INT || b->format_ == SAMPLEFORMAT_UINT) &&
                             (b->bits_ == 8 || b->bits_ == 16 || b->bits_ == 32);
        const bool real = b->format_ == SAMPLEFORMAT_IEEEFP && b->bits_ == 32;
        const bool ok = lossless && (integer || real) && channels == 1 && photometric == PHOTOMETRIC_MINISBLACK &&
                        width == static_cast<uint32_t>(info.width) && height == static_cast<uint32_t>(info.height) &&
                        b->blockWidth_ > 0 && b->blockHeight_ > 0 && TIFFIsCODECConfigured(compression);
        if (!ok) {
            TIFFClose(tif);
            return nullptr;
        }
        b->blocksAcross_ = (width + b->blockWidth_ - 1) / b->blockWidth_;
        b->budget_ = static_cast<size_t>(std::max(cacheMegabytes, 1)) << 20;
        b->idle_.push_back(tif);
        return b;
    }

    ~BlockTiff() {
        for (TIFF* tif : idle_) {
            TIFFClose(tif);
        }
    }

    // Columns [x0, x1) of rows [y0, y1) into out, row-major. Throws Error on a decoding error.
    void read(int x0, int y0, int x1, int y1, float* out) {
        const size_t outWidth = static_cast<size_t>(x1 - x0);
        for (uint32_t by = static_cast<uint32_t>(y0) / blockHeight_; by * blockHeight_ < static_cast<uint32_t>(y1); ++by) {
            for (uint32_t bx = static_cast<uint32_t>(x0) / blockWidth_; bx * blockWidth_ < static_cast<uint32_t>(x1);
                 ++bx) {
                const std::shared_ptr<const std::vector<float>> block = get(bx, by);
                const int bx0 = static_cast<int>(bx * blockWidth_), by0 = static_cast<int>(by * blockHeight_);
                const int cx0 = std::max(x0, bx0), cx1 = std::min(x1, bx0 + static_cast<int>(blockWidth_));
                const int cy0 = std::max(y0, by0), cy1 = std::min(y1, by0 + static_cast<int>(blockHeight_));
                for (int y = cy0; y < cy1; ++y) {
                    const float* from = block->data() + static_cast<size_t>(y - by0) * blockWidth_ + (cx0 - bx0);
                    std::copy(from, from + (cx1 - cx0), out + static_cast<size_t>(y - y0) * outWidth + (cx0 - x0));
                }
            }
        }
    }

private:
    struct Entry {
        std::shared_ptr<const std::vector<float>> values;
        uint64_t lastUse = 0;
    };

    BlockTiff() = default;

    TIFF* openHandle() const {
        return openTiffQuietly(path_, "r");
    }

    // Block (bx, by), decoded; from the cache or decoded now (outside the lock).
    std::shared_ptr<const std::vector<float>> get(uint32_t bx, uint32_t by) {
        const uint32_t index = by * blocksAcross_ + bx;
        TIFF* tif = nullptr;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (auto it = cache_.find(index); it != cache_.end()) {
                it->second.lastUse = ++clock_;
                return it->second.values;
            }
            if (!idle_.empty()) {
                tif = idle_.back();
                idle_.pop_back();
            }
        }
        if (!tif && !(tif = openHandle())) {
            fail(path_, "cannot reopen the file");
        }
        auto values = std::make_shared<std::vector<float>>();
        const bool ok = decode(tif, index, *values);
        std::lock_guard<std::mutex> lock(mutex_);
        idle_.push_back(tif);
        if (!ok) {
            fail(path_, std::string("read failed: cannot decode ") + (tiled_ ? "tile " : "strip ") +
                            std::to_string(index));
        }
        const size_t bytes = values->size() * sizeof(float);
        // Evict the least recently used blocks beyond the budget (a block in use stays alive
        // through its shared_ptr).
        while (!cache_.empty() && used_ + bytes > budget_) {
            auto oldest = cache_.begin();
            for (auto it = cache_.begin(); it != cache_.end(); ++it) {
                if (it->second.lastUse < oldest->second.lastUse) {
                    oldest = it;
                }
            }
            used_ -= oldest->second.values->size() * sizeof(float);
            cache_.erase(oldest);
        }
        auto [it, inserted] = cache_.try_emplace(index, Entry{values, ++clock_});
        if (inserted) {
            used_ += bytes;
        }
        return it->second.values;
    }

    bool decode(TIFF* tif, uint32_t index, std::vector<float>& values) const {
        const size_t count = static_cast<size_t>(blockWidth_) * blockHeight_;
        std::vector<uint8_t> raw(count * (bits_ / 8));
        const tmsize_t got = tiled_ ? TIFFReadEncodedTile(tif, index, raw.data(), static_cast<tmsize_t>(raw.size()))
                                    : TIFFReadEncodedStrip(tif, index, raw.data(), static_cast<tmsize_t>(raw.size()));
        // The last strip may hold fewer rows; missing rows are never read (outside the image).
        if (got < 0) {
            return false;
        }
        values.resize(count);
        const auto convert = [&](auto type) {
            using T = decltype(type);
            for (size_t k = 0; k < count; ++k) {
                T v;
                std::memcpy(&v, raw.data() + k * sizeof(T), sizeof(T));
                values[k] = static_cast<float>(v);
            }
        };
        const bool isSigned = format_ == SAMPLEFORMAT_INT;
        if (format_ == SAMPLEFORMAT_IEEEFP) {
            std::memcpy(values.data(), raw.data(), count * sizeof(float));
        } else if (bits_ == 8) {
            isSigned ? convert(int8_t{}) : convert(uint8_t{});
        } else if (bits_ == 16) {
            isSigned ? convert(int16_t{}) : convert(uint16_t{});
        } else {
            isSigned ? convert(int32_t{}) : convert(uint32_t{});
        }
        return true;
    }

    std::string path_;
    uint32_t width_ = 0, height_ = 0;
    uint32_t blockWidth_ = 0, blockHeight_ = 0, blocksAcross_ = 0;
    uint16_t bits_ = 0, format_ = SAMPLEFORMAT_UINT;
    bool tiled_ = false;
    size_t budget_ = 0;
    std::mutex mutex_;
    std::vector<TIFF*> idle_;                    // open handles not in use
    std::unordered_map<uint32_t, Entry> cache_; // decoded blocks by index
    size_t used_ = 0;
    uint64_t clock_ = 0;
};

} // namespace

struct RasterSource::Impl {
    OIIO::ImageCache* cache = nullptr;
    OIIO::ustring name;
    // Set when an uncompressed float32 TIFF can be read without any cache: each row of a window
    // is one pread (the cache would copy every sample twice into freshly faulted memory, one band
    // at a time under its per-file lock, and hold up to --cache-mb of it).
    std::unique_ptr<TiffPixelReader> floats;
    std::unique_ptr<BlockTiff> blocks;  // or when libtiff decodes it, block by block
    std::unique_ptr<TiffPixelReader> pixels; // 8- or 16-bit samples read without the cache

    ~Impl() {
        if (cache) {
            cache->invalidate(name); // close the file and drop its tiles
        }
    }
};

std::unique_ptr<RasterSource> RasterSource::open(const std::string& path, int cacheMegabytes) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        fail(path, "no such file");
    }
    if (!std::filesystem::is_regular_file(path, ec)) {
        fail(path, "not a regular file");
    }
    std::unique_ptr<RasterSource> source(new RasterSource());
    source->path_ = path;
    source->impl_ = std::make_unique<Impl>();
    Impl& impl = *source->impl_;
    impl.cache = processCache(cacheMegabytes);
    impl.name = OIIO::ustring(path);
    OIIO::ImageSpec spec;
    if (!impl.cache->get_imagespec(impl.name, spec)) {
        std::string why = impl.cache->geterror();
        if (why.empty()) {
            why = "not an image OpenImageIO can read";
        }
        const auto nl = why.find('\n');
        fail(path, "cannot read: " + why.substr(0, nl));
    }
    if (spec.depth > 1) {
        fail(path, "volume images are not supported");
    }
    RasterInfo& info = source->info_;
    info.width = spec.width;
    info.height = spec.height;
    info.channels = spec.nchannels;
    info.type = sampleTypeOf(spec.format);
    info.nodata = declaredNodata(spec);
    OIIO::ustring format;
    if (impl.cache->get_image_info(impl.name, 0, 0, OIIO::ustring("fileformat"), OIIO::TypeString, &format)) {
        info.formatName = format.string();
    }
    if (!info.nodata && info.formatName == "tiff") {
        info.nodata = geoTiffNodata(path);
    }
    if (info.width < 1 || info.height < 1 || info.channels < 1) {
        fail(path, "empty image");
    }
    if (info.formatName == "tiff" && info.type == SampleType::Float32) {
        impl.floats = TiffPixelReader::open(path, info.width, info.height, info.channels, 4, true);
    }
    if (!impl.floats) {
        impl.blocks = BlockTiff::open(path, info, cacheMegabytes);
    }
    if (info.formatName == "tiff" && (info.type == SampleType::UInt8 || info.type == SampleType::UInt16)) {
        impl.pixels =
            TiffPixelReader::open(path, info.width, info.height, info.channels, info.type == SampleType::UInt8 ? 1 : 2);
    }
    return source;
}

RasterSource::~RasterSource() = default;

namespace {
void checkWindow(const std::string& path, const RasterInfo& info, int x0, int y0, int x1, int y1) {
    if (x0 < 0 || y0 < 0 || x1 > info.width || y1 > info.height || x0 >= x1 || y0 >= y1) {
        fail(path, "window [" + std::to_string(x0) + "," + std::to_string(x1) + ")x[" + std::to_string(y0) + "," +
                       std::to_string(y1) + ") outside the image");
    }
}

// Reads a window of one channel in the file's own integer type T and converts each value to
// float32 by value: OIIO's own conversion to float would normalise it (v / 255, v / 32767...).
template <typename T>
bool readIntegersAsFloat(OIIO::TypeDesc::BASETYPE type, OIIO::ImageCache* cache, OIIO::ustring name, int x0, int y0,
                         int x1, int y1, int channel, float* out) {
    const size_t count = static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0);
    std::vector<T> values(count);
    if (!cache->get_pixels(name, 0, 0, x0, x1, y0, y1, 0, 1, channel, channel + 1, type, values.data())) {
        return false;
    }
    for (size_t k = 0; k < count; ++k) {
        out[k] = static_cast<float>(values[k]);
    }
    return true;
}
} // namespace

void RasterSource::readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const {
    checkWindow(path_, info_, x0, y0, x1, y1);
    if (channel < 0 || channel >= info_.channels) {
        fail(path_, "no channel " + std::to_string(channel));
    }
    if (impl_->floats) {
        if (!impl_->floats->readFloat(x0, y0, x1, y1, channel, out)) {
            fail(path_, std::string("read failed: ") + (errno ? std::strerror(errno) : "file too short"));
        }
        return;
    }
    if (impl_->blocks) {
        impl_->blocks->read(x0, y0, x1, y1, out);
        return;
    }
    OIIO::ImageCache* cache = impl_->cache;
    const OIIO::ustring name = impl_->name;
    bool ok = false;
    switch (info_.type) {
    case SampleType::UInt8:
        ok = readIntegersAsFloat<uint8_t>(OIIO::TypeDesc::UINT8, cache, name, x0, y0, x1, y1, channel, out);
        break;
    case SampleType::Int8:
        ok = readIntegersAsFloat<int8_t>(OIIO::TypeDesc::INT8, cache, name, x0, y0, x1, y1, channel, out);
        break;
    case SampleType::UInt16:
        ok = readIntegersAsFloat<uint16_t>(OIIO::TypeDesc::UINT16, cache, name, x0, y0, x1, y1, channel, out);
        break;
    case SampleType::Int16:
        ok = readIntegersAsFloat<int16_t>(OIIO::TypeDesc::INT16, cache, name, x0, y0, x1, y1, channel, out);
        break;
    case SampleType::UInt32:
        ok = readIntegersAsFloat<uint32_t>(OIIO::TypeDesc::UINT32, cache, name, x0, y0, x1, y1, channel, out);
        break;
    case SampleType::Int32:
        ok = readIntegersAsFloat<int32_t>(OIIO::TypeDesc::INT32, cache, name, x0, y0, x1, y1, channel, out);
        break;
    default: // floating point: converted to float32 by value
        ok = cache->get_pixels(name, 0, 0, x0, x1, y0, y1, 0, 1, channel, channel + 1, OIIO::TypeFloat, out);
        break;
    }
    if (!ok) {
        std::string why = cache->geterror();
        fail(path_, "read failed: " + why.substr(0, why.find('\n')));
    }
}

void RasterSource::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const {
    checkWindow(path_, info_, x0, y0, x1, y1);
    if (c0 < 0 || c1 > info_.channels || c0 >= c1) {
        fail(path_, "channels [" + std::to_string(c0) + "," + std::to_string(c1) + ") outside the image");
    }
    // OIIO converts integer types to UINT16 by normalisation (v8 * 257); 8-bit input is
    // widened to its plain value 0..255 instead, as documented.
    const bool eightBit = info_.type == SampleType::UInt8 || info_.type == SampleType::Int8;
    const size_t count = static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0) * static_cast<size_t>(c1 - c0);
    if (impl_->pixels) {
        if (!impl_->pixels->readUInt16(x0, y0, x1, y1, c0, c1, out)) {
            fail(path_, std::string("read failed: ") + (errno ? std::strerror(errno) : "file too short"));
        }
        return;
    }
    if (eightBit) {
        std::vector<uint8_t> bytes(count);
        if (!impl_->cache->get_pixels(impl_->name, 0, 0, x0, x1, y0, y1, 0, 1, c0, c1, OIIO::TypeDesc::UINT8,
                                      bytes.data())) {
            std::string why = impl_->cache->geterror();
            fail(path_, "read failed: " + why.substr(0, why.find('\n')));
        }
        for (size_t k = 0; k < count; ++k) {
            out[k] = bytes[k];
        }
        return;
    }
    if (!impl_->cache->get_pixels(impl_->name, 0, 0, x0, x1, y0, y1, 0, 1, c0, c1, OIIO::TypeDesc::UINT16, out)) {
        std::string why = impl_->cache->geterror();
        fail(path_, "read failed: " + why.substr(0, why.find('\n')));
    }
}

void RasterSource::readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out,
                             std::ptrdiff_t rowStride) const {
    checkWindow(path_, info_, x0, y0, x1, y1);
    if (c0 < 0 || c1 > info_.channels || c0 >= c1) {
        fail(path_, "channels [" + std::to_string(c0) + "," + std::to_string(c1) + ") outside the image");
    }
    if (info_.type != SampleType::UInt8) {
        fail(path_, "readUInt8 on samples that are not 8-bit unsigned");
    }
    if (impl_->pixels) {
        if (!impl_->pixels->readUInt8(x0, y0, x1, y1, c0, c1, out, rowStride)) {
            fail(path_, std::string("read failed: ") + (errno ? std::strerror(errno) : "file too short"));
        }
        return;
    }
    const size_t rowBytes = static_cast<size_t>(x1 - x0) * static_cast<size_t>(c1 - c0);
    std::vector<uint8_t> bytes(rowBytes * static_cast<size_t>(y1 - y0));
    if (!impl_->cache->get_pixels(impl_->name, 0, 0, x0, x1, y0, y1, 0, 1, c0, c1, OIIO::TypeDesc::UINT8,
                                  bytes.data())) {
        std::string why = impl_->cache->geterror();
        fail(path_, "read failed: " + why.substr(0, why.find('\n')));
    }
    for (int y = y0; y < y1; ++y) {
        std::copy_n(&bytes[static_cast<size_t>(y - y0) * rowBytes], rowBytes,
                    out + static_cast<std::ptrdiff_t>(y - y0) * rowStride);
    }
}

} // namespace pyramid
