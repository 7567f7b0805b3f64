// Heights between the vertices of one level of elevation tiles: the one rule that the height
// query (`pyramid height`, pyramid_elevation_height), the previews and the aperture's horizon
// search read heights by.
//
// A level is `across` x `across` tiles of n intervals; a tile holds (n + 5)^2 samples, row 0 the
// south, with a 2-sample border, so vertex i of the tile is sample i + 2. Vertex coordinates
// (x, y) run over 0 .. across * n from the level's south-west corner. The height at a point is
// the bilinear interpolation, in double precision, of the four samples of the cell that holds
// it, in this order:
//     south = z(i, j) + (z(i + 1, j) - z(i, j)) * wx
//     north = z(i, j + 1) + (z(i + 1, j + 1) - z(i, j + 1)) * wx
//     height = south + (north - south) * wy
// A coordinate beyond the level is clamped to it (its edge continues); the east and north edges
// belong to the last cells. The functions are inline: the aperture's horizon search reads
// through them hundreds of times per pixel.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace pyramid {

// The cell of a level that holds a point: the tile, the vertex (i, j) of that tile at the
// cell's south-west corner (0 .. n - 1), and the point's fractions (wx, wy) across the cell.
struct LevelCell {
    int tx = 0, ty = 0;
    int i = 0, j = 0;
    double wx = 0.0, wy = 0.0;
};

namespace level_heights_detail {

// Tile t, vertex k of that tile and the fraction w across the cell, along one axis.
inline void axisCell(int n, int64_t across, double c, int& t, int& k, double& w) {
    const int64_t vertices = across * n;
    c = std::clamp(c, 0.0, static_cast<double>(vertices));
    const int64_t whole = std::min<int64_t>(static_cast<int64_t>(std::floor(c)), vertices - 1);
    t = static_cast<int>(whole / n);
    k = static_cast<int>(whole - int64_t{t} * n);
    w = c - static_cast<double>(whole);
}

} // namespace level_heights_detail

// The cell holding vertex coordinates (x, y) of a level of `across` x `across` tiles of n
// intervals, (x, y) clamped to 0 .. across * n.
inline LevelCell levelCell(int n, int64_t across, double x, double y) {
    LevelCell cell;
    level_heights_detail::axisCell(n, across, x, cell.tx, cell.i, cell.wx);
    level_heights_detail::axisCell(n, across, y, cell.ty, cell.j, cell.wy);
    return cell;
}

// The height at `cell` in the samples `z` of its tile ((n + 5)^2 floats, row 0 the south).
inline double cellHeight(const float* z, int n, const LevelCell& cell) {
    const size_t side = static_cast<size_t>(n) + 5;
    const auto at = [&](int a, int b) {
        return static_cast<double>(z[static_cast<size_t>(b + 2) * side + static_cast<size_t>(a + 2)]);
    };
    const int i = cell.i, j = cell.j;
    const double south = at(i, j) + (at(i + 1, j) - at(i, j)) * cell.wx;
    const double north = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * cell.wx;
    return south + (north - south) * cell.wy;
}

} // namespace pyramid
