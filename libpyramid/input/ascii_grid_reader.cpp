#include "libpyramid/input/ascii_grid_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <set>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/esri_grid_header.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

constexpr size_t kHeaderBytes = 4096;  // a header's keyword lines stay far below
constexpr size_t kChunkBytes = 1 << 20; // the text read at a time
constexpr size_t kLongestValue = 256;  // a longer word is no number

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

const std::set<std::string>& headerKeywords() {
    static const std::set<std::string> k = {"ncols",     "nrows",     "xllcorner", "xllcenter", "yllcorner",
                                            "yllcenter", "cellsize",  "dx",        "dy",        "nodata_value"};
    return k;
}

struct Header {
    RasterInfo info;
    size_t dataOffset = 0; // where the values begin
};

class File {
public:
    explicit File(const std::string& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {
        if (fd_ < 0) {
            fail(path, std::string("cannot open: ") + std::strerror(errno));
        }
    }
    ~File() { ::close(fd_); }
    File(const File&) = delete;
    File& operator=(const File&) = delete;
    // Up to `size` bytes at the current position; 0 at the end. Throws naming `path` on an error.
    size_t read(char* to, size_t size, const std::string& path) const {
        for (;;) {
            const ssize_t n = ::read(fd_, to, size);
            if (n >= 0) {
                return static_cast<size_t>(n);
            }
            if (errno != EINTR) {
                fail(path, std::string("cannot read: ") + std::strerror(errno));
            }
        }
    }
    void seek(size_t offset) const { ::lseek(fd_, static_cast<off_t>(offset), SEEK_SET); }
    uint64_t size(const std::string& path) const {
        struct stat st {};
        if (fstat(fd_, &st) != 0) {
            fail(path, std::string("cannot read: ") + std::strerror(errno));
        }
        return static_cast<uint64_t>(st.st_size);
    }

private:
    int fd_;
};

// The header, when the file begins with one of its keywords.
std::optional<Header> readHeader(const std::string& path) {
    const File file(path);
    std::string text(kHeaderBytes, '\0');
    text.resize(file.read(text.data(), text.size(), path));
    EsriKeys keys;
    size_t at = 0;
    for (;;) {
        while (at < text.size() && isBlank(text[at])) {
            ++at;
        }
        if (at >= text.size() || !std::isalpha(static_cast<unsigned char>(text[at]))) {
            break; // the values begin (or the file ends)
        }
        const size_t lineEnd = std::min(text.find('\n', at), text.size());
        std::string key, value;
        size_t k = at;
        for (; k < lineEnd && !isBlank(text[k]); ++k) {
            key += text[k];
        }
        for (; k < lineEnd && isBlank(text[k]); ++k) {
        }
        for (; k < lineEnd && !isBlank(text[k]); ++k) {
            value += text[k];
        }
        key = lowerAsciiText(key);
        if (!headerKeywords().count(key)) {
            if (keys.empty()) {
                return std::nullopt; // not an ASCII grid
            }
            break; // the values begin: the decoder names a word that is no number
        }
        if (lineEnd == kHeaderBytes) {
            fail(path, "its header does not end within " + std::to_string(kHeaderBytes) + " bytes");
        }
        keys[key] = value;
        at = lineEnd + 1;
    }
    if (keys.empty()) {
        return std::nullopt;
    }
    Header h;
    RasterInfo& info = h.info;
    const auto count = [&](const char* key) {
        const std::optional<double> v = esriNumber(keys, key, path);
        if (!v || *v < 1 || *v > 2147483647.0 || *v != std::floor(*v)) {
            fail(path, std::string("an ASCII grid's header needs ") + key + ", a whole number from 1");
        }
        return static_cast<int>(*v);
    };
    info.width = count("ncols");
    info.height = count("nrows");
    info.channels = 1;
    info.type = SampleType::Float32;
    info.formatName = "aaigrid";
    info.nodata = esriNumber(keys, "nodata_value", path);
    // Each value takes a character and a separator (the last none): a header giving more values
    // than its file can hold is refused before any row is allocated.
    const double values = static_cast<double>(info.width) * info.height;
    const double bytes = static_cast<double>(file.size(path)) - static_cast<double>(at);
    if (bytes < 2.0 * values - 1.0) {
        fail(path, "holds " + std::to_string(file.size(path)) + " bytes, too few for the " +
                       std::to_string(info.width) + " x " + std::to_string(info.height) + " values its header gives");
    }
    if (const std::optional<std::array<double, 6>> t = esriTransform(keys, info.height, path)) {
        info.georeference = sidecarCrsPlacement(path, *t);
    }
    h.dataOffset = at;
    return h;
}

// The values, row by row, from a buffer of the text refilled as it is used.
class AsciiGridDecoder : public DecodedRows::Decoder {
public:
    AsciiGridDecoder(std::string path, const Header& header)
        : path_(std::move(path)), file_(path_), width_(header.info.width), height_(header.info.height) {
        file_.seek(header.dataOffset);
        buffer_.resize(kChunkBytes + kLongestValue);
    }

