#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <mutex>

#include "formats/error.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/parallel.hpp"
#include "libpyramid/support/vector_clones.hpp"

namespace pyramid {

std::string numberText(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", x);
    return text;
}

namespace {

// Subtrees encoded at once, in the memory estimate of cutLevel (a constant, not the thread
// count: the cut decides the tile order in the file, which must not depend on the threads).
constexpr int64_t kSubtreesInFlight = 4;

// The cut-off level C: levels 0..C are encoded from a grid of every 2^(M-C)-th finest sample
// held in memory, the deeper ones subtree by subtree from level-(C+1) footprints read on
// demand. C minimises the samples held at once: the grid (counted twice: its heights and the
// level-C reconstructions) plus kSubtreesInFlight footprints; C = M (everything in memory) is a
// candidate too, and wins for small pyramids. Subtree roots need a quadrant parent: C >= minLevel.
int cutLevel(int minLevel, int maxLevel, int tileSize, int64_t N) {
    int best = maxLevel;
    double bestSamples = static_cast<double>(N + 1) * static_cast<double>(N + 1);
    for (int c = maxLevel - 1; c >= minLevel; --c) {
        const double grid = static_cast<double>((N >> (maxLevel - c)) + 1);
        const double footprint = static_cast<double>((static_cast<int64_t>(tileSize + 4) << (maxLevel - c - 1)) + 1);
        const double samples = 2.0 * grid * grid + static_cast<double>(kSubtreesInFlight) * footprint * footprint;
        if (samples < bestSamples) {
            best = c;
            bestSamples = samples;
        }
    }
    return best;
}

struct Plan {
    ResidualHeader header;
    int M = 0;         // maxLevel
    int minLevel = 0;
    int T = 0;         // tileSize
    int R = 0;         // root tile intervals
    int64_t N = 0;     // finest intervals
    int C = 0;         // deepest level encoded from the in-memory grid
    float scale = 1.0f;
    bool folded = false;                 // GridEdges::Folded: borders are real samples, never clamped

    int64_t levelIntervals(int l) const { return static_cast<int64_t>(R) << l; }
    int tileIntervals(int l) const { return l < minLevel ? T >> (minLevel - l) : T; }
    int tilesPerSide(int l) const { return l < minLevel ? 1 : 1 << (l - minLevel); }
};

// Per-level error statistics, merged in a fixed order (sums of squares are order-sensitive).
struct LevelStats {
    int64_t samples = 0;
    double maxError = 0.0;
    double sumSquares = 0.0;
    int maxAbsResidual = 0;
    int64_t overflowResidual = 0; // largest |r| beyond int16, 0 if none

