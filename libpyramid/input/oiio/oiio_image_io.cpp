// libpyramid_oiio.so: OpenImageIO's readers and writers for libpyramid, loaded on demand
// (libpyramid/input/image_io_module.hpp says why). Reads go through one process-wide ImageCache,
// so any size of image is read by windows in bounded memory, from many threads at once.
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <mutex>

#include "libpyramid/input/image_io_module.hpp"
#include "libpyramid/input/nodata_text.hpp"

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

OIIO::TypeDesc typeDescOf(SampleType t) {
    switch (t) {
    case SampleType::UInt8:
        return OIIO::TypeDesc::UINT8;
    case SampleType::Int8:
        return OIIO::TypeDesc::INT8;
    case SampleType::UInt16:
        return OIIO::TypeDesc::UINT16;
    case SampleType::Int16:
        return OIIO::TypeDesc::INT16;
    case SampleType::UInt32:
        return OIIO::TypeDesc::UINT32;
    case SampleType::Int32:
        return OIIO::TypeDesc::INT32;
    case SampleType::Float16:
        return OIIO::TypeDesc::HALF;
    case SampleType::Float32:
        return OIIO::TypeDesc::FLOAT;
    case SampleType::Float64:
        return OIIO::TypeDesc::DOUBLE;
    case SampleType::Other:
        break;
    }
    return OIIO::TypeDesc::UNKNOWN;
}

// The first line of an OpenImageIO error message.
std::string firstLine(std::string text) {
    text.resize(std::min(text.size(), text.find('\n')));
    return text;
}

// The nodata value a file declares through OpenImageIO's attributes, if any. Throws Error for
// a text value that is not a number, NaN or an infinity (the caller names the file).
std::optional<double> declaredNodata(const OIIO::ImageSpec& spec) {
    for (const char* name : {"GDAL_NODATA", "tiff:GDAL_NODATA", "oiio:nodata", "nodata"}) {
        const OIIO::ParamValue* p = spec.find_attribute(name);
        if (!p) {
            continue;
        }
        if (p->type() == OIIO::TypeString) {
            return parseDeclaredNodata(p->get_string(), "", name);
        }
        return static_cast<double>(p->get_float());
    }
    return std::nullopt;
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
        // Colours as stored: OpenImageIO would otherwise multiply them by alpha on reading.
        c->attribute("unassociatedalpha", 1);
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

class CachedImage final : public ModuleImage {
public:
    CachedImage(OIIO::ImageCache* cache, OIIO::ustring name, RasterInfo info)
        : cache_(cache), name_(name), info_(std::move(info)) {}
    ~CachedImage() override { cache_->invalidate(name_); } // close the file and drop its tiles

    const RasterInfo& info() const override { return info_; }

    bool read(int x0, int y0, int x1, int y1, int c0, int c1, SampleType type, void* out,
              std::string& error) const override {
        if (cache_->get_pixels(name_, 0, 0, x0, x1, y0, y1, 0, 1, c0, c1, typeDescOf(type), out)) {
            return true;
        }
        error = firstLine(cache_->geterror());
        if (error.empty()) {
            error = "OpenImageIO could not read the pixels";
        }
        return false;
    }

private:
    OIIO::ImageCache* cache_;
    OIIO::ustring name_;
    RasterInfo info_;
};

std::unique_ptr<ModuleImage> openImage(const std::string& path, int cacheMegabytes, std::string& error) {
    try {
        OIIO::ImageCache* cache = processCache(cacheMegabytes);
        const OIIO::ustring name(path);
        OIIO::ImageSpec spec;
        if (!cache->get_imagespec(name, spec)) {
            error = firstLine(cache->geterror());
            if (error.empty()) {
                error = "not an image OpenImageIO can read";
            }
            return nullptr;
        }
        if (spec.depth > 1) {
            error = "volume images are not supported";
            return nullptr;
        }
        RasterInfo info;
        info.width = spec.width;
        info.height = spec.height;
        info.channels = spec.nchannels;
        info.alpha = spec.nchannels > 1 && spec.alpha_channel == spec.nchannels - 1;
        info.type = sampleTypeOf(spec.format);
        info.nodata = declaredNodata(spec);
        OIIO::ustring format;
        if (cache->get_image_info(name, 0, 0, OIIO::ustring("fileformat"), OIIO::TypeString, &format)) {
            info.formatName = format.string();
        }
        return std::make_unique<CachedImage>(cache, name, std::move(info));
    } catch (const std::exception& e) {
        error = e.what();
        return nullptr;
    }
}

bool writeImage(const std::string& path, int width, int height, int channels, SampleType type, SampleType fileType,
                const void* pixels, std::string& error) {
    try {
        auto out = OIIO::ImageOutput::create(path);
        if (!out) {
            error = firstLine(OIIO::geterror());
            return false;
        }
        OIIO::ImageSpec spec(width, height, channels, typeDescOf(fileType));
        // The samples are written as they are: a last channel named alpha (grey and alpha, RGBA)
        // is unassociated, as the pyramids store it, so that no writer divides the colours by it
        // (PNG) or labels them premultiplied (TIFF's ExtraSamples).
        if (channels == 2) {
            spec.channelnames = {"Y", "A"};
            spec.alpha_channel = 1;
        }
        spec.attribute("oiio:UnassociatedAlpha", 1);
        if (!out->open(path, spec) || !out->write_image(typeDescOf(type), pixels) || !out->close()) {
            error = firstLine(out->geterror());
            return false;
        }
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

// The library's own version at run time (openimageio_version(): 10000 major + 100 minor + patch).
std::string libraryVersion() {
    const int v = OIIO::openimageio_version();
    return std::to_string(v / 10000) + "." + std::to_string(v / 100 % 100) + "." + std::to_string(v % 100);
}

const ImageIoModule kModule{kImageIoModuleAbi, &openImage, &writeImage, &libraryVersion};

} // namespace

} // namespace pyramid

extern "C" __attribute__((visibility("default"))) const pyramid::ImageIoModule* pyramid_image_io_module() {
    return &pyramid::kModule;
}
