#include "libpyramid/input/jpeg_raster_reader.hpp"

// jpeglib.h needs FILE and size_t declared first.
#include <cstdio>
#include <cstddef>

#include <jpeglib.h>
// After jpeglib.h, whose configuration says which messages exist.
#include <jerror.h>

#include <algorithm>
#include <csetjmp>
#include <optional>

#include "formats/error.hpp"

namespace pyramid {

namespace {

std::string damaged(const std::string& why) { return "cannot read: damaged or truncated JPEG (" + why + ")"; }

// The warnings of corrupt data, which libjpeg decodes past (filling what is lost): errors here.
// Others (an unknown JFIF revision, a bad ICC marker) do not touch the pixels.
bool corruptData(int code) {
    switch (code) {
    case JWRN_ARITH_BAD_CODE:
    case JWRN_BOGUS_PROGRESSION:
    case JWRN_EXTRANEOUS_DATA:
    case JWRN_HIT_MARKER:
    case JWRN_HUFF_BAD_CODE:
    case JWRN_JPEG_EOF:
    case JWRN_MUST_RESYNC:
    case JWRN_NOT_SEQUENTIAL: return true;
    default: return false;
    }
}

// libjpeg's state. Every call into libjpeg that may fail is made where a setjmp of the same
// function catches the error handler's longjmp; nothing with a destructor lives between them.
class JpegDecoder : public DecodedRows::Decoder {
public:
    explicit JpegDecoder(std::string path) : path_(std::move(path)) {
        cinfo_.err = jpeg_std_error(&errors_.mgr);
        errors_.mgr.error_exit = onError;
        errors_.mgr.emit_message = onMessage;
        errors_.self = this;
    }
    ~JpegDecoder() override {
        if (created_) {
            jpeg_destroy_decompress(&cinfo_);
        }
        if (file_) {
            std::fclose(file_);
        }
    }
    JpegDecoder(const JpegDecoder&) = delete;
    JpegDecoder& operator=(const JpegDecoder&) = delete;

    // False when the file is not a JPEG (it does not start with a marker's FF D8 FF).
    bool open() {
        file_ = std::fopen(path_.c_str(), "rb");
        if (!file_) {
            return false; // the caller's readers report it
        }
        unsigned char start[3] = {};
        if (std::fread(start, 1, 3, file_) != 3 || start[0] != 0xFF || start[1] != 0xD8 || start[2] != 0xFF) {
            return false;
        }
        std::rewind(file_);
        return true;
    }

    // The header; false for the kinds left to OpenImageIO.
    bool readHeader(RasterInfo& info, bool& progressive) {
        if (setjmp(errors_.jump)) {
            fail(path_, damaged(message_));
        }
        jpeg_create_decompress(&cinfo_);
        created_ = true;
        jpeg_stdio_src(&cinfo_, file_);
        jpeg_read_header(&cinfo_, TRUE);
        failOnCorruptData();
        if (cinfo_.data_precision != 8) {
            return false;
        }
        if (cinfo_.jpeg_color_space == JCS_GRAYSCALE && cinfo_.num_components == 1) {
            cinfo_.out_color_space = JCS_GRAYSCALE;
            info.channels = 1;
        } else if ((cinfo_.jpeg_color_space == JCS_YCbCr || cinfo_.jpeg_color_space == JCS_RGB) &&
                   cinfo_.num_components == 3) {
            cinfo_.out_color_space = JCS_RGB;
            info.channels = 3;
        } else {
            return false;
        }
        info.width = static_cast<int>(cinfo_.image_width);
        info.height = static_cast<int>(cinfo_.image_height);
        info.type = SampleType::UInt8;
        info.formatName = "jpeg";
        progressive = jpeg_has_multiple_scans(&cinfo_);
        return true;
    }

