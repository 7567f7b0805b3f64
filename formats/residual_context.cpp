// Context-coded residual tiles (doc/format.md, 1.8): the public entry points, and the coder of
// versions 0 and 1 (versions 2 and 3, the parent modes, are in residual_context_v2.cpp, the shared parts in
// residual_context_models.hpp).
#include "formats/residual_context.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <cstring>

#include "formats/error.hpp"
#include "formats/residual_context_models.hpp"
#include "formats/residual_context_v2.hpp"
#include "formats/residual_range_coder.hpp"

namespace pyramid {

namespace {

using namespace context_coding;

// An escape's bit length - 1: 0..16 in version 0, 0..17 in version 1 (mode 2's values reach 79871).
template <int Version>
constexpr uint32_t kExponents = Version == 0 ? 17 : 18;
constexpr uint8_t kVersion = 2; // the version the encoder writes

template <int Version>
int modelOf(const uint32_t* magnitude, int x, int y, int size) {
    return tableOf(activityOf<Version>(magnitude, x, y, size), x, y);
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
    if (version < 0 || version > 2 || mode < -1 || mode > std::min(version, 1) + 1) {
        fail("", "context-coded residual tile: no mode " + std::to_string(mode) + " in version " + std::to_string(version));
    }
    const auto encode = [&](int m) {
        const auto u = static_cast<uint8_t>(m);
        return version == 0 ? encodeMode<0>(residuals, size, u)
                            : version == 1 ? encodeMode<1>(residuals, size, u) : encodeVersion2(residuals, size, u);
    };
    if (mode >= 0) {
        return encode(mode);
    }
    // Every mode of the version in order, the first of equal sizes kept.
    std::vector<uint8_t> best = encode(0);
    for (int m = 1; m <= std::min(version, 1) + 1; ++m) {
        std::vector<uint8_t> other = encode(m);
        if (other.size() < best.size()) {
            best = std::move(other);
        }
    }
    return best;
}

bool contextBlobNeedsParent(std::span<const uint8_t> blob) {
    return blob.size() >= kHeaderBytes && isContextResidualBlob(blob) && blob[7] == 3;
}

std::vector<uint8_t> encodeContextParentMode(std::span<const int16_t> residuals, int size,
                                             std::span<const int32_t> parentPlane, int mode) {
    const size_t samples = static_cast<size_t>(size) * static_cast<size_t>(size);
    if (size < 1 || size > 65535 || residuals.size() != samples || parentPlane.size() != samples) {
        fail("", "residual tile: buffers do not match " + std::to_string(size) + "x" + std::to_string(size));
    }
    if (mode != -1 && (mode < 3 || mode > 5)) {
        fail("", "context-coded residual tile: no mode " + std::to_string(mode) + " in version 3");
    }
    return context_coding::encodeParentMode(residuals, size, parentPlane, mode);
}

std::vector<int16_t> decodeContextResiduals(std::span<const uint8_t> blob, int size, const std::string& where,
                                            std::span<const int32_t> parentPlane) {
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
    if (version > 3 || (version == 3 && (mode < 3 || mode > 5)) || (version < 3 && mode > std::min<int>(version, 1) + 1)) {
        fail(where, "context-coded residual tile of an unknown kind (mode " + std::to_string(mode) + ", version " +
                        std::to_string(version) + ")");
    }
    switch (version) {
    case 0:
        return decodeMode<0>(blob, size, mode, where);
    case 1:
        return decodeMode<1>(blob, size, mode, where);
    case 3:
        if (parentPlane.size() != static_cast<size_t>(size) * static_cast<size_t>(size)) {
            fail(where, "context-coded residual tile in the parent mode, read without its parent tile");
        }
        return decodeParentMode(blob, size, parentPlane, where);
    default:
        return decodeVersion2(blob, size, mode, where);
    }
}

} // namespace pyramid