    void merge(const LevelStats& o) {
        samples += o.samples;
        maxError = std::max(maxError, o.maxError);
        sumSquares += o.sumSquares;
        maxAbsResidual = std::max(maxAbsResidual, o.maxAbsResidual);
        overflowResidual = std::max(overflowResidual, o.overflowResidual);
    }
};

struct EncodedTile {
    int level = 0, tx = 0, ty = 0;
    std::vector<float> recon;
    std::vector<uint8_t> blob;
    LevelStats stats;
};

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

// Deflate level of the residual tiles. Through libtiff (libdeflate, one compressor per tile),
// level 2 encodes residual tiles about 4 times faster than level 6, for 10 to 17 % more bytes
// (bench/README.md); the stream is standard Deflate either way, as the original runtime reads.
constexpr int kResidualDeflateLevel = 2;

// Encodes tile (l, tx, ty) against its parent's reconstruction (null at the root), reading the
// source heights of level-l positions from `src` (finest-grid coordinates; clamped to the map
// unless the plan's edges are folded).
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
// in place of the prediction in z. Sample i is at height[column(i)], valid[column(i)].
// roundHalfEven's operations, with selections instead of branches and no reduction, so that
// the compiler vectorises the loop (this file is compiled with -fno-trapping-math, which lets
// it evaluate both sides of a selection; the values are the same).
template <typename Column>
inline void encodeRowWith(const RowCoding& k, const float* __restrict height, const uint8_t* __restrict valid,
                          Column column, float* __restrict z, int16_t* __restrict r16, int S) {
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
    }
}

// The largest |r| of a row's valid samples, before clamping to int16. Stored values away from
// the int16 limits were not clamped: then it is the largest stored |r|. A row that reaches a
// limit (an overflow, or a residual of exactly -32768 or 32767) is measured again from the
// heights and the predictions, which z no longer holds: `prediction` gives them back.
template <typename Column, typename Prediction>
double largestResidual(const RowCoding& k, const float* height, const uint8_t* valid, Column column,
                       const int16_t* r16, int S, Prediction prediction) {
    int lo = 0, hi = 0;
    for (int i = 0; i < S; ++i) {
        lo = std::min(lo, static_cast<int>(r16[i]));
        hi = std::max(hi, static_cast<int>(r16[i]));
    }
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
    int i = 2;
    for (; i + 4 <= n + 2; i += 4) {
        for (int u = 0; u < 4; ++u) {
            count(i + u, u);
        }
    }
    for (; i < n + 2; ++i) {
        count(i, (i - 2) & 3);
    }
    if (edgeColumn >= n + 2 && edgeColumn < n + 5) {
        count(static_cast<int>(edgeColumn), 0);
    }
}

PYRAMID_VECTOR_CLONES
EncodedTile encodeTile(const Plan& plan, int l, int tx, int ty, const std::vector<float>* parent, const SourceGrid& src) {
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
        column[static_cast<size_t>(i)] = src.index(finest(ownX0 + i - 2), src.y0);
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
        const size_t row = src.index(src.x0, finest(q));
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
        if (uniform && columnStep == 1) {
            encodeRowWith(coding, height + firstColumn, valid + firstColumn, contiguous, z, r16, S);
        } else if (uniform) {
            encodeRowWith(coding, height + firstColumn, valid + firstColumn, strided, z, r16, S);
        } else {
            encodeRowWith(coding, height, valid, listed, z, r16, S);
        }
        maxAbs = std::max(maxAbs, largestResidual(coding, height, valid, listed, r16, S, prediction));
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
    out.blob = encodeResidualTiff(residuals, S, kResidualDeflateLevel);
    return out;
}

// Root-level nodata: a fixed number of Gauss-Seidel sweeps of Laplace's equation over the
// level-0 positions (with folded edges, its border positions too), from the mean of the valid
// ones (or of every valid grid sample when the root has none, or `emptyFill` when nothing is
// valid). Filled samples get valid = 2: encoded, but not counted as source.
void fillRootNodata(const Plan& plan, SourceGrid& grid, std::optional<float> emptyFill, const std::string& input) {
    const int64_t border = plan.folded ? 2 : 0;
    const int64_t side = plan.R + 1 + 2 * border;
    const int64_t unit = int64_t{1} << plan.M;
    std::vector<size_t> idx(static_cast<size_t>(side * side));
    double sum = 0.0;
    int64_t valid = 0;
    for (int64_t q = 0; q < side; ++q) {
        for (int64_t p = 0; p < side; ++p) {
            const size_t s = grid.index((p - border) * unit, (q - border) * unit);
            idx[static_cast<size_t>(p + q * side)] = s;
            if (grid.valid[s]) {
                sum += grid.height[s];
                ++valid;
            }
        }
    }
    if (valid == static_cast<int64_t>(idx.size())) {
        return;
    }
    if (valid == 0) {
        for (size_t s = 0; s < grid.valid.size(); ++s) {
            if (grid.valid[s]) {
                sum += grid.height[s];
                ++valid;
            }
        }
        if (valid == 0 && !emptyFill) {
            fail(input, "no valid height anywhere (everything is nodata)");
        }
        if (valid == 0) {
            sum = *emptyFill;
            valid = 1;
        }
    }
    const float mean = static_cast<float>(sum / static_cast<double>(valid));
    std::vector<double> v(idx.size());
    std::vector<bool> fixed(idx.size());
    for (size_t k = 0; k < idx.size(); ++k) {
        fixed[k] = grid.valid[idx[k]] != 0;
        v[k] = fixed[k] ? grid.height[idx[k]] : mean;
    }
    for (int sweep = 0; sweep < 500; ++sweep) {
        for (int64_t q = 0; q < side; ++q) {
            for (int64_t p = 0; p < side; ++p) {
                const size_t k = static_cast<size_t>(p + q * side);
                if (fixed[k]) {
                    continue;
                }
                const double l = v[static_cast<size_t>(std::max<int64_t>(p - 1, 0) + q * side)];
                const double r = v[static_cast<size_t>(std::min<int64_t>(p + 1, side - 1) + q * side)];
                const double d = v[static_cast<size_t>(p + std::max<int64_t>(q - 1, 0) * side)];
                const double u = v[static_cast<size_t>(p + std::min<int64_t>(q + 1, side - 1) * side)];
                v[k] = (l + r + d + u) * 0.25;
            }
        }
    }
    for (size_t k = 0; k < idx.size(); ++k) {
        if (!fixed[k]) {
            grid.height[idx[k]] = static_cast<float>(v[k]);
            grid.valid[idx[k]] = 2;
        }
    }
}

// The smallest 1, 2 or 5 x 10^k that is >= x.
double niceCeil(double x) {
    if (!(x > 0.0)) {
        return 0.0;
    }
    const double p = std::pow(10.0, std::floor(std::log10(x)));
    for (double m : {1.0, 2.0, 5.0, 10.0}) {
        if (m * p >= x * (1.0 - 1e-12)) {
            return m * p;
        }
    }
    return 10.0 * p;
}

// x rounded up to 3 significant digits, as messages print it ("0.239", "1.25e+04").
std::string roundUp3(double x) {
    const double p = std::pow(10.0, std::floor(std::log10(x)) - 2.0);
    return numberText(std::ceil(x / p - 1e-9) * p);
}

struct Overflow {
    double scale;
    int64_t residual;
    int level;
};

class Encoder {
public:
    Encoder(const Plan& plan, const HeightSource& sampler, const SourceGrid& grid, const DemEncodeOptions& options,
            int threads)
        : plan_(plan), sampler_(sampler), grid_(grid), options_(options), threads_(threads) {}