    void readRow(uint8_t* row) override {
        auto* out = reinterpret_cast<float*>(row);
        for (int x = 0; x < width_; ++x) {
            if (!nextValue(out[x], x)) {
                fail(path_, "ends after " + std::to_string(static_cast<int64_t>(row_) * width_ + x) + " of the " +
                                std::to_string(width_) + " x " + std::to_string(height_) +
                                " values its header gives");
            }
        }
        ++row_;
    }

    void finish() override {
        if (!next().empty()) {
            fail(path_, "holds more values than the " + std::to_string(width_) + " x " + std::to_string(height_) +
                            " its header gives");
        }
    }

private:
    // The next value, parsed where it stands (std::from_chars finds its end, which must be a
    // blank or the end of the file): at least kLongestValue bytes are loaded past its start,
    // unless the file ends first. False at the end of the file. Throws naming the row and
    // column `x` for a word that is no float32.
    bool nextValue(float& v, int x) {
        for (;;) {
            while (pos_ < end_ && isBlank(buffer_[pos_])) {
                ++pos_;
            }
            if (!eof_ && end_ - pos_ < kLongestValue) {
                refill();
                continue;
            }
            if (pos_ == end_) {
                return false;
            }
            const char* word = &buffer_[pos_];
            const char* last = buffer_.data() + end_;
            const char* first = *word == '+' ? word + 1 : word;
            const std::from_chars_result r = std::from_chars(first, last, v);
            if (r.ec == std::errc() && r.ptr < last && isBlank(*r.ptr)) {
                pos_ = static_cast<size_t>(r.ptr - buffer_.data());
                return true;
            }
            if (r.ec == std::errc() && r.ptr == last && eof_) {
                pos_ = end_;
                return true;
            }
            const char* stop = word;
            while (stop < last && !isBlank(*stop)) {
                ++stop;
            }
            if (stop == last && !eof_) {
                fail(path_, "row " + std::to_string(row_) + ": a word of more than " + std::to_string(kLongestValue) +
                                " characters is no number");
            }
            fail(path_, "row " + std::to_string(row_) + ", column " + std::to_string(x) + ": \"" +
                            printableText(std::string_view(word, static_cast<size_t>(stop - word))) + "\" is " +
                            (r.ec == std::errc::result_out_of_range ? "beyond float32's range" : "not a number"));
        }
    }

    // The next word (empty at the end of the file).
    std::string_view next() {
        for (;;) {
            while (pos_ < end_ && isBlank(buffer_[pos_])) {
                ++pos_;
            }
            size_t stop = pos_;
            while (stop < end_ && !isBlank(buffer_[stop])) {
                ++stop;
            }
            if (stop < end_ || (eof_ && stop > pos_)) {
                const std::string_view word(&buffer_[pos_], stop - pos_);
                pos_ = stop;
                return word;
            }
            if (eof_) {
                return {};
            }
            if (stop - pos_ >= kLongestValue) {
                fail(path_, "row " + std::to_string(row_) + ": a word of more than " + std::to_string(kLongestValue) +
                                " characters is no number");
            }
            refill();
        }
    }

    void refill() {
        const size_t kept = end_ - pos_;
        std::memmove(buffer_.data(), buffer_.data() + pos_, kept);
        pos_ = 0;
        end_ = kept;
        const size_t n = file_.read(buffer_.data() + end_, buffer_.size() - end_, path_);
        end_ += n;
        eof_ = n == 0;
    }

    std::string path_;
    File file_;
    int width_, height_;
    int row_ = 0;
    std::vector<char> buffer_;
    size_t pos_ = 0, end_ = 0;
    bool eof_ = false;
};

} // namespace

std::optional<RasterInfo> describeAsciiGrid(const std::string& path) {
    std::optional<Header> h = readHeader(path);
    return h ? std::optional<RasterInfo>(h->info) : std::nullopt;
}

std::unique_ptr<DecodedRows> openAsciiGrid(const std::string& path, int cacheMegabytes) {
    const std::optional<Header> h = readHeader(path);
    if (!h) {
        return nullptr;
    }
    auto rows = std::make_unique<DecodedRows>(path, h->info, cacheMegabytes, 16);
    rows->start(std::make_unique<AsciiGridDecoder>(path, *h));
    return rows;
}

} // namespace pyramid
