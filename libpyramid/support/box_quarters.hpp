// Boxes of cells halved until a question about them is answered (where a map may reach, at which
// level): the one rule for cutting a box of cells [x0, x1) x [y0, y1) into its quarters.
#pragma once
#include <cstdint>

namespace pyramid {

// Calls part(x0, y0, x1, y1) for each quarter of the box, in Z order: the box halved along each
// side longer than one cell (so 2 or 4 parts; a box of one cell is not cut and gives none).
template <class Part>
void forEachQuarter(int64_t x0, int64_t y0, int64_t x1, int64_t y1, const Part& part) {
    const int64_t mx = x1 - x0 > 1 ? (x0 + x1) / 2 : x1, my = y1 - y0 > 1 ? (y0 + y1) / 2 : y1;
    if (mx == x1 && my == y1) {
        return;
    }
    part(x0, y0, mx, my);
    if (mx < x1) {
        part(mx, y0, x1, my);
    }
    if (my < y1) {
        part(x0, my, mx, y1);
        if (mx < x1) {
            part(mx, my, x1, y1);
        }
    }
}

} // namespace pyramid
