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
// belong to the last cells.
#pragma once
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

// The cell holding vertex coordinates (x, y) of a level of `across` x `across` tiles of n
// intervals, (x, y) clamped to 0 .. across * n.
LevelCell levelCell(int n, int64_t across, double x, double y);

// The height at `cell` in the samples `z` of its tile ((n + 5)^2 floats, row 0 the south).
double cellHeight(const float* z, int n, const LevelCell& cell);

} // namespace pyramid
