#include "libpyramid/encode/dem/dem_tile_fit.hpp"

#include <algorithm>
#include <cstdio>

#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"

namespace pyramid {

namespace {

// The largest tile size whose tiles the original runtime reads (T + 5 < 256); the largest the
// format takes is kMaxTileSize.
constexpr int64_t kReadableTile = 250;
// The default root tile's intervals: the fit's root is the smallest at least this large.
constexpr int kDefaultRoot = 24;

std::string grid(int64_t side) { return std::to_string(side) + "x" + std::to_string(side); }

} // namespace

DemTileFit fitDemTiles(int width, int height, bool stretch, const std::string& where) {
    if (width < 2 || height < 2) {
        fail(where, "input of " + std::to_string(width) + "x" + std::to_string(height) +
                        " samples is too small (2x2 at least)");
    }
    const int64_t L = std::max(width, height) - 1;
    int64_t T = 0;
    int k = 0;
    // 1 and 2: L = T * 2^k with T even. Walking k up, T falls: the first readable T is the
    // largest one; the last unreadable one before it is the smallest beyond 250.
    int64_t unreadable = 0;
    int unreadableK = 0;
    for (int j = 0; (L >> j) >= 2 && (L % (int64_t{1} << j)) == 0; ++j) {
        const int64_t t = L >> j;
        if (t % 2 != 0) {
            continue;
        }
        if (t <= kReadableTile) {
            T = t;
            k = j;
            break;
        }
        if (t <= kMaxTileSize) {
            unreadable = t;
            unreadableK = j;
        }
    }
    if (T == 0 && unreadable > 0) {
        T = unreadable;
        k = unreadableK;
    }
    if (T == 0) {
        // 3: no exact fit; the smallest N >= L of readable tiles is at the smallest k that
        // makes them readable (a larger k only rounds L up to a coarser multiple).
        for (k = 0;; ++k) {
            const int64_t step = int64_t{2} << k; // N is a multiple of 2^(k+1)
            T = 2 * ((L + step - 1) / step);
            if (T <= kReadableTile) {
                break;
            }
        }
    }
    DemTileFit fit;
    fit.tileSize = static_cast<int>(T);
    // The root's intervals stay even (the runtime's elevation tiles are: elevationDelta), so a
    // halving needs T divisible by 4 << minLevel.
    fit.minLevel = 0;
    while (fit.tileSize % (4 << fit.minLevel) == 0 && (fit.tileSize >> (fit.minLevel + 1)) >= kDefaultRoot) {
        ++fit.minLevel;
    }
    fit.rootTileSize = fit.tileSize >> fit.minLevel;
    fit.maxLevel = fit.minLevel + k;
    fit.intervals = T << k;
    fit.inputIntervals = L;
    fit.width = width;
    fit.height = height;
    fit.stretch = stretch;
    fit.exact = fit.intervals == L && (!stretch || width == height);
    return fit;
}

std::string DemTileFit::describe() const {
    std::string s = "tile size " + std::to_string(tileSize) + ", root tile size " + std::to_string(rootTileSize) +
                     " (minLevel " + std::to_string(minLevel) + "), maxLevel " + std::to_string(maxLevel) + ": ";
    const std::string input = std::to_string(width) + "x" + std::to_string(height);
    if (exact) {
        s += width == height ? "the finest level is the input's " + input + " grid, no resampling"
                             : "the input's " + input + " samples are finest samples of its " +
                                   grid(intervals + 1) + " grid, no resampling (the rest is nodata)";
    } else if (intervals == inputIntervals) {
        s += "the longer side's " + std::to_string(inputIntervals + 1) +
             " samples are finest samples, the shorter side is stretched (resampled)";
    } else {
        char ratio[32];
        std::snprintf(ratio, sizeof ratio, "%.4g", resampling());
        s += "no grid of the format is the input's (" + std::to_string(inputIntervals) +
             " intervals are no even tile size up to " + std::to_string(kMaxTileSize) +
             " times a power of two); the least resampling: " +
             input + " input samples onto a " + grid(intervals + 1) + " finest grid, " + ratio +
             " finest intervals per input interval";
    }
    return s;
}

} // namespace pyramid
