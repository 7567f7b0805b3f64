// Version 3's mode 5, the terrace mode (doc/format.md 1.8): where a tile's shadows take few of
// the integers in their range (heights from an 8-bit map, or stored in coarse steps), the tile
// codes the sorted list of the shadows it holds, its *terraces*, and then each sample's terrace
// index, predicted by the terrace nearest its parent plane, in tables chosen by how far the
// median predictor over its neighbours' indices lies from that: a sample one terrace off costs
// a value of 1, not a step of the heights.
#include <algorithm>
#include <bit>
#include <cstdlib>
#include <memory>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_context_models.hpp"
#include "formats/residual_context_state.hpp"
#include "formats/residual_context_v2.hpp"
#include "formats/residual_context_values.hpp"
#include "formats/residual_range_coder.hpp"

namespace pyramid::context_coding {

namespace {

constexpr uint8_t kTerraceMode = 5;
// Shadows lie within +-kShadowLimit (formats/residual_shadow.hpp: a parent plane within +-2^30,
// plus an int16 residual).
constexpr int64_t kShadowLimit = (int64_t{1} << 30) + (int64_t{1} << 15);
constexpr uint32_t kLengths = 33; // a number's bit length, 0..32
constexpr size_t kTerraceSets = 4;
// isTerraced counts the distinct shadows of a tile whose range spans at most this in a bitmap.
constexpr uint64_t kBitmapRange = uint64_t{1} << 24;

// The terrace list's numbers: the count less one and the lowest terrace (zigzag) as a bit length
// in 6 equally likely bits and the bits below its leading one, 16 at a time from the top; each
// gap to the next terrace less one as its bit length from an adaptive table, the top 4 bits below
// the leading one as binary decisions in the context of the length and the bits before, and the
// rest equally likely.
struct ListModels {
    Model<kLengths> lengths;
    std::array<BitModel, kLengths * kPrefixes> bits;
};

void encodeNumber(RangeEncoder& coder, uint32_t u) {
    const int length = std::bit_width(u);
    coder.encodeBits(static_cast<uint32_t>(length), 6);
    for (int rest = length - 1; rest > 0;) {
        const int chunk = std::min(rest, 16);
        rest -= chunk;
        coder.encodeBits((u >> rest) & ((1u << chunk) - 1u), chunk);
    }
}

uint32_t decodeNumber(RangeDecoder& coder, const std::string& where) {
    const auto length = static_cast<int>(coder.decodeBits(6));
    if (length > 32) {
        fail(where, "context-coded residual tile: a terrace list's number of " + std::to_string(length) + " bits");
    }
    uint32_t u = length > 0 ? 1 : 0;
    for (int rest = length - 1; rest > 0;) {
        const int chunk = std::min(rest, 16);
        rest -= chunk;
        u = (u << chunk) | coder.decodeBits(chunk);
    }
    return u;
}

void encodeGap(RangeEncoder& coder, ListModels& models, uint32_t gap) {
    const auto length = static_cast<uint32_t>(std::bit_width(gap));
    coder.encode(models.lengths.cumulative(length), models.lengths.count[length], models.lengths.total);
    models.lengths.update(length);
    if (length > 0) {
        encodeBelowLeadingOne(coder, &models.bits[length * kPrefixes], gap, static_cast<int>(length) - 1);
    }
}

uint32_t decodeGap(RangeDecoder& coder, ListModels& models) {
    const uint32_t length = decodeSymbol(coder, models.lengths);
    return length == 0 ? 0 : decodeBelowLeadingOne(coder, &models.bits[length * kPrefixes], static_cast<int>(length) - 1);
}

uint32_t zigzag64(int64_t v) { return static_cast<uint32_t>(v >= 0 ? 2 * v : -2 * v - 1); }
int64_t unzigzag64(uint32_t z) { return (z & 1u) != 0 ? -static_cast<int64_t>(z / 2) - 1 : static_cast<int64_t>(z / 2); }

// The index of the first terrace at or above `v` (std::lower_bound's), found from `hint`
// outwards in steps that double, then by halving: the parent plane and the heights change
// little from one sample to the next, and no search takes more than twice the halving's steps.
size_t lowerBoundFrom(const std::vector<int64_t>& t, int64_t v, size_t hint) {
    const size_t n = t.size();
    size_t lo = 0, hi = std::min(hint, n); // the answer lies in [lo, hi]
    size_t step = 1;
    if (hi < n && t[hi] < v) {
        lo = hi + 1;
        while (lo + step - 1 < n && t[lo + step - 1] < v) {
            lo += step;
            step *= 2;
        }
        hi = std::min(n, lo + step - 1);
    } else {
        while (hi >= step && t[hi - step] >= v) {
            hi -= step;
            step *= 2;
        }
        lo = hi >= step ? hi - step + 1 : 0;
    }
    return static_cast<size_t>(std::lower_bound(t.begin() + static_cast<std::ptrdiff_t>(lo),
                                                t.begin() + static_cast<std::ptrdiff_t>(hi), v) - t.begin());
}

// The terrace nearest the parent plane `g` (the lower of two as near), searched from `hint`.
int32_t nearestTerrace(const std::vector<int64_t>& terraces, int64_t g, size_t hint) {
    size_t k = lowerBoundFrom(terraces, g, hint);
    if (k == terraces.size() || (k > 0 && g - terraces[k - 1] <= terraces[k] - g)) {
        --k;
    }
    return static_cast<int32_t>(k);
}

// The sample's context: the prediction is the terrace nearest its parent plane; the set of tables
// is how far (0 to 3 terraces and more) that lies from the median predictor over the neighbours'
// indices (mode 1's rules on the first row and column; the prediction itself at (0, 0)); the
// table within the set version 2's, by the activity over the neighbours' magnitudes; the sign
// model version 2's, with the sign of the predicted terrace less the parent plane.
// `hint`: the sample before's prediction.
Context terraceContext(const Planes& planes, const std::vector<int64_t>& terraces, size_t i, int x, int y, size_t hint) {
    const size_t s = planes.stride;
    const int32_t* t = planes.residual.data();
    const int64_t g = planes.parentAt(x, y);
    Context c;
    c.prediction = nearestTerrace(terraces, g, hint);
    const int32_t west = x > 0 ? t[i - 1] : (y > 0 ? t[i - s] : c.prediction);
    const int32_t south = y > 0 ? t[i - s] : west;
    const int32_t southWest = x > 0 && y > 0 ? t[i - s - 1] : west;
    const int64_t apart = std::abs(median(west, south, southWest) - c.prediction);
    const auto set = static_cast<size_t>(std::min<int64_t>(kTerraceSets - 1, apart));
    const uint32_t* m = planes.magnitude.data();
    const uint32_t activity = 2 * m[i - 1] + 2 * m[i - s] + m[i - s - 1] + m[i - s + 1] + m[i - 2] + m[i - 2 * s];
    c.table = static_cast<size_t>(tableOf(activity, x, y)) + set * kModels;
    const int parity = (x & 1) + 2 * (y & 1);
    c.pattern = static_cast<size_t>((parity * 3 + signOf(planes.value[i - 1]) + 1) * 3 + signOf(planes.value[i - s]) + 1);
    c.sign = signModel(c.pattern, terraces[static_cast<size_t>(c.prediction)] - g, set);
    return c;
}

std::vector<int64_t> terracesOf(std::span<const int16_t> residuals, std::span<const int32_t> parent) {
    std::vector<int64_t> h(residuals.size());
    for (size_t k = 0; k < h.size(); ++k) {
        h[k] = static_cast<int64_t>(parent[k]) + residuals[k];
    }
    std::sort(h.begin(), h.end());
    h.erase(std::unique(h.begin(), h.end()), h.end());
    return h;
}

} // namespace

bool isTerraced(std::span<const int16_t> residuals, std::span<const int32_t> parent) {
    int64_t lo = INT64_MAX, hi = INT64_MIN;
    for (size_t k = 0; k < residuals.size(); ++k) {
        const int64_t h = int64_t{parent[k]} + residuals[k];
        lo = std::min(lo, h);
        hi = std::max(hi, h);
    }
    const auto range = static_cast<uint64_t>(hi - lo) + 1;
    if (range > kBitmapRange) { // rare (a tile spanning 2^24 units): the list itself
        const std::vector<int64_t> terraces = terracesOf(residuals, parent);
        return terraces.size() <= kMaxTerraces && terraces.size() * 2 <= range;
    }
    // The distinct shadows counted in a bitmap of the range, until they are too many.
    const uint64_t most = std::min<uint64_t>(kMaxTerraces, range / 2);
    std::vector<uint64_t> seen((range + 63) / 64);
    uint64_t distinct = 0;
    for (size_t k = 0; k < residuals.size(); ++k) {
        const auto at = static_cast<uint64_t>(int64_t{parent[k]} + residuals[k] - lo);
        uint64_t& word = seen[at / 64];
        const uint64_t bit = uint64_t{1} << (at % 64);
        if ((word & bit) == 0) {
            word |= bit;
            if (++distinct > most) {
                return false;
            }
        }
    }
    return true;
}

std::vector<uint8_t> encodeTerraceMode(std::span<const int16_t> residuals, int size, std::span<const int32_t> parent) {
    const std::vector<int64_t> terraces = terracesOf(residuals, parent);
    if (terraces.size() > kMaxTerraces) {
        fail("", "context-coded residual tile: more than " + std::to_string(kMaxTerraces) + " terraces");
    }
    if (std::abs(terraces.front()) > kShadowLimit || std::abs(terraces.back()) > kShadowLimit) {
        fail("", "context-coded residual tile: a parent plane beyond +-2^30");
    }
    std::vector<uint8_t> out = {kContextResidualMagic[0], kContextResidualMagic[1], kContextResidualMagic[2],
                                kContextResidualMagic[3], static_cast<uint8_t>(size & 0xff),
                                static_cast<uint8_t>(size >> 8), kTerraceMode, 3};
    out.reserve(residuals.size() / 2 + kHeaderBytes);
    RangeEncoder coder(out);
    encodeNumber(coder, static_cast<uint32_t>(terraces.size() - 1));
    encodeNumber(coder, zigzag64(terraces[0]));
    const auto list = std::make_unique<ListModels>();
    for (size_t k = 1; k < terraces.size(); ++k) {
        encodeGap(coder, *list, static_cast<uint32_t>(terraces[k] - terraces[k - 1] - 1));
    }
    const PlanesLease lease(size, 0);
    Planes& planes = *lease;
    planes.parent = parent.data();
    const auto models = std::make_unique<Models<kTerraceSets>>();
    size_t hint = 0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = planes.at(x, y);
            const size_t k = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
            const int64_t h = static_cast<int64_t>(parent[k]) + residuals[k];
            const Context c = terraceContext(planes, terraces, i, x, y, hint);
            hint = static_cast<size_t>(c.prediction);
            const auto index = static_cast<int32_t>(lowerBoundFrom(terraces, h, hint));
            const int32_t v = index - c.prediction;
            planes.residual[i] = index;
            planes.value[i] = v;
            planes.magnitude[i] = static_cast<uint32_t>(std::abs(v));
            encodeValue(coder, *models, c.table, c.sign, v);
        }
    }
    coder.finish();
    return out;
}

