#include "libpyramid/runtime/level_heights.hpp"

#include <algorithm>
#include <cmath>

namespace pyramid {

namespace {

// Tile t, vertex k of that tile and the fraction w across the cell, along one axis.
void axisCell(int n, int64_t across, double c, int& t, int& k, double& w) {
    const int64_t vertices = across * n;
    c = std::clamp(c, 0.0, static_cast<double>(vertices));
    const int64_t whole = std::min<int64_t>(static_cast<int64_t>(std::floor(c)), vertices - 1);
    t = static_cast<int>(whole / n);
    k = static_cast<int>(whole - int64_t{t} * n);
    w = c - static_cast<double>(whole);
}

} // namespace

LevelCell levelCell(int n, int64_t across, double x, double y) {
    LevelCell cell;
    axisCell(n, across, x, cell.tx, cell.i, cell.wx);
    axisCell(n, across, y, cell.ty, cell.j, cell.wy);
    return cell;
}

double cellHeight(const float* z, int n, const LevelCell& cell) {
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
