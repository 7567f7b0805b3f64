// Copying one pixel's few values: a count known only at run time makes compilers call memcpy for
// each pixel (a loop of `n` copies is recognised as one), which costs more than the copy; one case
// per usual count is unrolled instead.
#pragma once
#include <algorithm>
#include <cstddef>

namespace pyramid {

template <typename T>
inline void copyPixel(const T* from, T* to, size_t n) {
    switch (n) {
    case 4:
        to[3] = from[3];
        [[fallthrough]];
    case 3:
        to[2] = from[2];
        [[fallthrough]];
    case 2:
        to[1] = from[1];
        [[fallthrough]];
    case 1:
        to[0] = from[0];
        return;
    default:
        std::copy_n(from, n, to);
    }
}

} // namespace pyramid
