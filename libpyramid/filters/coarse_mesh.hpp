// The parent tile's render mesh evaluated at a child vertex (doc/format.md, 3.1 "Coarse
// elevations"): the one description of where coarse values come from, used for the coarse
// elevations zc (CPU elevation producer) and the coarse normals (CPU normal producer), and
// written once more in GLSL (gl/gl_coarse_mesh.hpp) in the same order.
//
// The parent's mesh is a grid of gridSize quads over the parent quad, with north-west to
// south-east diagonals. Over the child quad its cells are c = 2n / gridSize child samples wide.
// For child vertex (u, v), 0..n:
//   cx = min(u / c, gridSize/2 - 1), fx = (u - cx*c) * (1/c)   (float32; likewise cy, fy)
//   corner AB is parent sample ((cx+A)*c/2 + (tx%2)*n/2 + 2, (cy+B)*c/2 + (ty%2)*n/2 + 2)
//   lower-left triangle (fx + fy <= 1):  ((1-fx-fy) * z00 + fx * z10) + fy * z01
//   upper-right triangle (fx + fy > 1):  ((fx+fy-1) * z11 + (1-fy) * z10) + (1-fx) * z01
// with the weights in float32 in that order (then, for double values, converted exactly).
#pragma once
#include <algorithm>
#include <cstddef>

namespace pyramid {

class CoarseMesh {
public:
    // Tile (tx, ty) of n intervals under a parent rendered with gridSize quads a side.
    CoarseMesh(int n, int gridSize, int tx, int ty)
        : c_(2 * n / gridSize), cells_(gridSize / 2), ox_((tx & 1) * (n / 2) + 2), oy_((ty & 1) * (n / 2) + 2),
          invC_(1.0f / static_cast<float>(c_)) {}

    struct At {
        int x0 = 0, y0 = 0, x1 = 0, y1 = 0; // parent samples of corners 00 (x0, y0) to 11 (x1, y1)
        float fx = 0.0f, fy = 0.0f;
        bool lower = true; // the lower-left triangle: z11 is not used
    };

    At at(int u, int v) const {
        At a;
        const int cx = std::min(u / c_, cells_ - 1), cy = std::min(v / c_, cells_ - 1);
        a.fx = static_cast<float>(u - cx * c_) * invC_;
        a.fy = static_cast<float>(v - cy * c_) * invC_;
        a.x0 = cx * c_ / 2 + ox_;
        a.y0 = cy * c_ / 2 + oy_;
        a.x1 = (cx + 1) * c_ / 2 + ox_;
        a.y1 = (cy + 1) * c_ / 2 + oy_;
        a.lower = a.fx + a.fy <= 1.0f;
        return a;
    }

    // Row v of the mesh over a float tile: out[u] = coarseMix(at(u, v), ...) of the parent's
    // values `zm` (rows `stride` apart) for u = 0..n. The same operations in the same order per
    // vertex (coarse_mesh.cpp).
    void mixRow(int v, const float* zm, size_t stride, float* out) const;

    int cellSamples() const { return c_; }
    int cells() const { return cells_; }
    float invCell() const { return invC_; }

private:
    int c_, cells_, ox_, oy_;
    float invC_;
};

// The mesh's value at `a` from its corners' values (z11 read only in the upper triangle).
template <class T>
T coarseMix(const CoarseMesh::At& a, T z00, T z10, T z01, T z11) {
    if (a.lower) {
        return (static_cast<T>(1.0f - a.fx - a.fy) * z00 + static_cast<T>(a.fx) * z10) + static_cast<T>(a.fy) * z01;
    }
    return (static_cast<T>(a.fx + a.fy - 1.0f) * z11 + static_cast<T>(1.0f - a.fy) * z10) +
           static_cast<T>(1.0f - a.fx) * z01;
}

} // namespace pyramid
