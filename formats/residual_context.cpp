#include "formats/residual_context.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <cstring>

#include "formats/error.hpp"

namespace pyramid {

namespace {

// The codec's constants: part of the format (doc/format.md, 1.8). Changing any of them changes
// every blob.
constexpr uint32_t kDirect = 32;                // zigzag values 0..31 are symbols of their own
constexpr uint32_t kSymbols = kDirect + 1;      // and symbol 32 escapes larger ones
constexpr uint32_t kExponents = 17;             // an escape's bit length - 1: 0..16
constexpr int kActivityBins = 14;
constexpr int kModels = kActivityBins * 4;      // activity bin x the sample's grid parity
constexpr uint32_t kIncrement = 24;             // a symbol's count grows by this when coded
constexpr uint32_t kTotalLimit = 1u << 16;      // counts are halved when their total passes it
constexpr size_t kHeaderBytes = 8;
constexpr uint32_t kTop = 1u << 24;             // the coder renormalises below this range

// An adaptive frequency table: counts start at 1, grow by kIncrement when their symbol is
// coded, and are halved (rounding up) when their total passes kTotalLimit, so that every total
// stays within the coder's 16 bits.
template <uint32_t N>
struct Model {
    std::array<uint32_t, N> count;
    uint32_t total = N;
    Model() { count.fill(1); }
    void update(uint32_t s) {
        count[s] += kIncrement;
        total += kIncrement;
        if (total > kTotalLimit) {
            total = 0;
            for (uint32_t& c : count) {
                c = (c + 1) / 2;
                total += c;
            }
        }
    }
    uint32_t cumulative(uint32_t s) const {
        uint32_t sum = 0;
        for (uint32_t k = 0; k < s; ++k) {
            sum += count[k];
        }
        return sum;
    }
};

// A range coder with carry propagation: 32-bit range, 64-bit low, bytes out most significant
// first. The first byte it writes is always 0.
class RangeEncoder {
public:
    explicit RangeEncoder(std::vector<uint8_t>& out) : out_(out) {}
    void encode(uint32_t cum, uint32_t freq, uint32_t total) {
        const uint32_t r = range_ / total;
        low_ += static_cast<uint64_t>(r) * cum;
        range_ = r * freq;
        while (range_ < kTop) {
            range_ <<= 8;
            shiftLow();
        }
    }
    template <uint32_t N>
    void encode(Model<N>& m, uint32_t s) {
        encode(m.cumulative(s), m.count[s], m.total);
        m.update(s);
    }
    // `bits` (at most 16) equally likely bits.
    void encodeBits(uint32_t value, int bits) {
        if (bits > 0) {
            encode(value, 1, 1u << bits);
        }
    }
    void finish() {
        for (int k = 0; k < 5; ++k) {
            shiftLow();
        }
    }

private:
    void shiftLow() {
        if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
            const auto carry = static_cast<uint8_t>(low_ >> 32);
            uint8_t byte = cache_;
            do {
                out_.push_back(static_cast<uint8_t>(byte + carry));
                byte = 0xFF;
            } while (--pending_ != 0);
            cache_ = static_cast<uint8_t>(low_ >> 24);
        }
        ++pending_;
        low_ = (low_ & 0x00FFFFFFu) << 8;
    }