    // Encodes the whole pyramid at plan_.scale into `writer`; returns the first overflow, if any.
    std::optional<Overflow> run(ResidualFileWriter& writer, std::vector<LevelStats>& stats, int64_t& nodataFilled) {
        stats.assign(static_cast<size_t>(plan_.M) + 1, LevelStats{});
        total_ = plan_.header.tileCount();
        done_ = 0;
        std::vector<std::vector<float>> previous;
        for (int l = 0; l <= plan_.C; ++l) {
            const int side = plan_.tilesPerSide(l);
            const int64_t count = static_cast<int64_t>(side) * side;
            std::vector<EncodedTile> tiles(static_cast<size_t>(count));
            parallelFor(count, threads_, [&](int64_t m) {
                const auto [tx, ty] = mortonDecode(static_cast<uint64_t>(m));
                const std::vector<float>* parent = nullptr;
                if (l > 0) {
                    const int pside = plan_.tilesPerSide(l - 1);
                    parent = l <= plan_.minLevel ? &previous[0]
                                                 : &previous[static_cast<size_t>((ty / 2) * pside + tx / 2)];
                }
                tiles[static_cast<size_t>(m)] = encodeTile(plan_, l, static_cast<int>(tx), static_cast<int>(ty), parent, grid_);
            });
            std::vector<std::vector<float>> current(static_cast<size_t>(count));
            for (EncodedTile& t : tiles) {
                write(writer, t, stats);
                current[static_cast<size_t>(t.ty * side + t.tx)] = std::move(t.recon);
            }
            if (stats[static_cast<size_t>(l)].overflowResidual) {
                return Overflow{plan_.scale, stats[static_cast<size_t>(l)].overflowResidual, l};
            }
            previous = std::move(current);
        }
        if (plan_.C == plan_.M) {
            for (int64_t y = 0; y <= plan_.N; ++y) {
                const uint8_t* valid = grid_.valid.data() + grid_.index(0, y);
                nodataFilled += (plan_.N + 1) - std::count(valid, valid + plan_.N + 1, uint8_t{1});
            }
            return std::nullopt;
        }
        return runSubtrees(writer, stats, previous, nodataFilled);
    }

private:
    void write(ResidualFileWriter& writer, const EncodedTile& t, std::vector<LevelStats>& stats) {
        writer.writeTileBytes(t.level, t.tx, t.ty, t.blob);
        if (options_.reconstruction) {
            options_.reconstruction(t.level, t.tx, t.ty, t.recon);
        }
        stats[static_cast<size_t>(t.level)].merge(t.stats);
        ++done_;
        if (options_.progress) {
            options_.progress(done_, total_);
        }
    }

