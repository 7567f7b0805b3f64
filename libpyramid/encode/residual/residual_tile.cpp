#include "libpyramid/encode/residual/residual_tile.hpp"

#include <cmath>
#include <cstring>

#include "formats/residual_codec.hpp"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "formats/vector_clones.hpp"

namespace pyramid {

namespace {

// nearbyint(x) in the default rounding mode (to nearest, ties to even), without a libm call per
// sample (baseline x86-64 has no rounding instruction): adding and removing 2^52 drops the
// fraction of any |x| < 2^52 with exactly that rounding; larger magnitudes are integers already.
inline double roundHalfEven(double x) {
    constexpr double kTwo52 = 4503599627370496.0;
    const double a = std::fabs(x);
    if (!(a < kTwo52)) {
        return x;
    }
    return std::copysign((a + kTwo52) - kTwo52, x);
}


// How heights become residuals: r = round-half-even((height - prediction) / scale), by a
// multiplication when scale is a power of two (the same correctly rounded quotient).
struct RowCoding {
    bool powerOfTwo;
    double inverse; // 1 / scale when a power of two
    double step;    // scale, as a double
    float scale;
};

// Residuals of one row of a tile, written to r16 (0 at invalid samples, clamped to int16), and
// the runtime's reconstruction `z = prediction + float(r) * scale` (doc/format.md, section 3)
// in place of the prediction in z; lo and hi are lowered and raised to the row's stored
// values. Sample i is at height[column(i)], valid[column(i)]. roundHalfEven's operations, with
// selections instead of branches and no floating-point reduction, so that the compiler
// vectorises the loop (this file is compiled with -fno-trapping-math, which lets
// it evaluate both sides of a selection; the values are the same).
template <typename Column>
inline void encodeRowWith(const RowCoding& k, const float* __restrict height, const uint8_t* __restrict valid,
                          Column column, float* __restrict z, int16_t* __restrict r16, int S, int& lo, int& hi) {
    constexpr double kTwo52 = 4503599627370496.0;
    const bool powerOfTwo = k.powerOfTwo;
    const double inverse = k.inverse, step = k.step;
    const float scale = k.scale;
    for (int i = 0; i < S; ++i) {
        const size_t c = column(i);
        const double difference = static_cast<double>(height[c]) - static_cast<double>(z[i]);
        const double x = powerOfTwo ? difference * inverse : difference / step;
        const double a = std::fabs(x);
        const double rounded = a < kTwo52 ? std::copysign((a + kTwo52) - kTwo52, x) : x;
        const double r = valid[c] != 0 ? rounded : 0.0;
        const auto stored = static_cast<int16_t>(static_cast<int32_t>(std::min(std::max(r, -32768.0), 32767.0)));
        r16[i] = stored;
        z[i] = z[i] + static_cast<float>(stored) * scale;
        lo = std::min(lo, static_cast<int>(stored));
        hi = std::max(hi, static_cast<int>(stored));
    }
}

// The largest |r| of a row's valid samples, before clamping to int16, from the row's least and
// greatest stored values lo <= 0 <= hi (encodeRowWith's). Stored values away from the int16
// limits were not clamped: then it is the largest stored |r|. A row that reaches a
// limit (an overflow, or a residual of exactly -32768 or 32767) is measured again from the
// heights and the predictions, which z no longer holds: `prediction` gives them back.
template <typename Column, typename Prediction>
double largestResidual(const RowCoding& k, const float* height, const uint8_t* valid, Column column, int lo, int hi,
                       int S, Prediction prediction) {
    if (lo > -32768 && hi < 32767) {
        return static_cast<double>(std::max(-lo, hi));
    }
    double largest = 0.0;
    for (int i = 0; i < S; ++i) {
        const size_t c = column(i);
        if (valid[c] != 0) {
            const double difference = static_cast<double>(height[c]) - static_cast<double>(prediction(i));
            largest = std::max(largest, std::fabs(roundHalfEven(k.powerOfTwo ? difference * k.inverse : difference / k.step)));
        }
    }
    return largest;
}

// The error statistics of a tile in four lanes: sample i of a row goes to lane (i - 2) mod 4,
// and the lanes are combined in a fixed order at the end. The same values for any thread count,
// without one long chain of dependent additions.
struct ErrorLanes {
    int64_t counts[4] = {0, 0, 0, 0};
    double maxima[4] = {0.0, 0.0, 0.0, 0.0};
    double sums[4] = {0.0, 0.0, 0.0, 0.0};
};

// Adds the errors |z - height| of the samples a tile owns in one of its rows: i in [2, n + 2),
// and the map's last column when the tile holds it (at `edgeColumn`). Only source samples count
// (valid == 1: not nodata, not filled).
template <typename Column>
inline void addErrors(const float* height, const uint8_t* valid, Column column, const float* z, int n,
                      int64_t edgeColumn, ErrorLanes& lanes) {
    const auto count = [&](int i, int u) {
        const size_t c = column(i);
        const double e = std::fabs(static_cast<double>(z[i]) - static_cast<double>(height[c]));
        const bool counted = valid[c] == 1;
        lanes.counts[u] += counted ? 1 : 0;
        lanes.maxima[u] = std::max(lanes.maxima[u], counted ? e : 0.0);
        lanes.sums[u] += counted ? e * e : 0.0;
    };
    // Four samples at a time, the four lanes side by side in vectors (GCC's vector extension:
    // element-wise IEEE operations, the same values as count's): each lane's error, or 0 where
    // it does not count (|d| by clearing the sign bit, as fabs).
    using Double4 = double __attribute__((vector_size(32)));
    using Int4 = int64_t __attribute__((vector_size(32)));
    Double4 sums, maxima;
    Int4 counts;
    std::memcpy(&sums, lanes.sums, sizeof sums);
    std::memcpy(&maxima, lanes.maxima, sizeof maxima);
    std::memcpy(&counts, lanes.counts, sizeof counts);
    const Int4 magnitude = {INT64_MAX, INT64_MAX, INT64_MAX, INT64_MAX};
    const Double4 zero = {0.0, 0.0, 0.0, 0.0};
    int i = 2;
    for (; i + 4 <= n + 2; i += 4) {
        Double4 d;
        Int4 counted;
        for (int u = 0; u < 4; ++u) {
            const size_t c = column(i + u);
            d[u] = static_cast<double>(z[i + u]) - static_cast<double>(height[c]);
            counted[u] = valid[c] == 1 ? 1 : 0;
        }
        const Double4 e = counted != 0 ? reinterpret_cast<Double4>(reinterpret_cast<Int4>(d) & magnitude) : zero;
        counts += counted;
        maxima = maxima < e ? e : maxima;
        sums += e * e;
    }
    std::memcpy(lanes.sums, &sums, sizeof sums);
    std::memcpy(lanes.maxima, &maxima, sizeof maxima);
    std::memcpy(lanes.counts, &counts, sizeof counts);
    for (; i < n + 2; ++i) {
        count(i, (i - 2) & 3);
    }
    if (edgeColumn >= n + 2 && edgeColumn < n + 5) {
        count(static_cast<int>(edgeColumn), 0);
    }
}

} // namespace

PYRAMID_VECTOR_CLONES
EncodedTile encodeResidualTile(const ResidualPlan& plan, int l, int tx, int ty, const std::vector<float>* parent, const SourceGrid& src) {
    EncodedTile out;
    out.level = l;
    out.tx = tx;
    out.ty = ty;
    const int n = plan.tileIntervals(l);
    const int S = n + 5;
    const size_t area = static_cast<size_t>(S) * static_cast<size_t>(S);
    // recon holds the prediction P first; each sample is then replaced by its reconstruction.
    out.recon.assign(area, 0.0f);
    if (parent) {
        const size_t parentStride = static_cast<size_t>(plan.tileIntervals(l - 1)) + 5;
        const bool whole = l <= plan.minLevel;
        upsampleAndAdd(parent->data(), parentStride, n, whole ? 1 : quadrantOffset(tx, n),
                       whole ? 1 : quadrantOffset(ty, n), out.recon.data(), static_cast<size_t>(S));
    }
    // Per-thread scratch, reused from tile to tile: no allocation or zero fill per tile.
    thread_local std::vector<int16_t> residuals;
    thread_local std::vector<size_t> column;
    thread_local std::vector<float> predicted;
    residuals.resize(area);
    column.resize(static_cast<size_t>(S));
    predicted.resize(static_cast<size_t>(S));
    const int64_t Nl = plan.levelIntervals(l);
    const int shift = plan.M - l;
    const double step = static_cast<double>(plan.scale);
    // Dividing by a power of two is multiplying by its exact reciprocal (the same correctly
    // rounded quotient), and a multiplication costs a fraction of a division.
    int exponent = 0;
    const bool powerOfTwo = std::frexp(step, &exponent) == 0.5;
    const double inverse = powerOfTwo ? 1.0 / step : 0.0;
    const int64_t ownX0 = static_cast<int64_t>(tx) * n, ownY0 = static_cast<int64_t>(ty) * n;
    // Finest-grid coordinate of level-l position q (a multiplication: q may be negative).
    const auto finest = [&](int64_t q) { return (plan.folded ? q : std::clamp<int64_t>(q, 0, Nl)) * (int64_t{1} << shift); };
    // Offsets in `src` of each column's sample, computed once per tile.
    for (int i = 0; i < S; ++i) {
        column[static_cast<size_t>(i)] = src.column(finest(ownX0 + i - 2));
    }
    // Column of the map's last samples (at i >= n + 2 if the tile reaches them).
    const int64_t edgeColumn = Nl - ownX0 + 2;
    // Columns at a constant step (every tile whose samples are not clamped at the map's edge)
    // are read as a strided row, which the compiler vectorises; others through the table.
    const size_t firstColumn = column[0];
    const size_t columnStep = S > 1 ? column[1] - column[0] : 1;
    bool uniform = true;
    for (int i = 0; i < S; ++i) {
        uniform = uniform && column[static_cast<size_t>(i)] == firstColumn + static_cast<size_t>(i) * columnStep;
    }
    // Statistics in locals, not through out.stats: the compiler then keeps them in registers.
    ErrorLanes stats;
    double maxAbs = 0.0;
    const RowCoding coding{powerOfTwo, inverse, step, plan.scale};
    for (int j = 0; j < S; ++j) {
        const int64_t q = ownY0 + j - 2;
        const size_t row = src.rowStart(finest(q));
        const float* height = src.height.data() + row;
        const uint8_t* valid = src.valid.data() + row;
        float* z = out.recon.data() + static_cast<size_t>(j) * static_cast<size_t>(S);
        int16_t* r16 = residuals.data() + static_cast<size_t>(j) * static_cast<size_t>(S);
        // The predictions of the row, kept for measuring an overflowing row again.
        std::copy(z, z + S, predicted.data());
        const size_t* table = column.data();
        const auto contiguous = [](int i) { return static_cast<size_t>(i); };
        const auto strided = [columnStep](int i) { return static_cast<size_t>(i) * columnStep; };
        const auto listed = [table](int i) { return table[i]; };
        const auto prediction = [&](int i) { return predicted[static_cast<size_t>(i)]; };
        int lo = 0, hi = 0;
        if (uniform && columnStep == 1) {
            encodeRowWith(coding, height + firstColumn, valid + firstColumn, contiguous, z, r16, S, lo, hi);
        } else if (uniform) {
            encodeRowWith(coding, height + firstColumn, valid + firstColumn, strided, z, r16, S, lo, hi);
        } else {
            encodeRowWith(coding, height, valid, listed, z, r16, S, lo, hi);
        }
        maxAbs = std::max(maxAbs, largestResidual(coding, height, valid, listed, lo, hi, S, prediction));
        // A sample counts in the error statistics if the tile owns it: i in [2, n + 2) of an
        // owned row, and the map's last column.
        const bool ownedRow = (q >= ownY0 && q < ownY0 + n) || q == Nl;
        if (!ownedRow) {
            continue;
        }
        if (uniform && columnStep == 1) {
            addErrors(height + firstColumn, valid + firstColumn, contiguous, z, n, edgeColumn, stats);
        } else if (uniform) {
            addErrors(height + firstColumn, valid + firstColumn, strided, z, n, edgeColumn, stats);
        } else {
            addErrors(height, valid, listed, z, n, edgeColumn, stats);
        }
    }
    const int64_t samples = (stats.counts[0] + stats.counts[1]) + (stats.counts[2] + stats.counts[3]);
    const double maxError = std::max(std::max(stats.maxima[0], stats.maxima[1]), std::max(stats.maxima[2], stats.maxima[3]));
    const double sumSquares = (stats.sums[0] + stats.sums[1]) + (stats.sums[2] + stats.sums[3]);
    // |r| >= 32768 does not fit the symmetric int16 range: an overflow (doc/dem-encoding.md).
    out.stats.samples = samples;
    out.stats.maxError = maxError;
    out.stats.sumSquares = sumSquares;
    const auto largest = static_cast<int64_t>(std::min(maxAbs, 4.0e18));
    out.stats.maxAbsResidual = static_cast<int>(std::min<int64_t>(largest, 32768));
    out.stats.overflowResidual = largest > 32767 ? largest : 0;
    out.blob = encodeResidualBlob(residuals, S, plan.coding);
    return out;
}

std::vector<uint8_t> zeroResidualBlob(int size, const ResidualTileCoding& coding) {
    const std::vector<int16_t> zeros(static_cast<size_t>(size) * static_cast<size_t>(size), 0);
    return encodeResidualBlob(zeros, size, coding);
}

} // namespace pyramid
