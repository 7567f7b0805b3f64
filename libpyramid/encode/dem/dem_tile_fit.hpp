// `preprocessDem --tile-size auto` (doc/dem-encoding.md, "Fitting the pyramid to the input"):
// the tile size, root tile size and levels whose finest grid is the input's own grid, so that
// the input is coded sample for sample, without resampling.
//
// The planar geometry (dem_sampling.hpp) maps the input's longer side, L = max(W, H) - 1
// intervals, onto the root quad's N = tileSize << (maxLevel - minLevel) finest intervals; with
// N = L finest sample x is input column x exactly (and the rows likewise), whatever the shorter
// side: the input sits at the north-west corner and the rest is nodata. tileSize is an even
// number, so an exact fit needs L = T * 2^k with T even, from 2 to 8192 (k = maxLevel -
// minLevel >= 0). The rule:
//
// 1. The largest T <= 250 (tiles of T + 5 < 256 samples, what the original Proland runtime
//    reads) with T * 2^k = L: e.g. 1201 -> 150 x 8, 2049 and 4097 -> 128 x 16 and 128 x 32,
//    513 -> 128 x 4, 257 -> 128 x 2.
// 2. Else the smallest T > 250 with T * 2^k = L, whose tiles only libpyramid's readers take
//    (the programs warn): 3601 -> 450 x 8, 10801 -> 1350 x 8.
// 3. Else (L odd, or L's odd factor above 4096) no grid of the format is the input's: the
//    input is resampled, and the least: the smallest N >= L that tiles of T <= 250 make, i.e.
//    the smallest k with T = 2 * ceil(L / 2^(k+1)) <= 250, N = T * 2^k (less than 2^(k+1)
//    more intervals than L: under 1.6 % for L >= 125). E.g. 1000 samples (L = 999) -> N = 1000
//    = 250 x 4, 1.001 finest intervals per input interval. (N < L would
//    drop input samples; the resampling is spread over the whole input anyway, so the tiles
//    stay ones the original runtime reads.)
//
// The root tile then has R = T / 2^minLevel intervals, an even number (the runtime's elevation
// tiles below minLevel have R * 2^l intervals, and those must be even: elevationDelta): the
// smallest such R of at least 24 (the default root, whose hole filling converges:
// doc/dem-encoding.md, "Nodata"), or T itself when no halving of T is even and at least 24
// (e.g. T 128 -> R 32, minLevel 2; T 192 -> R 24, minLevel 3; T 150 -> R 150, minLevel 0).
// maxLevel = minLevel + k.
//
// With `stretch` (width and height mapped independently) a non-square input's shorter side is
// resampled whatever the tiles: the fit is its longer side's, and not exact.
#pragma once
#include <cstdint>
#include <string>

namespace pyramid {

struct DemTileFit {
    int tileSize = 0;
    int rootTileSize = 0;
    int minLevel = 0;
    int maxLevel = 0;
    int64_t intervals = 0;      // N: finest intervals across the root quad
    int64_t inputIntervals = 0; // L = max(width, height) - 1: the input intervals N spans
    int width = 0;              // the input's
    int height = 0;
    bool stretch = false;
    // Every input sample is a finest-grid sample: no resampling at all (N = L, and a square
    // input or the aspect kept).
    bool exact = false;

    // Tiles of at most 255 samples, which the original Proland runtime reads.
    bool prolandReadable() const { return tileSize + 5 < 256; }
    // Finest intervals per input interval along the longer side: 1 for an exact fit.
    double resampling() const { return static_cast<double>(intervals) / static_cast<double>(inputIntervals); }
    // One sentence for messages and reports, e.g. "tile size 150, root tile size 150 (minLevel
    // 0), maxLevel 3: the finest level is the input's 1201x1201 grid, no resampling".
    std::string describe() const;
};

// The fit of a width x height input (rule above). Throws Error naming `where` for inputs
// smaller than 2 x 2, as makeDemGeometry does.
DemTileFit fitDemTiles(int width, int height, bool stretch, const std::string& where);

} // namespace pyramid
