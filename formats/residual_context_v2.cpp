#include "formats/residual_context_v2.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <memory>

#include "formats/error.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_context_models.hpp"
#include "formats/residual_range_coder.hpp"

namespace pyramid::context_coding {

namespace {

// Version 2's constants (doc/format.md, 1.8).
constexpr uint32_t kDirectMagnitudes = 16;             // magnitudes 0..15 are symbols of their own
constexpr uint32_t kMagnitudes = kDirectMagnitudes + 1; // and symbol 16 escapes larger ones
constexpr uint32_t kExponents = 17;                     // an escape's bit length - 1: 0..16
constexpr int kModelledBits = 4;                        // the top bits below an escape's leading one
constexpr size_t kPrefixes = size_t{1} << kModelledBits;
constexpr size_t kEscapeTables = kActivityBins / 2;
constexpr size_t kSignContexts = 4 * 27 * 3;
// Version 3's parent mode: a sample's neighbours' shadows within this of each other are flat; a
// shadow prediction must have done this much better than the grid predictor on the four nearest
// samples of the same place in the grid to be chosen where they are not; predictions are held
// within +-kPredictionLimit.
constexpr int32_t kFlatSpread = 1;
constexpr uint32_t kSwitchMargin = 32;
constexpr int64_t kPredictionLimit = 65536;

// Version 2's tables (one set), or version 3's (three: the grid predictor, a flat neighbourhood,
// the shadow predictor chosen by past errors).
template <size_t Sets>
struct Models {
    std::array<Model<kMagnitudes>, kModels * Sets> magnitudes;
    std::array<Model<kExponents>, kEscapeTables> exponents;
    std::array<BitModel, kEscapeTables * kExponents * kPrefixes> bits;
    std::array<BitModel, kSignContexts * Sets> signs;
    Models() {
        static const std::array<std::array<uint32_t, kMagnitudes>, kModels> initial = [] {
            std::array<std::array<uint32_t, kMagnitudes>, kModels> t{};
            for (int k = 0; k < kModels; ++k) {
                const std::array<uint32_t, 17> weight = priorWeights(k);
                t[static_cast<size_t>(k)][0] = 1 + (weight[0] >> 16);
                for (size_t q = 1; q < kMagnitudes; ++q) {
                    t[static_cast<size_t>(k)][q] = 2 * (1 + (weight[q] >> 16));
                }
            }
            return t;
        }();
        for (size_t k = 0; k < magnitudes.size(); ++k) {
            magnitudes[k].start(initial[k % kModels]);
        }
    }
};

int signOf(int32_t v) { return (v > 0) - (v < 0); }

// The tile's residuals, values and magnitudes so far, each in a plane with two columns of zeros
// on the left, three on the right and two rows below: a sample's neighbours outside the tile read
// 0, as the format says, without a test. The parent mode also keeps the shadows and each
// predictor's errors.
struct Planes {
    int size;
    size_t stride;
    std::vector<int32_t> residual, value, shadow;
    std::vector<uint32_t> magnitude, gridError, shadowError;
    const int32_t* parent = nullptr; // the parent plane, size x size (mode 3)
    Planes(int size_, bool parentMode)
        : size(size_), stride(static_cast<size_t>(size_) + 5), residual(stride * (static_cast<size_t>(size_) + 2)),
          value(residual.size()), shadow(parentMode ? residual.size() : 0), magnitude(residual.size()),
          gridError(shadow.size()), shadowError(shadow.size()) {}
    size_t at(int x, int y) const { return (static_cast<size_t>(y) + 2) * stride + static_cast<size_t>(x) + 2; }
};

// What a sample's coding depends on, from the values coded before it.
struct Context {
    int32_t prediction;
    size_t table;
    size_t sign;      // the sign context without the magnitude class
    int32_t grid = 0; // mode 3: the grid predictor's and the shadow predictor's predictions
    int32_t fromShadow = 0;
};

int32_t limitPrediction(int64_t p) { return static_cast<int32_t>(std::clamp(p, -kPredictionLimit, kPredictionLimit)); }

// Shadows reach +-(2^30 + 2^15): their sums and differences are taken in 64 bits.
int64_t median(int64_t a, int64_t b, int64_t c) {
    return c >= std::max(a, b) ? std::min(a, b) : (c <= std::min(a, b) ? std::max(a, b) : a + b - c);
}

// Mode 3: the shadow predictor (the median predictor over the neighbours' shadows, less the
// sample's parent plane) and the set of tables it codes with.
[[gnu::always_inline]] inline Context parentContext(const Planes& planes, size_t i, int x, int y, int32_t grid,
                                                   uint32_t activity) {
    const size_t s = planes.stride;
    const int32_t* h = planes.shadow.data();
    const int32_t g = planes.parent[static_cast<size_t>(y) * static_cast<size_t>(planes.size) + static_cast<size_t>(x)];
    int64_t w = h[i - 1], south = h[i - s], sw = h[i - s - 1], se = h[i - s + 1];
    if (x == 0) {
        w = sw = south;
    }
    if (y == 0) {
        south = sw = se = w;
    }
    if (x + 1 == planes.size) {
        se = south;
    }
    if (x == 0 && y == 0) {
        w = south = sw = se = g;
    }
    const int32_t fromShadow = limitPrediction(median(w, south, sw) - g);
    size_t set = 0;
    int32_t p = grid;
    const int64_t spread = std::max(std::max(w, south), std::max(sw, se)) - std::min(std::min(w, south), std::min(sw, se));
    if (x > 0 && y > 0 && x + 1 < planes.size && spread <= kFlatSpread) {
        set = 1;
        p = fromShadow;
    } else {
        const auto past = [&](const std::vector<uint32_t>& e) {
            return e[i - 2] + e[i - 2 * s] + e[i - 2 * s - 2] + e[i - 2 * s + 2];
        };
        if (past(planes.shadowError) + kSwitchMargin < past(planes.gridError)) {
            set = 2;
            p = fromShadow;
        }
    }
    if (set != 1) {
        activity += static_cast<uint32_t>(std::abs(p));
    }
    activity += 2 * static_cast<uint32_t>(std::abs(fromShadow - grid));
    const int parity = (x & 1) + 2 * (y & 1);
    const int west = signOf(planes.value[i - 1]);
    const int below = signOf(planes.value[i - s]);
    const auto sign = static_cast<size_t>(((parity * 3 + west + 1) * 3 + below + 1) * 3 + signOf(p) + 1) * 3;
    return {p, static_cast<size_t>(tableOf(activity, x, y)) + set * kModels, sign + set * kSignContexts, grid, fromShadow};
}

template <int Mode>
[[gnu::always_inline]] inline Context contextOf(const Planes& planes, size_t i, int x, int y) {
    const size_t s = planes.stride;
    const int32_t* r = planes.residual.data();
    const int parity = (x & 1) + 2 * (y & 1);
    int32_t p = 0;
    if constexpr (Mode == 1) { // the median predictor, with its own rules on the first row and column
        const int32_t a = x > 0 ? r[i - 1] : (y > 0 ? r[i - s] : 0);
        const int32_t b = y > 0 ? r[i - s] : a;
        const int32_t c = x > 0 && y > 0 ? r[i - s - 1] : a;
        p = c >= std::max(a, b) ? std::min(a, b) : (c <= std::min(a, b) ? std::max(a, b) : a + b - c);
    } else if constexpr (Mode >= 2) {
        if (parity != 0) {
            const int* w = kPredictionWeights[parity - 1];
            p = (w[0] * r[i - 1] + w[1] * r[i - s] + w[2] * r[i - s - 1] + w[3] * r[i - s + 1] + w[4] * r[i - 2] +
                 w[5] * r[i - 2 * s] + 8) >> 4;
        }
    }
    const uint32_t* m = planes.magnitude.data();
    uint32_t activity = 2 * m[i - 1] + 2 * m[i - s] + m[i - s - 1] + m[i - s + 1] + m[i - 2] + m[i - 2 * s];
    if constexpr (Mode == 3) {
        return parentContext(planes, i, x, y, p, activity);
    }
    if constexpr (Mode == 2) {
        activity += static_cast<uint32_t>(std::abs(p));
    }
    const int west = signOf(planes.value[i - 1]);
    const int south = signOf(planes.value[i - s]);
    const auto sign = static_cast<size_t>(((parity * 3 + west + 1) * 3 + south + 1) * 3 + signOf(p) + 1) * 3;
    return {p, static_cast<size_t>(tableOf(activity, x, y)), sign};
}

size_t magnitudeClass(uint32_t a) { return (a > 2 ? 1u : 0u) + (a > 8 ? 1u : 0u); }

template <uint32_t N>
[[gnu::always_inline]] inline uint32_t decodeSymbol(RangeDecoder& coder, Model<N>& m) {
    const uint32_t s = coder.decodeSymbol(m.count, m.total);
    m.update(s);
    return s;
}

// Mode 3 keeps each sample's shadow and both predictors' errors for the samples after it.
[[gnu::always_inline]] inline void keepParentState(Planes& planes, size_t i, int x, int y, int32_t residual, const Context& c) {
    planes.shadow[i] = planes.parent[static_cast<size_t>(y) * static_cast<size_t>(planes.size) + static_cast<size_t>(x)] + residual;
    planes.gridError[i] = static_cast<uint32_t>(std::abs(residual - c.grid));
    planes.shadowError[i] = static_cast<uint32_t>(std::abs(residual - c.fromShadow));
}

template <int Mode>
using ModelsOf = Models<Mode == 3 ? 3 : 1>;

template <int Mode>
void encodeSamples(std::span<const int16_t> residuals, int size, const int32_t* parent, RangeEncoder& coder) {
    Planes planes(size, Mode == 3);
    planes.parent = parent;
    const auto models = std::make_unique<ModelsOf<Mode>>();
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = planes.at(x, y);
            const int32_t residual = residuals[static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)];
            planes.residual[i] = residual;
            const Context c = contextOf<Mode>(planes, i, x, y);
            const int32_t v = residual - c.prediction;
            const auto a = static_cast<uint32_t>(std::abs(v));
            planes.value[i] = v;
            planes.magnitude[i] = a;
            if constexpr (Mode == 3) {
                keepParentState(planes, i, x, y, residual, c);
            }
            Model<kMagnitudes>& m = models->magnitudes[c.table];
            const uint32_t symbol = std::min(a, kDirectMagnitudes);
            coder.encode(m.cumulative(symbol), m.count[symbol], m.total);
            m.update(symbol);
            if (symbol == kDirectMagnitudes) {
                const uint32_t e = a - kDirectMagnitudes + 1; // 1 .. 2^17 - 1
                const auto k = static_cast<uint32_t>(std::bit_width(e)) - 1;
                const size_t escapes = (c.table % kModels) / 8;
                Model<kExponents>& exponents = models->exponents[escapes];
                coder.encode(exponents.cumulative(k), exponents.count[k], exponents.total);
                exponents.update(k);
                const int modelled = std::min(static_cast<int>(k), kModelledBits);
                size_t prefix = 1;
                for (int j = 0; j < modelled; ++j) {
                    const int bit = static_cast<int>((e >> (k - 1 - static_cast<uint32_t>(j))) & 1u);
                    coder.encodeBit(models->bits[(escapes * kExponents + k) * kPrefixes + prefix], bit);
                    prefix = prefix * 2 + static_cast<size_t>(bit);
                }
                const int rest = static_cast<int>(k) - modelled;
                coder.encodeBits(e & ((1u << rest) - 1u), rest);
            }
            if (a != 0) {
                coder.encodeBit(models->signs[c.sign + magnitudeClass(a)], v < 0 ? 1 : 0);
            }
        }
    }
}

