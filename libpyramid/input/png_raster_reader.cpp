#include "libpyramid/input/png_raster_reader.hpp"

#include <png.h>

#include <csetjmp>
#include <optional>
#include <cstdio>
#include <vector>

#include "formats/error.hpp"

namespace pyramid {

namespace {

std::string damaged(const std::string& why) { return "cannot read: damaged or truncated PNG (" + why + ")"; }

// libpng's state. Every call into libpng that may fail is made where a setjmp of the same
// function catches its longjmp; nothing with a destructor lives between them.
class PngDecoder : public DecodedRows::Decoder {
public:
    explicit PngDecoder(std::string path) : path_(std::move(path)) {}
    ~PngDecoder() override {
        if (png_) {
            png_destroy_read_struct(&png_, info_ ? &info_ : nullptr, nullptr);
        }
        if (file_) {
            std::fclose(file_);
        }
    }
    PngDecoder(const PngDecoder&) = delete;
    PngDecoder& operator=(const PngDecoder&) = delete;

    // False when the file is not a PNG; throws when libpng cannot be set up.
    bool open() {
        file_ = std::fopen(path_.c_str(), "rb");
        if (!file_) {
            return false; // the caller's readers report it
        }
        png_byte signature[8] = {};
        if (std::fread(signature, 1, sizeof signature, file_) != sizeof signature ||
            png_sig_cmp(signature, 0, sizeof signature) != 0) {
            return false;
        }
        png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, this, onError, onWarning);
        if (!png_ || !(info_ = png_create_info_struct(png_))) {
            fail(path_, "cannot read: out of memory");
        }
        return true;
    }