    void readRow(uint8_t* row) override {
        if (setjmp(errors_.jump)) {
            fail(path_, damaged(message_));
        }
        if (!started_) {
            // A progressive image is read whole here, before its first row.
            jpeg_start_decompress(&cinfo_);
            started_ = true;
        }
        JSAMPROW rows[1] = {row};
        jpeg_read_scanlines(&cinfo_, rows, 1);
        failOnCorruptData();
    }
    void finish() override {
        if (setjmp(errors_.jump)) {
            fail(path_, damaged(message_));
        }
        jpeg_finish_decompress(&cinfo_);
        failOnCorruptData();
    }

private:
    struct Errors {
        jpeg_error_mgr mgr;
        std::jmp_buf jump;
        JpegDecoder* self;
    };
    static JpegDecoder* of(j_common_ptr cinfo) { return reinterpret_cast<Errors*>(cinfo->err)->self; }
    static std::string text(j_common_ptr cinfo) {
        char buffer[JMSG_LENGTH_MAX] = {};
        (*cinfo->err->format_message)(cinfo, buffer);
        return buffer;
    }
    [[noreturn]] static void onError(j_common_ptr cinfo) {
        JpegDecoder* d = of(cinfo);
        d->message_ = text(cinfo);
        std::longjmp(d->errors_.jump, 1);
    }
    // Warnings (level -1): the first of corrupt data is kept; trace messages are dropped.
    static void onMessage(j_common_ptr cinfo, int level) {
        JpegDecoder* d = of(cinfo);
        if (level < 0 && d->corrupt_.empty() && corruptData(cinfo->err->msg_code)) {
            d->corrupt_ = text(cinfo);
        }
    }
    void failOnCorruptData() const {
        if (!corrupt_.empty()) {
            fail(path_, damaged(corrupt_));
        }
    }

    std::string path_;
    FILE* file_ = nullptr;
    jpeg_decompress_struct cinfo_{};
    Errors errors_{};
    bool created_ = false;
    bool started_ = false;
    std::string message_; // the error that stopped libjpeg
    std::string corrupt_; // the first warning of corrupt data
};

} // namespace

namespace {

// A JPEG's decoder, past its header, and what the image is; null for files left to others.
struct JpegHeader {
    std::unique_ptr<JpegDecoder> decoder;
    RasterInfo info;
    bool progressive = false;
};

std::optional<JpegHeader> readJpegHeader(const std::string& path) {
    JpegHeader h;
    h.decoder = std::make_unique<JpegDecoder>(path);
    if (!h.decoder->open() || !h.decoder->readHeader(h.info, h.progressive)) {
        return std::nullopt;
    }
    return h;
}

} // namespace

std::optional<RasterInfo> describeJpegRaster(const std::string& path) {
    std::optional<JpegHeader> h = readJpegHeader(path);
    return h ? std::optional<RasterInfo>(h->info) : std::nullopt;
}

std::unique_ptr<DecodedRows> openJpegRaster(const std::string& path, int cacheMegabytes) {
    std::optional<JpegHeader> h = readJpegHeader(path);
    if (!h) {
        return nullptr;
    }
    const RasterInfo& info = h->info;
    const bool progressive = h->progressive;
    if (progressive) {
        // libjpeg holds every coefficient (2 bytes a sample, chroma included at most) before the
        // first row: that must fit the budget, as the decoded image itself does not have to.
        const size_t coefficients = static_cast<size_t>(info.width) * static_cast<size_t>(info.height) *
                                    static_cast<size_t>(info.channels) * 2;
        const size_t budget = static_cast<size_t>(std::max(cacheMegabytes, 1)) << 20;
        if (coefficients > budget) {
            const size_t megabytes = (coefficients + (size_t{1} << 20) - 1) >> 20;
            failOption("cacheMegabytes", path + ": a progressive JPEG is held whole while it is decoded, " +
                                             std::to_string(megabytes) + " MB, more than a cache of " +
                                             std::to_string(cacheMegabytes) + " MB: give a cache of at least " +
                                             std::to_string(megabytes) + " MB, or save the image as baseline JPEG");
        }
    }
    auto rows = std::make_unique<DecodedRows>(path, info, cacheMegabytes, 16);
    rows->start(std::move(h->decoder));
    return rows;
}

} // namespace pyramid