template <int Mode>
std::vector<int16_t> decodeSamples(RangeDecoder& coder, int size, const int32_t* parent, const std::string& where) {
    Planes planes(size, Mode == 3);
    planes.parent = parent;
    const auto models = std::make_unique<ModelsOf<Mode>>();
    std::vector<int16_t> out(static_cast<size_t>(size) * static_cast<size_t>(size));
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = planes.at(x, y);
            const Context c = contextOf<Mode>(planes, i, x, y);
            uint32_t a = decodeSymbol(coder, models->magnitudes[c.table]);
            if (a == kDirectMagnitudes) {
                const size_t escapes = (c.table % kModels) / 8;
                const uint32_t k = decodeSymbol(coder, models->exponents[escapes]);
                const int modelled = std::min(static_cast<int>(k), kModelledBits);
                size_t prefix = 1;
                for (int j = 0; j < modelled; ++j) {
                    const int bit = coder.decodeBit(models->bits[(escapes * kExponents + k) * kPrefixes + prefix]);
                    prefix = prefix * 2 + static_cast<size_t>(bit);
                }
                const int rest = static_cast<int>(k) - modelled;
                const uint32_t e = (static_cast<uint32_t>(prefix) << rest) | coder.decodeBits(rest);
                a = kDirectMagnitudes + e - 1;
            }
            auto v = static_cast<int32_t>(a);
            if (a != 0) {
                const int32_t negative = coder.decodeBit(models->signs[c.sign + magnitudeClass(a)]);
                v = (v ^ -negative) + negative;
            }
            const int32_t residual = v + c.prediction;
            if (residual < -32768 || residual > 32767) {
                fail(where, "context-coded residual tile: a residual of " + std::to_string(residual) + " is beyond int16");
            }
            planes.residual[i] = residual;
            planes.value[i] = v;
            planes.magnitude[i] = a;
            if constexpr (Mode == 3) {
                keepParentState(planes, i, x, y, residual, c);
            }
            out[static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)] = static_cast<int16_t>(residual);
        }
    }
    return out;
}

} // namespace

