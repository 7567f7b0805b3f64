#include "libpyramid/input/dted_reader.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <vector>

#include "formats/error.hpp"
#include "formats/byte_source.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

constexpr uint64_t kLabelBytes = 80;   // a VOL or HDR tape label, and the UHL record
constexpr uint64_t kHeaderBytes = 3428; // UHL, DSI and ACC: 80 + 648 + 2700
constexpr uint64_t kDsiDatum = 80 + 144; // the DSI's horizontal datum, from the UHL
constexpr size_t kBandBytes = size_t{4} << 20; // the heights read at a time
constexpr int kVoid = -32767;

struct Header {
    RasterInfo info;
    uint64_t dataOffset = 0;  // the first column's record
    uint64_t recordBytes = 0; // 12 + 2 x height
};

// The value of `count` decimal digits at `text`; -1 when one is no digit.
int digitsValue(const char* text, int count) {
    int value = 0;
    for (int k = 0; k < count; ++k) {
        if (text[k] < '0' || text[k] > '9') {
            return -1;
        }
        value = value * 10 + (text[k] - '0');
    }
    return value;
}

// An origin written DDDMMSSH, in degrees; fails naming `what` when it is not.
double originDegrees(const char* text, const char* positive, const char* negative, double limit,
                     const std::string& path, const char* what) {
    const int d = digitsValue(text, 3), m = digitsValue(text + 3, 2), s = digitsValue(text + 5, 2);
    const char h = text[7];
    const double degrees = d + m / 60.0 + s / 3600.0;
    if (d < 0 || m < 0 || s < 0 || m > 59 || s > 59 || (h != positive[0] && h != negative[0]) || degrees > limit) {
        fail(path, std::string("its UHL record's ") + what + " of origin \"" + printableText(std::string_view(text, 8)) +
                       "\" is not DDDMMSS and " + positive + " or " + negative);
    }
    return h == negative[0] ? -degrees : degrees;
}

// The header, when the file begins with a UHL record (after tape labels).
std::optional<Header> readHeader(const std::string& path) {
    const std::shared_ptr<const ByteSource> file = openFileSource(path);
    const uint64_t size = file->size();
    std::array<char, kLabelBytes> uhl{};
    uint64_t at = 0;
    for (;; at += kLabelBytes) {
        if (at + kLabelBytes > size) {
            return std::nullopt;
        }
        file->readAt(at, uhl.data(), kLabelBytes);
        if (std::memcmp(uhl.data(), "UHL1", 4) == 0) {
            break;
        }
        if (at >= 2 * kLabelBytes || (std::memcmp(uhl.data(), "VOL", 3) != 0 && std::memcmp(uhl.data(), "HDR", 3) != 0)) {
            return std::nullopt;
        }
    }
    std::array<char, 5> datum{};
    std::array<char, 3> dsi{}, acc{};
    if (size >= at + kHeaderBytes) {
        file->readAt(at + kLabelBytes, dsi.data(), 3);
        file->readAt(at + 728, acc.data(), 3);
        file->readAt(at + kDsiDatum, datum.data(), 5);
    }
    if (std::memcmp(dsi.data(), "DSI", 3) != 0 || std::memcmp(acc.data(), "ACC", 3) != 0) {
        fail(path, "a DTED file's UHL record must be followed by its DSI and ACC records (648 and 2700 bytes)");
    }
    Header h;
    RasterInfo& info = h.info;
    const double longitude = originDegrees(&uhl[4], "E", "W", 180.0, path, "longitude");
    const double latitude = originDegrees(&uhl[12], "N", "S", 90.0, path, "latitude");
    const int dx = digitsValue(&uhl[20], 4), dy = digitsValue(&uhl[24], 4);
    info.width = digitsValue(&uhl[47], 4);
    info.height = digitsValue(&uhl[51], 4);
    if (dx < 1 || dy < 1) {
        fail(path, "its UHL record's intervals \"" + printableText(std::string_view(&uhl[20], 8)) +
                       "\" are not two numbers of tenths of a second from 1");
    }
    if (info.width < 1 || info.height < 1) {
        fail(path, "its UHL record's counts of longitude lines and latitude points \"" +
                       printableText(std::string_view(&uhl[47], 8)) +
                       "\" are not two numbers from 1");
    }
    info.channels = 1;
    info.type = SampleType::Int16;
    info.formatName = "dted";
    info.nodata = kVoid;
    h.dataOffset = at + kHeaderBytes;
    h.recordBytes = 12 + 2 * static_cast<uint64_t>(info.height);
    const uint64_t needed = h.dataOffset + h.recordBytes * static_cast<uint64_t>(info.width);
    if (size < needed) {
        fail(path, "holds " + std::to_string(size) + " bytes, too few for the " + std::to_string(info.width) +
                       " columns of " + std::to_string(info.height) + " heights its UHL record gives (" +
                       std::to_string(needed) + " bytes)");
    }
    const std::string datumName(datum.data(), datum.size());
    int epsg = 4326;
    if (datumName == "WGS72") {
        epsg = 4322;
    } else if (datumName != "WGS84" && datumName != "     ") {
        fail(path, "its DSI record's horizontal datum \"" + printableText(datumName) + "\" is neither WGS84 nor WGS72");
    }
    // The posts are points: sample (x, y) is the point (lon + x dx, lat + (height - 1 - y) dy).
    const double stepX = dx / 36000.0, stepY = dy / 36000.0;
    const std::array<double, 6> t = {longitude - stepX / 2, stepX, 0.0,
                                     latitude + (info.height - 1) * stepY + stepY / 2, 0.0, -stepY};
    info.georeference = placedInEpsgCrs(epsg, t, path);
    if (info.georeference) {
        info.georeference->pixelIsPoint = true;
        info.georeference->heightUnit = HeightUnit{"metre", 1.0, "DTED"}; // the standard's unit
    }
    return h;
}