std::vector<int16_t> decodeTerraceMode(std::span<const uint8_t> blob, int size, std::span<const int32_t> parent,
                                       const std::string& where) {
    RangeDecoder coder(blob.subspan(kHeaderBytes), where);
    const uint32_t last = decodeNumber(coder, where);
    if (last >= kMaxTerraces || last >= static_cast<uint64_t>(size) * static_cast<uint64_t>(size)) {
        fail(where, "context-coded residual tile: " + std::to_string(uint64_t{last} + 1) + " terraces in a tile of " +
                        std::to_string(size) + "x" + std::to_string(size));
    }
    std::vector<int64_t> terraces(size_t{last} + 1);
    terraces[0] = unzigzag64(decodeNumber(coder, where));
    const auto list = std::make_unique<ListModels>();
    for (size_t k = 1; k < terraces.size(); ++k) {
        terraces[k] = terraces[k - 1] + 1 + decodeGap(coder, *list);
    }
    if (std::abs(terraces.front()) > kShadowLimit || std::abs(terraces.back()) > kShadowLimit) {
        fail(where, "context-coded residual tile: a terrace beyond +-(2^30 + 2^15)");
    }
    const PlanesLease lease(size, 0);
    Planes& planes = *lease;
    planes.parent = parent.data();
    const auto models = std::make_unique<Models<kTerraceSets>>();
    std::vector<int16_t> out(static_cast<size_t>(size) * static_cast<size_t>(size));
    size_t hint = 0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = planes.at(x, y);
            const Context c = terraceContext(planes, terraces, i, x, y, hint);
            hint = static_cast<size_t>(c.prediction);
            const int32_t v = decodeValue(coder, *models, c.table, c.sign);
            const int64_t index = int64_t{c.prediction} + v;
            if (index < 0 || index > int64_t{last}) {
                fail(where, "context-coded residual tile: terrace " + std::to_string(index) + " of " +
                                std::to_string(uint64_t{last} + 1));
            }
            const int64_t residual = terraces[static_cast<size_t>(index)] - planes.parentAt(x, y);
            if (residual < -32768 || residual > 32767) {
                fail(where, "context-coded residual tile: a residual of " + std::to_string(residual) + " is beyond int16");
            }
            planes.residual[i] = static_cast<int32_t>(index);
            planes.value[i] = v;
            planes.magnitude[i] = static_cast<uint32_t>(std::abs(v));
            out[static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)] = static_cast<int16_t>(residual);
        }
    }
    coder.finish();
    return out;
}

} // namespace pyramid::context_coding