    std::vector<uint8_t>& out_;
    uint64_t low_ = 0;
    uint32_t range_ = 0xFFFFFFFFu;
    uint8_t cache_ = 0;
    uint64_t pending_ = 1;
};

class RangeDecoder {
public:
    RangeDecoder(std::span<const uint8_t> bytes, const std::string& where) : in_(bytes), where_(where) {
        if (in_.size() < 5 || in_[0] != 0) {
            fail(where_, "context-coded residual tile: damaged stream start");
        }
        for (int k = 0; k < 5; ++k) {
            code_ = (code_ << 8) | next();
        }
    }
    uint32_t decodeFrequency(uint32_t total) {
        r_ = range_ / total;
        return std::min(code_ / r_, total - 1);
    }
    void consume(uint32_t cum, uint32_t freq) {
        code_ -= r_ * cum;
        range_ = r_ * freq;
        while (range_ < kTop) {
            range_ <<= 8;
            code_ = (code_ << 8) | next();
        }
    }
    template <uint32_t N>
    uint32_t decode(Model<N>& m) {
        const uint32_t v = decodeFrequency(m.total);
        uint32_t s = 0, cum = 0;
        while (cum + m.count[s] <= v) {
            cum += m.count[s];
            ++s;
        }
        consume(cum, m.count[s]);
        m.update(s);
        return s;
    }
    uint32_t decodeBits(int bits) {
        if (bits == 0) {
            return 0;
        }
        const uint32_t v = decodeFrequency(1u << bits);
        consume(v, 1);
        return v;
    }
    // Every byte read, none beyond the end.
    void finish() const {
        if (overrun_) {
            fail(where_, "context-coded residual tile: the stream ends early");
        }
        if (pos_ != in_.size()) {
            fail(where_, "context-coded residual tile: " + std::to_string(in_.size() - pos_) +
                             " bytes after the end of the stream");
        }
    }

private:
    uint32_t next() {
        if (pos_ < in_.size()) {
            return in_[pos_++];
        }
        overrun_ = true;
        return 0;
    }

    std::span<const uint8_t> in_;
    const std::string& where_;
    size_t pos_ = 0;
    bool overrun_ = false;
    uint32_t code_ = 0;
    uint32_t range_ = 0xFFFFFFFFu;
    uint32_t r_ = 1;
};

uint32_t zigzag(int32_t v) { return v >= 0 ? 2u * static_cast<uint32_t>(v) : 2u * static_cast<uint32_t>(-v) - 1u; }
int32_t unzigzag(uint32_t z) {
    return (z & 1u) != 0 ? -static_cast<int32_t>((z + 1u) / 2u) : static_cast<int32_t>(z / 2u);
}

// The median predictor of a sample from its left (a), lower (b) and lower-left (c) neighbours
// in storage order; on the first row and column the missing ones are taken as doc/format.md
// says: a = b on the first column, b = c = a on the first row, and 0 for the first sample.
int32_t medianPrediction(const int32_t* r, int x, int y, int size) {
    const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
    const auto s = static_cast<size_t>(size);
    const int32_t a = x > 0 ? r[i - 1] : (y > 0 ? r[i - s] : 0);
    const int32_t b = y > 0 ? r[i - s] : a;
    const int32_t c = x > 0 && y > 0 ? r[i - s - 1] : a;
    if (c >= std::max(a, b)) {
        return std::min(a, b);
    }
    if (c <= std::min(a, b)) {
        return std::max(a, b);
    }
    return a + b - c;
}

// The model of a sample: the activity of the values already coded around it (left and lower
// twice, lower-left and lower-right once; 0 outside the tile), in bins of powers of two, and the
// sample's parity in the tile (even columns and rows copy the parent in the upsampling grid).
int modelOf(const uint32_t* magnitude, int x, int y, int size) {
    const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
    const auto s = static_cast<size_t>(size);
    const uint32_t w = x > 0 ? magnitude[i - 1] : 0;
    const uint32_t south = y > 0 ? magnitude[i - s] : 0;
    const uint32_t sw = x > 0 && y > 0 ? magnitude[i - s - 1] : 0;
    const uint32_t se = y > 0 && x + 1 < size ? magnitude[i - s + 1] : 0;
    const uint32_t activity = 2 * w + 2 * south + sw + se;
    const int bin = std::min(kActivityBins - 1, static_cast<int>(std::bit_width(activity)));
    return bin * 4 + (x & 1) + 2 * (y & 1);
}

struct Models {
    std::vector<Model<kSymbols>> values = std::vector<Model<kSymbols>>(kModels);
    Model<kExponents> exponents;
};

std::vector<uint8_t> encodeMode(std::span<const int16_t> residuals, int size, uint8_t mode) {
    const size_t n = residuals.size();
    std::vector<int32_t> r(residuals.begin(), residuals.end());
    std::vector<uint32_t> magnitude(n);
    std::vector<uint8_t> out = {kContextResidualMagic[0], kContextResidualMagic[1], kContextResidualMagic[2],
                                kContextResidualMagic[3], static_cast<uint8_t>(size & 0xff),
                                static_cast<uint8_t>(size >> 8), mode, 0};
    out.reserve(n + kHeaderBytes);
    RangeEncoder coder(out);
    Models models;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
            const int32_t v = mode == 0 ? r[i] : r[i] - medianPrediction(r.data(), x, y, size);
            magnitude[i] = static_cast<uint32_t>(std::abs(v));
            Model<kSymbols>& m = models.values[static_cast<size_t>(modelOf(magnitude.data(), x, y, size))];
            const uint32_t z = zigzag(v);
            if (z < kDirect) {
                coder.encode(m, z);
                continue;
            }
            coder.encode(m, kDirect);
            const uint32_t e = z - kDirect + 1; // 1 .. 2^17 - 1
            const int k = static_cast<int>(std::bit_width(e)) - 1;
            coder.encode(models.exponents, static_cast<uint32_t>(k));
            coder.encodeBits(e & ((1u << k) - 1u), k);
        }
    }
    coder.finish();
    return out;
}

} // namespace