    // The header, up to the image's first row; interlace handling turned on.
    void readHeader(bool& interlaced) {
        if (setjmp(png_jmpbuf(png_))) {
            fail(path_, damaged(error_));
        }
        png_init_io(png_, file_);
        png_set_sig_bytes(png_, 8);
#ifdef PNG_IGNORE_ADLER32
        // Every chunk's CRC is still checked, over the compressed bytes, so that damage is still
        // found; the zlib stream's own checksum over the decoded bytes would only repeat it, at a
        // tenth of the decoding thread's time.
        png_set_option(png_, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
#endif
        // A bad CRC fails the file in every chunk, not only the critical ones (libpng's default
        // warns and drops an ancillary chunk): a damaged file is refused whole.
        png_set_crc_action(png_, PNG_CRC_DEFAULT, PNG_CRC_ERROR_QUIT);
        png_read_info(png_, info_);
        expandAsOpenImageIO();
        if (png_get_bit_depth(png_, info_) == 16) {
            png_set_swap(png_); // PNG is big-endian; the samples are kept as host integers
        }
        interlaced = png_set_interlace_handling(png_) > 1;
        png_read_update_info(png_, info_);
    }

    png_structp png() const { return png_; }
    png_infop info() const { return info_; }

    void readImage(std::vector<png_bytep>& rows) {
        if (setjmp(png_jmpbuf(png_))) {
            fail(path_, damaged(error_));
        }
        png_read_image(png_, rows.data());
    }
    void readRow(uint8_t* row) override {
        if (setjmp(png_jmpbuf(png_))) {
            fail(path_, damaged(error_));
        }
        png_read_row(png_, row, nullptr);
    }
    void finish() override {
        if (setjmp(png_jmpbuf(png_))) {
            fail(path_, damaged(error_));
        }
        png_read_end(png_, nullptr);
    }

private:
    // The layouts that are not samples as they stand, widened as OpenImageIO's PNG reader widens
    // them (and so as the image I/O module read them before): a palette to its RGB colours;
    // grey of 1, 2 or 4 bits to 8 bits, scaled (1 bit: 0 and 255); a transparency chunk to an
    // alpha channel of the samples' depth (a palette's entries' alphas, or 0 where a grey or RGB
    // pixel is the chunk's colour and full elsewhere).
    void expandAsOpenImageIO() {
        const int colour = png_get_color_type(png_, info_);
        if (colour == PNG_COLOR_TYPE_PALETTE) {
            png_set_palette_to_rgb(png_);
        } else if (colour == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(png_, info_) < 8) {
            png_set_expand_gray_1_2_4_to_8(png_);
        }
        if (png_get_valid(png_, info_, PNG_INFO_tRNS)) {
            png_set_tRNS_to_alpha(png_);
        }
    }

    [[noreturn]] static void onError(png_structp png, png_const_charp message) {
        auto* d = static_cast<PngDecoder*>(png_get_error_ptr(png));
        d->error_ = message ? message : "decoding error";
        png_longjmp(png, 1);
    }
    static void onWarning(png_structp, png_const_charp) {}

    std::string path_;
    FILE* file_ = nullptr;
    png_structp png_ = nullptr;
    png_infop info_ = nullptr;
    std::string error_;
};

} // namespace

namespace {

// A PNG's decoder, past its header, and what the image is; null for a file that is not a PNG.
struct PngHeader {
    std::unique_ptr<PngDecoder> decoder;
    RasterInfo info;
    bool interlaced = false;
};

std::optional<PngHeader> readPngHeader(const std::string& path) {
    PngHeader h;
    h.decoder = std::make_unique<PngDecoder>(path);
    if (!h.decoder->open()) {
        return std::nullopt;
    }
    h.decoder->readHeader(h.interlaced);
    png_structp png = h.decoder->png();
    png_infop pngInfo = h.decoder->info();
    const png_uint_32 width = png_get_image_width(png, pngInfo);
    const png_uint_32 height = png_get_image_height(png, pngInfo);
    // The decoded rows' layout, after the expansions (png_read_update_info).
    const int depth = png_get_bit_depth(png, pngInfo);
    const int channels = png_get_channels(png, pngInfo);
    if (channels < 1 || channels > 4 || (depth != 8 && depth != 16)) {
        fail(path, damaged("a layout of " + std::to_string(channels) + " channels of " + std::to_string(depth) +
                           " bits after expansion"));
    }
    const size_t rowSamples = static_cast<size_t>(width) * static_cast<size_t>(channels);
    const size_t samples = rowSamples * height;
    if (height > 0x7fffffffu || width > 0x7fffffffu || samples / height != rowSamples ||
        samples > (size_t{1} << 40)) {
        fail(path, "cannot read: a " + std::to_string(width) + " x " + std::to_string(height) +
                       " PNG is too large to decode in memory; convert it to a tiled TIFF");
    }
    h.info.width = static_cast<int>(width);
    h.info.height = static_cast<int>(height);
    h.info.channels = channels;
    h.info.alpha = channels == 2 || channels == 4; // grey or RGB with alpha, or transparency made alpha
    h.info.type = depth == 8 ? SampleType::UInt8 : SampleType::UInt16;
    h.info.formatName = "png";
    return h;
}

} // namespace

std::optional<RasterInfo> describePngRaster(const std::string& path) {
    std::optional<PngHeader> h = readPngHeader(path);
    return h ? std::optional<RasterInfo>(h->info) : std::nullopt;
}

std::unique_ptr<DecodedRows> openPngRaster(const std::string& path, int cacheMegabytes) {
    std::optional<PngHeader> h = readPngHeader(path);
    if (!h) {
        return nullptr;
    }
    std::unique_ptr<PngDecoder> decoder = std::move(h->decoder);
    const bool interlaced = h->interlaced;
    const RasterInfo& info = h->info;
    const auto height = static_cast<size_t>(info.height);
    auto rows = std::make_unique<DecodedRows>(path, info, cacheMegabytes, 16);
    if (!interlaced) {
        rows->start(std::move(decoder));
        return rows;
    }
    if (!rows->inMemory()) {
        const size_t megabytes = (rows->imageBytes() + (size_t{1} << 20) - 1) >> 20;
        failOption("cacheMegabytes", path + ": an interlaced PNG is decoded whole, " + std::to_string(megabytes) +
                                         " MB, more than a cache of " + std::to_string(cacheMegabytes) +
                                         " MB: give a cache of at least " + std::to_string(megabytes) +
                                         " MB, or save the image without interlacing");
    }
    // Every pass touches every row: nothing is final before the end.
    std::vector<png_bytep> pointers(height);
    for (size_t y = 0; y < height; ++y) {
        pointers[y] = rows->rowInMemory(static_cast<int>(y));
    }
    decoder->readImage(pointers);
    decoder->finish();
    rows->markDecoded();
    return rows;
}

} // namespace pyramid