std::vector<uint8_t> encodeVersion2(std::span<const int16_t> residuals, int size, uint8_t mode) {
    std::vector<uint8_t> out = {kContextResidualMagic[0], kContextResidualMagic[1], kContextResidualMagic[2],
                                kContextResidualMagic[3], static_cast<uint8_t>(size & 0xff),
                                static_cast<uint8_t>(size >> 8), mode, 2};
    out.reserve(residuals.size() / 2 + kHeaderBytes);
    RangeEncoder coder(out);
    if (mode == 0) {
        encodeSamples<0>(residuals, size, nullptr, coder);
    } else if (mode == 1) {
        encodeSamples<1>(residuals, size, nullptr, coder);
    } else {
        encodeSamples<2>(residuals, size, nullptr, coder);
    }
    coder.finish();
    return out;
}

std::vector<int16_t> decodeVersion2(std::span<const uint8_t> blob, int size, uint8_t mode, const std::string& where) {
    RangeDecoder coder(blob.subspan(kHeaderBytes), where);
    std::vector<int16_t> out = mode == 0   ? decodeSamples<0>(coder, size, nullptr, where)
                               : mode == 1 ? decodeSamples<1>(coder, size, nullptr, where)
                                           : decodeSamples<2>(coder, size, nullptr, where);
    coder.finish();
    return out;
}

std::vector<uint8_t> encodeParentMode(std::span<const int16_t> residuals, int size, std::span<const int32_t> parent) {
    std::vector<uint8_t> out = {kContextResidualMagic[0], kContextResidualMagic[1], kContextResidualMagic[2],
                                kContextResidualMagic[3], static_cast<uint8_t>(size & 0xff),
                                static_cast<uint8_t>(size >> 8), 3, 3};
    out.reserve(residuals.size() / 2 + kHeaderBytes);
    RangeEncoder coder(out);
    encodeSamples<3>(residuals, size, parent.data(), coder);
    coder.finish();
    return out;
}

std::vector<int16_t> decodeParentMode(std::span<const uint8_t> blob, int size, std::span<const int32_t> parent,
                                      const std::string& where) {
    RangeDecoder coder(blob.subspan(kHeaderBytes), where);
    std::vector<int16_t> out = decodeSamples<3>(coder, size, parent.data(), where);
    coder.finish();
    return out;
}

} // namespace pyramid::context_coding
