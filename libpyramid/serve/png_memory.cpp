// PNG images encoded in memory (png_memory.hpp), through libpng's write callbacks.
#include "libpyramid/serve/png_memory.hpp"

#include <png.h>

#include <csetjmp>
#include <string>

#include "formats/error.hpp"

namespace pyramid::serve {

namespace {

void appendBytes(png_structp png, png_bytep data, png_size_t length) {
    auto* out = static_cast<std::string*>(png_get_io_ptr(png));
    out->append(reinterpret_cast<const char*>(data), length);
}

void flushNothing(png_structp) {}

int colourType(int channels) {
    switch (channels) {
    case 1:
        return PNG_COLOR_TYPE_GRAY;
    case 2:
        return PNG_COLOR_TYPE_GRAY_ALPHA;
    case 3:
        return PNG_COLOR_TYPE_RGB;
    default:
        return PNG_COLOR_TYPE_RGB_ALPHA;
    }
}

// The libpng calls, apart from any C++ object with a destructor: libpng reports an error by
// longjmp to here. Returns false on such an error.
bool writeImage(png_structp png, png_infop info, const uint8_t* pixels, int width, int height, int channels,
                std::string* out) {
    if (setjmp(png_jmpbuf(png)) != 0) {
        return false;
    }
    png_set_write_fn(png, out, appendBytes, flushNothing);
    png_set_compression_level(png, 1);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
                 colourType(channels), PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    const size_t stride = static_cast<size_t>(width) * static_cast<size_t>(channels);
    for (int row = 0; row < height; ++row) {
        png_write_row(png, const_cast<png_bytep>(pixels + stride * static_cast<size_t>(row)));
    }
    png_write_end(png, nullptr);
    return true;
}

} // namespace

std::string encodePng(const uint8_t* pixels, int width, int height, int channels) {
    if (width < 1 || height < 1 || channels < 1 || channels > 4) {
        fail("PNG", "no image of " + std::to_string(width) + " x " + std::to_string(height) + " pixels of " +
                        std::to_string(channels) + " channels");
    }
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
    if (info == nullptr) {
        png_destroy_write_struct(&png, nullptr);
        fail("PNG", "libpng could not start (out of memory)");
    }
    std::string out;
    out.reserve(static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(channels) / 2 + 256);
    const bool ok = writeImage(png, info, pixels, width, height, channels, &out);
    png_destroy_write_struct(&png, &info);
    if (!ok) {
        fail("PNG", "libpng failed to encode a tile");
    }
    return out;
}

} // namespace pyramid::serve
