// Terrain normals from elevation tiles (doc/shading.md, "Normals"): the one description that the
// CPU normal producer follows and the GLSL normal shader (gl/gl_normal_producer.cpp) repeats
// operation by operation, so that both agree bit for bit.
//
// A normal tile of an elevation tile of n intervals holds (n+1)^2 vertices (no border), row 0
// the south, four floats each: (nx, ny) the normal's horizontal components in the tile's
// tangent frame, (ncx, ncy) the coarse normal's (the parent's normals on its render mesh,
// filters/coarse_mesh.hpp). The vertical component is sqrt(1 - nx^2 - ny^2).
//
// Plane: the ground is the plane z = 0, samples h apart (the root quad's side / (2^level n)), in
// height units; the frame is x east, y north. Sphere: the root quad is a cube face's plane
// [-R, R]^2 at distance R, each sample at face position (x, y) with height z lies at
// (R + z) p / |p| with p = (x, y, R); the frame is the tile centre's: up U its direction, ux the
// face x axis projected on the tangent plane, uy = U x ux. Border samples beyond a face edge are
// the neighbouring face's samples (sphere/cube_faces.hpp): d samples beyond the edge x = R, p is
// (R, y, R - d h) on that face's plane (likewise for the other edges); beyond two edges at once
// (a cube corner) p stays on the extended plane. So two faces place a seam's samples alike.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

namespace pyramid {

enum class Deformation { Plane, Sphere };

// What a tile's normals need besides its heights.
struct NormalGeometry {
    Deformation deformation = Deformation::Plane;
    // Plane: twice the sample spacing, rounded to float32 (the divisor of central differences).
    float twoSpacing = 2.0f;
    // Sphere: the radius, the face's vertices a side at this level (N = n 2^level), the face
    // vertex of tile sample 0 (X0 = tx n - 2, likewise Y0: the border's first), the spacing
    // h = 2R / N (float64: ldexp(2R / n, -level)), and the tile's frame.
    double radius = 1.0, spacing = 0.0;
    int64_t faceVertices = 0, firstX = 0, firstY = 0;
    std::array<double, 3> ux{1.0, 0.0, 0.0}, uy{0.0, 1.0, 0.0};
};

// The geometry of tile (level, tx, ty) of n intervals. Plane: `size` is the root quad's side;
// sphere: the radius R (the root quad spans [-R, R]^2).
NormalGeometry normalGeometry(Deformation deformation, double size, int n, int level, int tx, int ty);

// The normal at tile sample (s, t) of heights `z` (n+5 a side, row 0 the south), 1 <= s, t <= n+3:
// central differences of its four neighbours.
//  * Plane, float32 in this order:
//      gx = (z[s+1,t] - z[s-1,t]) / twoSpacing,  gy = (z[s,t+1] - z[s,t-1]) / twoSpacing
//      l = sqrt((gx*gx + gy*gy) + 1),  (nx, ny) = (-gx / l, -gy / l)
//  * Sphere, float64: the face vertex X = X0 + s (Y likewise) is d = X - N beyond the edge
//      x = R when positive, d = X beyond x = -R when negative; inside, x = -R + X h. p is
//      (x, y, R) inside, (R, y, R - d h) or (-R, y, R + d h) beyond one edge in x (likewise in y,
//      d h for the distance), the extended plane's (x, y, R) beyond both. Then
//      k = (R + z) / sqrt((p0*p0 + p1*p1) + p2*p2), P = (p0 k, p1 k, p2 k);
//      a = P[s+1,t] - P[s-1,t], b = P[s,t+1] - P[s,t-1];
//      N = a x b = (a1 b2 - a2 b1, a2 b0 - a0 b2, a0 b1 - a1 b0), divided by
//      sqrt((N0 N0 + N1 N1) + N2 N2) (each component).
// planeNormal gives (nx, ny); sphereNormal the unit 3-D normal, and frameComponents its
// (nx, ny) in a frame: ((N0 u0 + N1 u1) + N2 u2), rounded to float32.
std::array<float, 2> planeNormal(const float* z, size_t stride, const NormalGeometry& g, int s, int t);
std::array<double, 3> sphereNormal(const float* z, size_t stride, const NormalGeometry& g, int s, int t);
std::array<float, 2> frameComponents(const std::array<double, 3>& normal, const NormalGeometry& g);

// A whole normal tile, (n+1)^2 x 4 floats into `out` (row 0 the south): the normals of
// `z` (geometry `g`) and the coarse normals of its parent (heights `parent`, geometry
// `parentGeometry`) on the parent's render mesh of gridSize quads, for tile (tx, ty). Without a
// parent (level 0) the coarse normals are the normals. Sphere: the parent's unit normals are
// mixed in 3-D (coarse_mesh.hpp's order, float64) and expressed in the child's frame.
void normalTile(const float* z, const NormalGeometry& g, const float* parent, const NormalGeometry& parentGeometry,
                int n, int gridSize, int tx, int ty, float* out);

} // namespace pyramid
