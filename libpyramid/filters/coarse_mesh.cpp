#include "libpyramid/filters/coarse_mesh.hpp"

#include <vector>

#include "formats/vector_clones.hpp"

namespace pyramid {

namespace {

// Offset o of every cell of a row, into line[cx] = the vertex at u = cx * c + o: each offset's
// weights are the same in every cell, so the compiler computes several cells at once, each with
// coarseMix's operations in its order. The corners of cell cx are r0/r1[cx * half + ox] and
// [+ half].
PYRAMID_VECTOR_CLONES
void mixOffset(const float* r0, const float* r1, int cells, int half, float fx, float fy, float* line) {
    if (fx + fy <= 1.0f) {
        const float w00 = 1.0f - fx - fy, w10 = fx, w01 = fy;
        for (int cx = 0; cx < cells; ++cx) {
            const int x0 = cx * half;
            line[cx] = (w00 * r0[x0] + w10 * r0[x0 + half]) + w01 * r1[x0];
        }
    } else {
        const float w11 = fx + fy - 1.0f, w10 = 1.0f - fy, w01 = 1.0f - fx;
        for (int cx = 0; cx < cells; ++cx) {
            const int x0 = cx * half;
            line[cx] = (w11 * r1[x0 + half] + w10 * r0[x0 + half]) + w01 * r1[x0];
        }
    }
}

// Cells of two samples (gridSize = n, the default): offsets 0 and 1 of every cell in one pass,
// stored in turn (mixOffset's operations, in its order). Offset 0 (fx = 0) is always in the
// lower triangle (fy <= 1).
PYRAMID_VECTOR_CLONES
void mixPairs(const float* r0, const float* r1, int cells, float fx, float fy, float* out) {
    const float a0 = 1.0f - 0.0f - fy, b0 = 0.0f, c0 = fy;
    if (fx + fy <= 1.0f) {
        const float a1 = 1.0f - fx - fy, b1 = fx, c1 = fy;
        for (int cx = 0; cx < cells; ++cx) {
            out[2 * cx] = (a0 * r0[cx] + b0 * r0[cx + 1]) + c0 * r1[cx];
            out[2 * cx + 1] = (a1 * r0[cx] + b1 * r0[cx + 1]) + c1 * r1[cx];
        }
    } else {
        const float a1 = fx + fy - 1.0f, b1 = 1.0f - fy, c1 = 1.0f - fx;
        for (int cx = 0; cx < cells; ++cx) {
            out[2 * cx] = (a0 * r0[cx] + b0 * r0[cx + 1]) + c0 * r1[cx];
            out[2 * cx + 1] = (a1 * r1[cx + 1] + b1 * r0[cx + 1]) + c1 * r1[cx];
        }
    }
}

} // namespace

void CoarseMesh::mixRow(int v, const float* zm, size_t stride, float* out) const {
    const At row = at(0, v);
    const float* r0 = zm + static_cast<size_t>(row.y0) * stride + ox_;
    const float* r1 = zm + static_cast<size_t>(row.y1) * stride + ox_;
    const int half = c_ / 2;
    const size_t cells = static_cast<size_t>(cells_);
    if (c_ == 2) {
        mixPairs(r0, r1, cells_, invC_, row.fy, out);
    } else {
        thread_local std::vector<float> lines;
        lines.resize(static_cast<size_t>(c_) * cells);
        for (int o = 0; o < c_; ++o) {
            mixOffset(r0, r1, cells_, half, static_cast<float>(o) * invC_, row.fy, &lines[static_cast<size_t>(o) * cells]);
        }
        for (size_t cx = 0; cx < cells; ++cx) {
            for (size_t o = 0; o < static_cast<size_t>(c_); ++o) {
                out[cx * static_cast<size_t>(c_) + o] = lines[o * cells + cx];
            }
        }
    }
    // u = n, the last cell's far edge (fx = n / c - (cells - 1) as at() computes it).
    const int n = cells_ * c_;
    const At a = at(n, v);
    const float* z0 = zm + static_cast<size_t>(a.y0) * stride;
    const float* z1 = zm + static_cast<size_t>(a.y1) * stride;
    out[n] = coarseMix(a, z0[a.x0], z0[a.x1], z1[a.x0], a.lower ? 0.0f : z1[a.x1]);
}

} // namespace pyramid