    void encodeSubtree(int l, int tx, int ty, const std::vector<float>& parent, const SourceGrid& footprint,
                       std::vector<EncodedTile>& out) {
        EncodedTile tile = encodeTile(plan_, l, tx, ty, &parent, footprint);
        // The children's parent; the tile keeps its reconstruction only for the hook, so that
        // memory stays per subtree.
        std::vector<float> recon;
        if (l < plan_.M) {
            recon = options_.reconstruction ? tile.recon : std::move(tile.recon);
        }
        if (!options_.reconstruction) {
            tile.recon.clear();
            tile.recon.shrink_to_fit();
        }
        out.push_back(std::move(tile));
        if (l < plan_.M) {
            for (int c = 0; c < 4; ++c) {
                encodeSubtree(l + 1, 2 * tx + (c & 1), 2 * ty + (c >> 1), recon, footprint, out);
            }
        }
    }

    // Subtrees go to the threads in Z order. The thread that completes the oldest unwritten
    // subtree writes it, and every later one already done, in Z order, while the other threads
    // go on encoding: no barrier per batch, no thread idle while tiles are written. A thread
    // starts subtree m only once m is within `window` subtrees of the oldest unwritten one, so
    // at most `window` subtrees' tiles are held at once.
    std::optional<Overflow> runSubtrees(ResidualFileWriter& writer, std::vector<LevelStats>& stats,
                                        const std::vector<std::vector<float>>& levelC, int64_t& nodataFilled) {
        const int top = plan_.C + 1;
        const int side = plan_.tilesPerSide(top);
        const int cside = plan_.tilesPerSide(plan_.C);
        const int64_t count = static_cast<int64_t>(side) * side;
        const int d = plan_.M - top;
        const int64_t window = std::max<int64_t>(kSubtreesInFlight, 2 * threads_);
        struct Done {
            std::vector<EncodedTile> tiles;
            int64_t filled = 0;
            bool ready = false;
        };
        std::vector<Done> done(static_cast<size_t>(window)); // subtree m in done[m % window]
        std::vector<SourceGrid> footprints(static_cast<size_t>(threads_));
        std::mutex mutex;
        std::condition_variable advanced;
        int64_t next = 0;     // the oldest unwritten subtree
        int64_t end = count;  // subtrees from `end` on are neither started nor written
        bool writing = false; // a thread is writing
        int64_t overflow = 0; // the writer's: the largest |residual| beyond int16 so far
        int overflowLevel = 0;
        const auto slot = [&](int64_t m) -> Done& { return done[static_cast<size_t>(m % window)]; };
        parallelFor(count, threads_, [&](int64_t m) {
            {
                std::unique_lock<std::mutex> lock(mutex);
                advanced.wait(lock, [&] { return m < next + window || m >= end; });
                if (m >= end) {
                    return;
                }
            }
            Done result;
            try {
                const auto [tx, ty] = mortonDecode(static_cast<uint64_t>(m));
                // Each thread reuses its footprint's buffers from subtree to subtree: no fresh
                // pages (faults, zeroing) per subtree.
                SourceGrid& footprint = footprints[static_cast<size_t>(omp_get_thread_num())];
                const int64_t T = plan_.T;
                footprint.stride = 1;
                // The subtree's tiles with their borders; clamped to the map unless edges are folded.
                const int64_t unit = int64_t{1} << d;
                const int64_t lo = plan_.folded ? std::numeric_limits<int64_t>::min() : 0;
                const int64_t hi = plan_.folded ? std::numeric_limits<int64_t>::max() : plan_.N;
                footprint.x0 = std::max<int64_t>(lo, (static_cast<int64_t>(tx) * T - 2) * unit);
                footprint.y0 = std::max<int64_t>(lo, (static_cast<int64_t>(ty) * T - 2) * unit);
                const int64_t x1 = std::min<int64_t>(hi, (static_cast<int64_t>(tx) * T + T + 2) * unit);
                const int64_t y1 = std::min<int64_t>(hi, (static_cast<int64_t>(ty) * T + T + 2) * unit);
                footprint.nx = x1 - footprint.x0 + 1;
                footprint.ny = y1 - footprint.y0 + 1;
                sampler_.sample(footprint);
                // Finest samples this subtree owns: [tx*T << d, (tx+1)*T << d), plus the map's edge.
                const int64_t ox0 = static_cast<int64_t>(tx) * T << d, ox1 = (static_cast<int64_t>(tx) + 1) * T << d;
                const int64_t oy0 = static_cast<int64_t>(ty) * T << d, oy1 = (static_cast<int64_t>(ty) + 1) * T << d;
                const int64_t rowEnd = oy1 == plan_.N ? oy1 + 1 : oy1;
                const int64_t columnEnd = ox1 == plan_.N ? ox1 + 1 : ox1;
                for (int64_t fy = oy0; fy < rowEnd; ++fy) {
                    const uint8_t* valid = footprint.valid.data() + footprint.index(ox0, fy);
                    result.filled += std::count(valid, valid + (columnEnd - ox0), uint8_t{0});
                }
                const std::vector<float>& parent = levelC[static_cast<size_t>((ty / 2) * cside + tx / 2)];
                encodeSubtree(top, static_cast<int>(tx), static_cast<int>(ty), parent, footprint, result.tiles);
            } catch (...) {
                std::lock_guard<std::mutex> lock(mutex);
                end = std::min(end, m);
                advanced.notify_all();
                throw;
            }
            std::unique_lock<std::mutex> lock(mutex);
            result.ready = true;
            slot(m) = std::move(result);
            if (writing) {
                return; // the writing thread takes it in turn
            }
            writing = true;
            while (next < end && slot(next).ready) {
                Done subtree = std::move(slot(next));
                slot(next) = Done{};
                lock.unlock();
                try {
                    nodataFilled += subtree.filled;
                    for (const EncodedTile& t : subtree.tiles) {
                        write(writer, t, stats);
                        if (t.stats.overflowResidual > overflow) {
                            overflow = t.stats.overflowResidual;
                            overflowLevel = t.level;
                        }
                    }
                } catch (...) {
                    lock.lock();
                    end = std::min(end, next);
                    writing = false;
                    advanced.notify_all();
                    throw;
                }
                lock.lock();
                ++next;
                // An overflow ends the encoding at the end of its group of kSubtreesInFlight
                // subtrees (the overflow reported is the group's largest), whatever the threads.
                if (overflow && next % kSubtreesInFlight == 0) {
                    end = std::min(end, next);
                }
                advanced.notify_all();
            }
            writing = false;
        });
        if (overflow) {
            return Overflow{plan_.scale, overflow, overflowLevel};
        }
        return std::nullopt;
    }

