#include "formats/residual_context.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <cstring>

#include "formats/error.hpp"
#include "formats/residual_range_coder.hpp"

namespace pyramid {

namespace {

using context_coding::RangeDecoder;
using context_coding::RangeEncoder;

// The codec's constants: part of the format (doc/format.md, 1.8). Changing any of them changes
// every blob.
constexpr uint32_t kDirect = 32;                // zigzag values 0..31 are symbols of their own
constexpr uint32_t kSymbols = kDirect + 1;      // and symbol 32 escapes larger ones
// An escape's bit length - 1: 0..16 in version 0, 0..17 in version 1 (mode 2's values reach 79871).
template <int Version>
constexpr uint32_t kExponents = Version == 0 ? 17 : 18;
constexpr int kActivityBins = 14;
constexpr int kModels = kActivityBins * 4;      // activity bin x the sample's grid parity
constexpr uint32_t kIncrement = 24;             // a symbol's count grows by this when coded
constexpr uint32_t kTotalLimit = 1u << 16;      // counts are halved when their total passes it
constexpr size_t kHeaderBytes = 8;
constexpr uint8_t kVersion = 1;                 // the version the encoder writes

// Version 1's initial counts: in table 4B + p of a sample of odd column or row (p > 0), symbol
// z starts at 1 + floor(32 theta^m) with m = ceil(z / 2) (16 for the escape) and theta =
// kTheta[B] / 256, in the fixed point of initialCounts; samples of even column and row (p = 0)
// copy their parent, so their tables start with 33 for symbol 0 (theta = 0).
constexpr std::array<uint32_t, kActivityBins> kTheta = {8, 96, 140, 160, 180, 200, 220, 232, 238, 240, 242, 242, 242, 242};
constexpr uint32_t kPriorWeight = 32;

// Version 1's mode 2: a prediction of each residual from the residuals left (W), below (S),
// below-left (SW), below-right (SE), two left (WW) and two below (SS), with weights in 16ths
// per place in the upsampling grid: (x odd, y even), (x even, y odd), (x odd, y odd). Samples of
// even column and row are predicted as 0.
constexpr int kPredictionWeights[3][6] = {
    // W   S  SW  SE  WW  SS
    {0, 5, -2, -2, -4, -1},
    {10, 0, -2, 2, -3, -3},
    {12, 6, 0, 0, -3, -2},
};

// An adaptive frequency table: counts start as the version says, grow by kIncrement when their
// symbol is coded, and are halved (rounding up) when their total passes kTotalLimit, so that
// every total stays within the coder's 16 bits.
template <uint32_t N>
struct Model {
    std::array<uint32_t, N> count;
    uint32_t total = N;
    Model() { count.fill(1); }
    void start(const std::array<uint32_t, N>& counts) {
        count = counts;
        total = 0;
        for (const uint32_t c : count) {
            total += c;
        }
    }
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

// Version 1's initial counts of value table `table` (doc/format.md, 1.8).
std::array<uint32_t, kSymbols> initialCounts(int table) {
    const uint32_t theta = table % 4 == 0 ? 0 : kTheta[static_cast<size_t>(table / 4)];
    std::array<uint32_t, 17> weight{}; // kPriorWeight theta^m in 16.16 fixed point
    weight[0] = kPriorWeight << 16;
    for (size_t m = 1; m < weight.size(); ++m) {
        weight[m] = (weight[m - 1] * theta) >> 8;
    }
    std::array<uint32_t, kSymbols> counts{};
    for (uint32_t z = 0; z < kSymbols; ++z) {
        const uint32_t m = z == kDirect ? 16 : (z + 1) / 2;
        counts[z] = 1 + (weight[m] >> 16);
    }
    return counts;
}

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

// Mode 2's prediction (version 1): residuals outside the tile are 0; the weighted sum in 16ths,
// rounded by (sum + 8) >> 4 (an arithmetic shift: floor).
int32_t gridPrediction(const int32_t* r, int x, int y, int size) {
    const int parity = (x & 1) + 2 * (y & 1);
    if (parity == 0) {
        return 0;
    }
    const int* w = kPredictionWeights[parity - 1];
    const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
    const auto s = static_cast<size_t>(size);
    int32_t sum = 0;
    if (x > 0) {
        sum += w[0] * r[i - 1] + (y > 0 ? w[2] * r[i - s - 1] : 0);
    }
    if (y > 0) {
        sum += w[1] * r[i - s] + (x + 1 < size ? w[3] * r[i - s + 1] : 0);
    }
    if (x > 1) {
        sum += w[4] * r[i - 2];
    }
    if (y > 1) {
        sum += w[5] * r[i - 2 * s];
    }
    return (sum + 8) >> 4;
}

int32_t prediction(int mode, const int32_t* r, int x, int y, int size) {
    if (mode == 0) {
        return 0;
    }
    return mode == 1 ? medianPrediction(r, x, y, size) : gridPrediction(r, x, y, size);
}

// The table of a sample: the activity of the values already coded around it (left and lower
// twice, lower-left and lower-right once, and in version 1 two left and two below once; 0
// outside the tile), in bins of powers of two, and the sample's parity in the tile (even columns
// and rows copy the parent in the upsampling grid).
template <int Version>
int modelOf(const uint32_t* magnitude, int x, int y, int size) {
    const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
    const auto s = static_cast<size_t>(size);
    const uint32_t w = x > 0 ? magnitude[i - 1] : 0;
    const uint32_t south = y > 0 ? magnitude[i - s] : 0;
    const uint32_t sw = x > 0 && y > 0 ? magnitude[i - s - 1] : 0;
    const uint32_t se = y > 0 && x + 1 < size ? magnitude[i - s + 1] : 0;
    uint32_t activity = 2 * w + 2 * south + sw + se;
    if constexpr (Version >= 1) {
        activity += (x > 1 ? magnitude[i - 2] : 0) + (y > 1 ? magnitude[i - 2 * s] : 0);
    }
    const int bin = std::min(kActivityBins - 1, static_cast<int>(std::bit_width(activity)));
    return bin * 4 + (x & 1) + 2 * (y & 1);
}

template <int Version>
struct Models {
    std::vector<Model<kSymbols>> values = std::vector<Model<kSymbols>>(kModels);
    // One escape table in version 0; one per two activity bins in version 1.
    std::vector<Model<kExponents<Version>>> exponents =
        std::vector<Model<kExponents<Version>>>(Version == 0 ? 1 : kActivityBins / 2);
    Models() {
        if constexpr (Version >= 1) {
            static const std::vector<std::array<uint32_t, kSymbols>> initial = [] {
                std::vector<std::array<uint32_t, kSymbols>> t;
                for (int k = 0; k < kModels; ++k) {
                    t.push_back(initialCounts(k));
                }
                return t;
            }();
            for (size_t k = 0; k < values.size(); ++k) {
                values[k].start(initial[k]);
            }
        }
    }
    Model<kExponents<Version>>& exponentsOf(int table) { return exponents[Version == 0 ? 0 : static_cast<size_t>(table / 8)]; }
};

template <uint32_t N>
uint32_t decodeSymbol(RangeDecoder& coder, Model<N>& m) {
    const uint32_t v = coder.decodeFrequency(m.total);
    uint32_t s = 0, cum = 0;
    while (cum + m.count[s] <= v) {
        cum += m.count[s];
        ++s;
    }
    coder.consume(cum, m.count[s]);
    m.update(s);
    return s;
}

// Equally likely bits: at most 16 in one interval (version 0 never needs more); version 1's
// 17-bit escapes code their bit 16 first, then the low 16.
void encodeLowBits(RangeEncoder& coder, uint32_t value, int bits) {
    if (bits > 16) {
        coder.encodeBits(value >> 16, bits - 16);
        coder.encodeBits(value & 0xFFFFu, 16);
        return;
    }
    coder.encodeBits(value, bits);
}
uint32_t decodeLowBits(RangeDecoder& coder, int bits) {
    if (bits > 16) {
        const uint32_t high = coder.decodeBits(bits - 16);
        return (high << 16) | coder.decodeBits(16);
    }
    return coder.decodeBits(bits);
}

template <int Version>
std::vector<uint8_t> encodeMode(std::span<const int16_t> residuals, int size, uint8_t mode) {
    const size_t n = residuals.size();
    std::vector<int32_t> r(residuals.begin(), residuals.end());
    std::vector<uint32_t> magnitude(n);
    std::vector<uint8_t> out = {kContextResidualMagic[0], kContextResidualMagic[1], kContextResidualMagic[2],
                                kContextResidualMagic[3], static_cast<uint8_t>(size & 0xff),
                                static_cast<uint8_t>(size >> 8), mode, static_cast<uint8_t>(Version)};
    out.reserve(n + kHeaderBytes);
    RangeEncoder coder(out);
    Models<Version> models;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
            const int32_t v = r[i] - prediction(mode, r.data(), x, y, size);
            magnitude[i] = static_cast<uint32_t>(std::abs(v));
            const int table = modelOf<Version>(magnitude.data(), x, y, size);
            Model<kSymbols>& m = models.values[static_cast<size_t>(table)];
            const uint32_t z = zigzag(v);
            if (z < kDirect) {
                coder.encode(m.cumulative(z), m.count[z], m.total);
                m.update(z);
                continue;
            }
            coder.encode(m.cumulative(kDirect), m.count[kDirect], m.total);
            m.update(kDirect);
            const uint32_t e = z - kDirect + 1; // 1 .. 2^18 - 1
            const int k = static_cast<int>(std::bit_width(e)) - 1;
            Model<kExponents<Version>>& exponents = models.exponentsOf(table);
            coder.encode(exponents.cumulative(static_cast<uint32_t>(k)), exponents.count[static_cast<size_t>(k)],
                         exponents.total);
            exponents.update(static_cast<uint32_t>(k));
            encodeLowBits(coder, e & ((1u << k) - 1u), k);
        }
    }
    coder.finish();
    return out;
}

template <int Version>
std::vector<int16_t> decodeMode(std::span<const uint8_t> blob, int size, uint8_t mode, const std::string& where) {
    const size_t n = static_cast<size_t>(size) * static_cast<size_t>(size);
    std::vector<int32_t> r(n);
    std::vector<uint32_t> magnitude(n);
    RangeDecoder coder(blob.subspan(kHeaderBytes), where);
    Models<Version> models;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
            const int table = modelOf<Version>(magnitude.data(), x, y, size);
            Model<kSymbols>& m = models.values[static_cast<size_t>(table)];
            uint32_t z = decodeSymbol(coder, m);
            if (z == kDirect) {
                const auto k = static_cast<int>(decodeSymbol(coder, models.exponentsOf(table)));
                const uint32_t e = (1u << k) | decodeLowBits(coder, k);
                z = kDirect + e - 1;
            }
            const int32_t v = unzigzag(z);
            magnitude[i] = static_cast<uint32_t>(std::abs(v));
            const int32_t value = v + prediction(mode, r.data(), x, y, size);
            if (value < -32768 || value > 32767) {
                fail(where, "context-coded residual tile: a residual of " + std::to_string(value) + " is beyond int16");
            }
            r[i] = value;
        }
    }
    coder.finish();
    return std::vector<int16_t>(r.begin(), r.end());
}

} // namespace

