#include "libpyramid/filters/terrain_normals.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

#include "libpyramid/filters/coarse_mesh.hpp"

namespace pyramid {

NormalGeometry normalGeometry(Deformation deformation, double size, int n, int level, int tx, int ty) {
    NormalGeometry g;
    g.deformation = deformation;
    if (deformation == Deformation::Plane) {
        g.twoSpacing = static_cast<float>(2.0 * std::ldexp(size / n, -level));
        return g;
    }
    g.radius = size;
    g.spacing = std::ldexp(2.0 * size / n, -level);
    g.faceVertices = int64_t{n} << level;
    g.firstX = int64_t{tx} * n - 2;
    g.firstY = int64_t{ty} * n - 2;
    // The frame at the tile's centre vertex (n/2 + 2 in tile samples).
    const double xc = -size + static_cast<double>(g.firstX + n / 2 + 2) * g.spacing;
    const double yc = -size + static_cast<double>(g.firstY + n / 2 + 2) * g.spacing;
    const double l = std::sqrt((xc * xc + yc * yc) + size * size);
    const std::array<double, 3> up{xc / l, yc / l, size / l};
    std::array<double, 3> ux{1.0 - up[0] * up[0], -(up[0] * up[1]), -(up[0] * up[2])};
    const double lx = std::sqrt((ux[0] * ux[0] + ux[1] * ux[1]) + ux[2] * ux[2]);
    ux = {ux[0] / lx, ux[1] / lx, ux[2] / lx};
    g.ux = ux;
    g.uy = {up[1] * ux[2] - up[2] * ux[1], up[2] * ux[0] - up[0] * ux[2], up[0] * ux[1] - up[1] * ux[0]};
    return g;
}

std::array<float, 2> planeNormal(const float* z, size_t stride, const NormalGeometry& g, int s, int t) {
    const auto at = [&](int i, int j) { return z[static_cast<size_t>(i) + static_cast<size_t>(j) * stride]; };
    const float gx = (at(s + 1, t) - at(s - 1, t)) / g.twoSpacing;
    const float gy = (at(s, t + 1) - at(s, t - 1)) / g.twoSpacing;
    const float l = std::sqrt((gx * gx + gy * gy) + 1.0f);
    return {-gx / l, -gy / l};
}

namespace {

std::array<double, 3> spherePoint(const float* z, size_t stride, const NormalGeometry& g, int s, int t) {
    const double R = g.radius, h = g.spacing;
    const int64_t X = g.firstX + s, Y = g.firstY + t, N = g.faceVertices;
    const int64_t dx = X > N ? X - N : X < 0 ? X : 0; // vertices beyond the edge (negative: the west one)
    const int64_t dy = Y > N ? Y - N : Y < 0 ? Y : 0;
    std::array<double, 3> p{-R + static_cast<double>(X) * h, -R + static_cast<double>(Y) * h, R};
    if (dx != 0 && dy == 0) {
        p = dx > 0 ? std::array<double, 3>{R, p[1], R - static_cast<double>(dx) * h}
                   : std::array<double, 3>{-R, p[1], R + static_cast<double>(dx) * h};
    } else if (dy != 0 && dx == 0) {
        p = dy > 0 ? std::array<double, 3>{p[0], R, R - static_cast<double>(dy) * h}
                   : std::array<double, 3>{p[0], -R, R + static_cast<double>(dy) * h};
    }
    const double k = (R + static_cast<double>(z[static_cast<size_t>(s) + static_cast<size_t>(t) * stride])) /
                     std::sqrt((p[0] * p[0] + p[1] * p[1]) + p[2] * p[2]);
    return {p[0] * k, p[1] * k, p[2] * k};
}

} // namespace

std::array<double, 3> sphereNormal(const float* z, size_t stride, const NormalGeometry& g, int s, int t) {
    const auto e = spherePoint(z, stride, g, s + 1, t), w = spherePoint(z, stride, g, s - 1, t);
    const auto n = spherePoint(z, stride, g, s, t + 1), so = spherePoint(z, stride, g, s, t - 1);
    const std::array<double, 3> a{e[0] - w[0], e[1] - w[1], e[2] - w[2]};
    const std::array<double, 3> b{n[0] - so[0], n[1] - so[1], n[2] - so[2]};
    const std::array<double, 3> c{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    const double l = std::sqrt((c[0] * c[0] + c[1] * c[1]) + c[2] * c[2]);
    return {c[0] / l, c[1] / l, c[2] / l};
}

std::array<float, 2> frameComponents(const std::array<double, 3>& v, const NormalGeometry& g) {
    return {static_cast<float>((v[0] * g.ux[0] + v[1] * g.ux[1]) + v[2] * g.ux[2]),
            static_cast<float>((v[0] * g.uy[0] + v[1] * g.uy[1]) + v[2] * g.uy[2])};
}

void normalTile(const float* z, const NormalGeometry& g, const float* parent, const NormalGeometry& parentGeometry,
                int n, int gridSize, int tx, int ty, float* out) {
    const auto stride = static_cast<size_t>(n + 5);
    const bool sphere = g.deformation == Deformation::Sphere;
    const CoarseMesh mesh(n, gridSize, tx, ty);
    // The parent's normals at its mesh vertices over this child: (cells + 1)^2 of them, at parent
    // samples (k * c/2 + origin); 3-D on a sphere, (nx, ny) on a plane.
    const int corners = mesh.cells() + 1;
    std::vector<std::array<double, 3>> parentNormals;
    if (parent) {
        const CoarseMesh::At origin = mesh.at(0, 0);
        const int half = mesh.cellSamples() / 2;
        parentNormals.resize(static_cast<size_t>(corners) * static_cast<size_t>(corners));
        for (int j = 0; j < corners; ++j) {
            for (int i = 0; i < corners; ++i) {
                const int x = origin.x0 + i * half, y = origin.y0 + j * half;
                auto& p = parentNormals[static_cast<size_t>(i + j * corners)];
                if (sphere) {
                    p = sphereNormal(parent, stride, parentGeometry, x, y);
                } else {
                    const std::array<float, 2> f = planeNormal(parent, stride, parentGeometry, x, y);
                    p = {f[0], f[1], 0.0};
                }
            }
        }
    }
    const auto cornerAt = [&](int x, int y) -> const std::array<double, 3>& {
        const CoarseMesh::At origin = mesh.at(0, 0);
        const int half = mesh.cellSamples() / 2;
        return parentNormals[static_cast<size_t>((x - origin.x0) / half + (y - origin.y0) / half * corners)];
    };
    for (int v = 0; v <= n; ++v) {
        for (int u = 0; u <= n; ++u) {
            float* o = out + (static_cast<size_t>(u) + static_cast<size_t>(v) * static_cast<size_t>(n + 1)) * 4;
            const std::array<float, 2> normal =
                sphere ? frameComponents(sphereNormal(z, stride, g, u + 2, v + 2), g) : planeNormal(z, stride, g, u + 2, v + 2);
            o[0] = normal[0];
            o[1] = normal[1];
            if (!parent) {
                o[2] = normal[0];
                o[3] = normal[1];
                continue;
            }
            const CoarseMesh::At a = mesh.at(u, v);
            const auto& n00 = cornerAt(a.x0, a.y0);
            const auto& n10 = cornerAt(a.x1, a.y0);
            const auto& n01 = cornerAt(a.x0, a.y1);
            const auto& n11 = cornerAt(a.x1, a.y1);
            if (sphere) {
                std::array<double, 3> mixed{};
                for (size_t k = 0; k < 3; ++k) {
                    mixed[k] = coarseMix(a, n00[k], n10[k], n01[k], n11[k]);
                }
                const std::array<float, 2> coarse = frameComponents(mixed, g);
                o[2] = coarse[0];
                o[3] = coarse[1];
            } else {
                // (nx, ny) were float32 and are mixed as float32.
                for (size_t k = 0; k < 2; ++k) {
                    o[2 + k] = coarseMix(a, static_cast<float>(n00[k]), static_cast<float>(n10[k]),
                                         static_cast<float>(n01[k]), static_cast<float>(n11[k]));
                }
            }
        }
    }
}

} // namespace pyramid
