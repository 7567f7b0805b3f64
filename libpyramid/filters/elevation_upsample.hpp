// The elevation upsample-and-add of doc/format.md ("Elevation arithmetic"): the one
// description that the encoder, the CPU elevation producer and the GLSL shader follow,
// operation by operation, so that all three agree bit for bit.
//
// Tiles are (n+5) x (n+5) float32 samples, row-major, row 0 = bottom, 2-sample borders.
#pragma once
#include <cstddef>
#include <cstdint>

#include "formats/residual_file.hpp" // quadrantOffset, the rule of the parent sample under a child

namespace pyramid {

// The 4-point interpolating filter (-1, 9, 9, -1)/16 on one line, in the documented order:
// ((z1 + z2) * 9 - (z0 + z3)) / 16.
inline float interpolate4(float z0, float z1, float z2, float z3) {
    return ((z1 + z2) * 9.0f - (z0 + z3)) / 16.0f;
}

// The prediction of child sample (i, j), 0 <= i, j <= n+4, from the parent tile: the parent
// sample index is (i/2 + px, j/2 + py). For a quadrant child px = 1 + (tx%2) * n/2 (same for y);
// for a whole-tile 2x upsample (a level below minLevel to the next) px = py = 1 and n is the
// child's size. `parent` has `parentStride` floats per row.
float predictElevation(const float* parent, size_t parentStride, int px, int py, int i, int j);

// out[i + j*outStride] = predictElevation(...) + out[i + j*outStride] for the whole
// (n+5)^2 child tile. `out` holds the scaled residuals on entry (r * scale, or 0) and the
// reconstructed elevations on return.
void upsampleAndAdd(const float* parent, size_t parentStride, int n, int px, int py,
                    float* out, size_t outStride);

} // namespace pyramid

namespace pyramid {

// A window of stored residuals, as a producer serves them: row j < rows holds `columns` residuals
// at first + j * stride, each served as float(r) * scale (one rounding); every other sample of
// the window (columns >= columns, rows >= rows) is 0.
struct ResidualWindow {
    const int16_t* first = nullptr;
    size_t stride = 0;
    int columns = 0;
    int rows = 0;
    float scale = 1.0f;
};

// upsampleAndAdd of the residuals `r` would serve, without writing them to `out` first:
// out[i + j*outStride] = predictElevation(...) + (float(r) * scale, or 0), the same operations in
// the same order, bit for bit.
void upsampleAndAddResiduals(const float* parent, size_t parentStride, int n, int px, int py,
                             const ResidualWindow& r, float* out, size_t outStride);

} // namespace pyramid