bool isContextResidualBlob(std::span<const uint8_t> blob) {
    return blob.size() >= 4 && std::memcmp(blob.data(), kContextResidualMagic, 4) == 0;
}

std::vector<uint8_t> encodeContextResiduals(std::span<const int16_t> residuals, int size) {
    return encodeContextResiduals(residuals, size, kVersion);
}

std::vector<uint8_t> encodeContextResiduals(std::span<const int16_t> residuals, int size, int version, int mode) {
    if (size < 1 || size > 65535 || residuals.size() != static_cast<size_t>(size) * static_cast<size_t>(size)) {
        fail("", "residual tile: buffer does not match " + std::to_string(size) + "x" + std::to_string(size));
    }
    if (version < 0 || version > 1 || mode < -1 || mode > version + 1) {
        fail("", "context-coded residual tile: no mode " + std::to_string(mode) + " in version " + std::to_string(version));
    }
    const auto encode = [&](int m) {
        return version == 0 ? encodeMode<0>(residuals, size, static_cast<uint8_t>(m))
                            : encodeMode<1>(residuals, size, static_cast<uint8_t>(m));
    };
    if (mode >= 0) {
        return encode(mode);
    }
    // Every mode of the version in order, the first of equal sizes kept.
    std::vector<uint8_t> best = encode(0);
    for (int m = 1; m <= version + 1; ++m) {
        std::vector<uint8_t> other = encode(m);
        if (other.size() < best.size()) {
            best = std::move(other);
        }
    }
    return best;
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
    const uint8_t version = blob[7];
    if (version > 1 || mode > version + 1) {
        fail(where, "context-coded residual tile of an unknown kind (mode " + std::to_string(mode) + ", version " +
                        std::to_string(version) + ")");
    }
    return version == 0 ? decodeMode<0>(blob, size, mode, where) : decodeMode<1>(blob, size, mode, where);
}

} // namespace pyramid