bool isContextResidualBlob(std::span<const uint8_t> blob) {
    return blob.size() >= 4 && std::memcmp(blob.data(), kContextResidualMagic, 4) == 0;
}

std::vector<uint8_t> encodeContextResiduals(std::span<const int16_t> residuals, int size) {
    if (size < 1 || size > 65535 || residuals.size() != static_cast<size_t>(size) * static_cast<size_t>(size)) {
        fail("", "residual tile: buffer does not match " + std::to_string(size) + "x" + std::to_string(size));
    }
    std::vector<uint8_t> plain = encodeMode(residuals, size, 0);
    std::vector<uint8_t> predicted = encodeMode(residuals, size, 1);
    return predicted.size() < plain.size() ? predicted : plain;
}

std::vector<int16_t> decodeContextResiduals(std::span<const uint8_t> blob, int size, const std::string& where) {
    if (blob.size() < kHeaderBytes || !isContextResidualBlob(blob)) {
        fail(where, "not a context-coded residual tile");
    }
    const int stored = blob[4] | (blob[5] << 8);
    if (stored != size) {
        fail(where, "context-coded residual tile of " + std::to_string(stored) + " samples a side, expected " +
                        std::to_string(size));
    }
    const uint8_t mode = blob[6];
    if (mode > 1 || blob[7] != 0) {
        fail(where, "context-coded residual tile of an unknown kind (mode " + std::to_string(mode) + ", version " +
                        std::to_string(blob[7]) + ")");
    }
    const size_t n = static_cast<size_t>(size) * static_cast<size_t>(size);
    std::vector<int32_t> r(n);
    std::vector<uint32_t> magnitude(n);
    RangeDecoder coder(blob.subspan(kHeaderBytes), where);
    Models models;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
            Model<kSymbols>& m = models.values[static_cast<size_t>(modelOf(magnitude.data(), x, y, size))];
            uint32_t z = coder.decode(m);
            if (z == kDirect) {
                const auto k = static_cast<int>(coder.decode(models.exponents));
                const uint32_t e = (1u << k) | coder.decodeBits(k);
                z = kDirect + e - 1;
            }
            const int32_t v = unzigzag(z);
            magnitude[i] = static_cast<uint32_t>(std::abs(v));
            const int32_t value = mode == 0 ? v : v + medianPrediction(r.data(), x, y, size);
            if (value < -32768 || value > 32767) {
                fail(where, "context-coded residual tile: a residual of " + std::to_string(value) + " is beyond int16");
            }
            r[i] = value;
        }
    }
    coder.finish();
    return std::vector<int16_t>(r.begin(), r.end());
}

} // namespace pyramid