// The heights, a band of rows at a time: one pread per column, the band's part of its record.
class DtedDecoder : public DecodedRows::Decoder {
public:
    DtedDecoder(std::string path, const Header& header)
        : path_(std::move(path)), file_(openFileSource(path_)), header_(header), width_(header.info.width),
          height_(header.info.height), sums_(static_cast<size_t>(width_), 0),
          checksums_(static_cast<size_t>(width_), 0) {
        bandRows_ = static_cast<int>(std::clamp<size_t>(kBandBytes / (2 * static_cast<size_t>(width_)), 1,
                                                        static_cast<size_t>(height_)));
        band_.resize(static_cast<size_t>(bandRows_) * static_cast<size_t>(width_));
    }

    void readRow(uint8_t* row) override {
        if (row_ == bandEnd_) {
            readBand();
        }
        std::memcpy(row, &band_[static_cast<size_t>(row_ - bandStart_) * static_cast<size_t>(width_)],
                    static_cast<size_t>(width_) * 2);
        ++row_;
    }

    void finish() override {}

private:
    // Rows [row_, row_ + bandRows_) (fewer at the south edge): latitude points [j0, j1) of every
    // column. The north band also reads each record's checksum, the south band its first eight
    // bytes (sentinel, block and column numbers), and with the south band every byte of each
    // record has been summed.
    void readBand() {
        bandStart_ = row_;
        bandEnd_ = std::min(row_ + bandRows_, height_);
        const uint64_t j0 = static_cast<uint64_t>(height_ - bandEnd_), j1 = static_cast<uint64_t>(height_ - bandStart_);
        const bool north = bandStart_ == 0, south = bandEnd_ == height_;
        const uint64_t from = south ? 0 : 8 + 2 * j0;
        const uint64_t to = north ? header_.recordBytes : 8 + 2 * j1;
        column_.resize(static_cast<size_t>(to - from));
        const uint64_t samples = 8 + 2 * j0 - from; // where point j0 lies in column_
        for (int x = 0; x < width_; ++x) {
            const uint64_t record = header_.dataOffset + static_cast<uint64_t>(x) * header_.recordBytes;
            file_->readAt(record + from, column_.data(), column_.size()); // throws naming the file
            const size_t summed = column_.size() - (north ? 4 : 0);
            uint32_t& sum = sums_[static_cast<size_t>(x)];
            for (size_t k = 0; k < summed; ++k) {
                sum += column_[k];
            }
            if (north) {
                const uint8_t* c = &column_[summed];
                checksums_[static_cast<size_t>(x)] = (uint32_t{c[0]} << 24) | (uint32_t{c[1]} << 16) | (uint32_t{c[2]} << 8) | c[3];
            }
            if (south) {
                checkRecord(x);
            }
            const uint8_t* from16 = &column_[static_cast<size_t>(samples)];
            const int rows = bandEnd_ - bandStart_;
            for (int k = 0; k < rows; ++k) { // point j0 + k is row bandEnd_ - 1 - k
                band_[static_cast<size_t>(rows - 1 - k) * static_cast<size_t>(width_) + static_cast<size_t>(x)] =
                    height(from16[2 * k], from16[2 * k + 1]);
            }
        }
    }

    void checkRecord(int x) {
        const uint8_t* c = column_.data();
        const int number = (c[4] << 8) | c[5];
        if (c[0] != 0xAA || number != x) {
            fail(path_, "column " + std::to_string(x) + "'s record does not begin as DTED's records do (sentinel 0xAA, "
                            "column " + std::to_string(x) + "): a damaged file, or one whose UHL counts are wrong");
        }
        if (sums_[static_cast<size_t>(x)] != checksums_[static_cast<size_t>(x)]) {
            fail(path_, "column " + std::to_string(x) + "'s checksum does not match its record's bytes: a damaged file");
        }
    }

    // Sign and magnitude, big-endian; two's complement where a producer wrote that (see the header).
    static int16_t height(uint8_t high, uint8_t low) {
        const int magnitude = ((high & 0x7f) << 8) | low;
        if ((high & 0x80) == 0) {
            return static_cast<int16_t>(magnitude);
        }
        const int value = -magnitude;
        if (value < -16000 && value != kVoid) {
            return static_cast<int16_t>(static_cast<uint16_t>((high << 8) | low));
        }
        return static_cast<int16_t>(value);
    }

    std::string path_;
    std::shared_ptr<const ByteSource> file_;
    Header header_;
    int width_, height_;
    int bandRows_ = 1;
    int row_ = 0, bandStart_ = 0, bandEnd_ = 0;
    std::vector<int16_t> band_;   // rows [bandStart_, bandEnd_), north first
    std::vector<uint8_t> column_; // one column's part of the band, as the file holds it
    std::vector<uint32_t> sums_;  // each record's bytes summed so far
    std::vector<uint32_t> checksums_; // as the north band read them
};

} // namespace

std::optional<RasterInfo> describeDted(const std::string& path) {
    std::optional<Header> h = readHeader(path);
    return h ? std::optional<RasterInfo>(h->info) : std::nullopt;
}

std::unique_ptr<DecodedRows> openDted(const std::string& path, int cacheMegabytes) {
    const std::optional<Header> h = readHeader(path);
    if (!h) {
        return nullptr;
    }
    auto rows = std::make_unique<DecodedRows>(path, h->info, cacheMegabytes, 1);
    rows->start(std::make_unique<DtedDecoder>(path, *h));
    return rows;
}

} // namespace pyramid
