#include "libpyramid/raster_source.hpp"

#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <tiffio.h>

#include <cstdarg>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <vector>

#include "formats/error.hpp"

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

int ignoreTiffMessage(TIFF*, void*, const char*, const char*, va_list) { return 1; }

// GDAL keeps a GeoTIFF's nodata value in its own ASCII tag (42113), which OpenImageIO does not
// expose: read it with libtiff. Its warnings (GeoTIFF tags it does not know) are not shown.
std::optional<double> geoTiffNodata(const std::string& path) {
    TIFFOpenOptions* options = TIFFOpenOptionsAlloc();
    TIFFOpenOptionsSetErrorHandlerExtR(options, ignoreTiffMessage, nullptr);
    TIFFOpenOptionsSetWarningHandlerExtR(options, ignoreTiffMessage, nullptr);
    TIFF* tif = TIFFOpenExt(path.c_str(), "r", options);
    TIFFOpenOptionsFree(options);
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

} // namespace

struct RasterSource::Impl {
    OIIO::ImageCache* cache = nullptr;
    OIIO::ustring name;

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

} // namespace pyramid