    const Plan& plan_;
    const HeightSource& sampler_;
    const SourceGrid& grid_;
    const DemEncodeOptions& options_;
    int threads_;
    int64_t total_ = 0;
    int64_t done_ = 0;
};

} // namespace

void encodeResidualPyramid(const ResidualPyramidJob& job, const std::string& output, const DemEncodeOptions& options,
                           DemReport& report) {
    Plan plan;
    plan.header = job.header;
    plan.M = plan.header.maxLevel;
    plan.minLevel = plan.header.minLevel;
    plan.T = plan.header.tileSize;
    plan.R = plan.T >> plan.minLevel;
    plan.N = plan.levelIntervals(plan.M);
    plan.C = cutLevel(plan.minLevel, plan.M, plan.T, plan.N);
    plan.folded = job.edges == GridEdges::Folded;
    const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
    report.threads = threads;

    // Pass 1: the in-memory grid of levels 0..C, one level-C row of samples at a time (each
    // reads two input rows at most), in row order, so the input streams through once.
    // With folded edges the grid reaches the root tile's borders, 2 level-0 intervals beyond.
    SourceGrid grid;
    grid.stride = int64_t{1} << (plan.M - plan.C);
    const int64_t margin = plan.folded ? int64_t{2} << plan.M : 0;
    grid.x0 = grid.y0 = -margin;
    grid.nx = grid.ny = (plan.N + 2 * margin) / grid.stride + 1;
    grid.height.resize(static_cast<size_t>(grid.nx * grid.ny));
    grid.valid.resize(grid.height.size());
    parallelFor(grid.ny, threads, [&](int64_t row) {
        SourceGrid line;
        line.stride = grid.stride;
        line.x0 = grid.x0;
        line.y0 = grid.y0 + row * grid.stride;
        line.nx = grid.nx;
        line.ny = 1;
        job.heights->sample(line);
        std::copy(line.height.begin(), line.height.end(), grid.height.begin() + row * grid.nx);
        std::copy(line.valid.begin(), line.valid.end(), grid.valid.begin() + row * grid.nx);
    });
    fillRootNodata(plan, grid, job.emptyFill, job.input);

    double scale = options.scale;
    if (options.autoScale) {
        double maxAbs = 0.0;
        for (size_t s = 0; s < grid.height.size(); ++s) {
            if (grid.valid[s]) {
                maxAbs = std::max(maxAbs, std::fabs(static_cast<double>(grid.height[s])));
            }
        }
        scale = std::max(niceCeil(maxAbs / 32767.0), 0.001);
    }
    for (int attempt = 0;; ++attempt) {
        plan.scale = static_cast<float>(scale);
        plan.header.scale = plan.scale;
        report.scalesTried.push_back(scale);
        std::vector<LevelStats> stats;
        int64_t nodataFilled = 0;
        ResidualFileWriter writer(output, plan.header);
        Encoder encoder(plan, *job.heights, grid, options, threads);
        const std::optional<Overflow> overflow = encoder.run(writer, stats, nodataFilled);
        if (overflow) {
            const double needed = scale * static_cast<double>(overflow->residual) / 32767.0;
            if (!options.autoScale || attempt >= 12) {
                fail(job.input, "residuals overflow int16 at scale " + numberText(scale) + " (|residual| " +
                                std::to_string(overflow->residual) + " at level " + std::to_string(overflow->level) +
                                "): use --scale " + roundUp3(needed) + " or more, or --scale auto");
            }
            scale = niceCeil(std::max(needed, scale * 1.000001));
            continue;
        }
        writer.commit();
        report.header = plan.header;
        report.tiles = plan.header.tileCount();
        report.sharedTiles = writer.sharedTiles();
        report.bytes = std::filesystem::file_size(output);
        report.finestSamples = (plan.N + 1) * (plan.N + 1);
        report.nodataFilled = nodataFilled;
        for (int l = 0; l <= plan.M; ++l) {
            const LevelStats& s = stats[static_cast<size_t>(l)];
            DemLevelReport lr;
            lr.level = l;
            lr.tiles = static_cast<int64_t>(plan.tilesPerSide(l)) * plan.tilesPerSide(l);
            lr.samples = s.samples;
            lr.maxError = s.maxError;
            lr.rmsError = s.samples ? std::sqrt(s.sumSquares / static_cast<double>(s.samples)) : 0.0;
            lr.maxAbsResidual = s.maxAbsResidual;
            report.levels.push_back(lr);
        }
        break;
    }
}

} // namespace pyramid
