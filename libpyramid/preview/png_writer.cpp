#include "libpyramid/preview/png_writer.hpp"

#include <png.h>

#include <csetjmp>
#include <cstring>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"

namespace pyramid {

struct PngWriter::Impl {
    std::string path;
    int width = 0, height = 0, channels = 0, depth = 0;
    int rows = 0;
    AtomicFile file;
    uint64_t at = 0;
    png_structp png = nullptr;
    png_infop info = nullptr;
    std::string error; // libpng's message, thrown by the caller after its longjmp
    std::vector<uint8_t> bigEndian;

    explicit Impl(const std::string& p) : path(p), file(p) {}
    ~Impl() { png_destroy_write_struct(&png, &info); }

    static void write(png_structp png, png_bytep data, png_size_t size) {
        auto* self = static_cast<Impl*>(png_get_io_ptr(png));
        try {
            self->file.writeAt(self->at, data, size);
            self->at += size;
        } catch (const std::exception& e) {
            self->error = e.what();
            png_error(png, "write");
        }
    }
    static void flush(png_structp) {}
    static void onError(png_structp png, png_const_charp message) {
        auto* self = static_cast<Impl*>(png_get_error_ptr(png));
        if (self->error.empty()) {
            self->error = self->path + ": cannot write the PNG: " + message;
        }
        png_longjmp(png, 1);
    }
    static void onWarning(png_structp, png_const_charp) {}
};

namespace {

// libpng reports errors by longjmp: every call into it is made from one of these functions,
// whose frames hold nothing with a destructor; they return false when libpng failed (its
// message in the writer's error).
bool startPng(png_structp png, png_infop info, void* io, png_rw_ptr write, png_flush_ptr flush, png_uint_32 width,
              png_uint_32 height, int depth, int colour, png_text* text, int texts) {
    if (setjmp(png_jmpbuf(png))) {
        return false;
    }
    png_set_write_fn(png, io, write, flush);
    // Deflate level 2 with the adaptive filters: on hillshades a third faster than zlib's default (6)
    // and no larger.
    png_set_compression_level(png, 2);
    png_set_IHDR(png, info, width, height, depth, colour, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (texts > 0) {
        png_set_text(png, info, text, texts);
    }
    png_write_info(png, info);
    return true;
}

bool writePngRow(png_structp png, const uint8_t* row) {
    if (setjmp(png_jmpbuf(png))) {
        return false;
    }
    png_write_row(png, const_cast<png_bytep>(row));
    return true;
}

bool endPng(png_structp png) {
    if (setjmp(png_jmpbuf(png))) {
        return false;
    }
    png_write_end(png, nullptr);
    return true;
}

} // namespace

PngWriter::PngWriter(const std::string& path, int width, int height, int channels, int depth,
                     const std::vector<PngText>& text) {
    if (width < 1 || height < 1 || width > 1000000 || height > 1000000) {
        fail(path, "a PNG of " + std::to_string(width) + " x " + std::to_string(height) + " pixels cannot be written");
    }
    if (channels < 1 || channels > 4 || (depth != 8 && depth != 16)) {
        fail(path, "a PNG holds 1 to 4 channels of 8 or 16 bits");
    }
    impl_ = std::make_unique<Impl>(path);
    Impl& m = *impl_;
    m.width = width;
    m.height = height;
    m.channels = channels;
    m.depth = depth;
    m.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &m, Impl::onError, Impl::onWarning);
    if (!m.png) {
        fail(path, "cannot start a PNG");
    }
    m.info = png_create_info_struct(m.png);
    if (!m.info) {
        fail(path, "cannot start a PNG");
    }
    static const int kColour[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                  PNG_COLOR_TYPE_RGB_ALPHA};
    std::vector<png_text> chunks(text.size());
    for (size_t k = 0; k < text.size(); ++k) {
        std::memset(&chunks[k], 0, sizeof(png_text));
        chunks[k].compression = PNG_TEXT_COMPRESSION_NONE;
        chunks[k].key = const_cast<char*>(text[k].key.c_str());
        chunks[k].text = const_cast<char*>(text[k].value.c_str());
        chunks[k].text_length = text[k].value.size();
    }
    if (!startPng(m.png, m.info, &m, Impl::write, Impl::flush, static_cast<png_uint_32>(width),
                  static_cast<png_uint_32>(height), depth, kColour[channels - 1], chunks.data(),
                  static_cast<int>(chunks.size()))) {
        throw Error(m.error);
    }
}

PngWriter::~PngWriter() = default;

void PngWriter::writeRow(const uint8_t* row) {
    Impl& m = *impl_;
    if (m.rows >= m.height) {
        fail(m.path, "more rows than the image's " + std::to_string(m.height));
    }
    if (!writePngRow(m.png, row)) {
        throw Error(m.error);
    }
    ++m.rows;
}

void PngWriter::writeRow16(const uint16_t* row) {
    Impl& m = *impl_;
    const size_t samples = static_cast<size_t>(m.width) * static_cast<size_t>(m.channels);
    m.bigEndian.resize(samples * 2);
    for (size_t k = 0; k < samples; ++k) {
        m.bigEndian[2 * k] = static_cast<uint8_t>(row[k] >> 8); // PNG stores 16-bit samples big-endian
        m.bigEndian[2 * k + 1] = static_cast<uint8_t>(row[k] & 0xFF);
    }
    writeRow(m.bigEndian.data());
}

void PngWriter::commit() {
    Impl& m = *impl_;
    if (m.rows != m.height) {
        fail(m.path, std::to_string(m.rows) + " rows written of " + std::to_string(m.height));
    }
    if (!endPng(m.png)) {
        throw Error(m.error);
    }
    m.file.commit();
}

} // namespace pyramid
