#include "libpyramid/encode/dem/sphere_root_fill.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/sphere/face_sampler.hpp"

namespace pyramid {

namespace {

using PointKey = std::tuple<int64_t, int64_t, int64_t>;

PointKey keyOf(const CubePoint& p) {
    return {p.x, p.y, p.z};
}

// The distinct cube points of the six faces' grids of r intervals (every R / r-th root sample),
// numbered in face, row and column order, with their heights where the root sample is valid
// (a point's samples on its faces are bit-identical) and their distinct neighbours: one
// interval away in the plane of the face that numbered them, folded across an edge onto the
// neighbour face (4, or 3 at a cube corner).
struct CubeGrid {
    int64_t r = 0;
    int64_t step = 0; // in root intervals
    std::map<PointKey, int64_t> nodeOf;
    std::vector<double> value;
    std::vector<uint8_t> fixed;
    std::vector<FaceSample> first; // face and position (in grid intervals) that numbered each point
    std::vector<int64_t> start;    // neighbours of point k: neighbours[start[k] .. start[k + 1])
    std::vector<int64_t> neighbours;
};

CubeGrid cubeGrid(const FaceGrid& grid, int64_t unit, int64_t R, int64_t r,
                  const std::vector<std::vector<float>>& height, const std::vector<std::vector<uint8_t>>& valid) {
    CubeGrid g;
    g.r = r;
    g.step = R / r;
    const auto keyAt = [&](int face, int64_t p, int64_t q) {
        return keyOf(cubePoint(grid, FaceSample{face, p * g.step * unit, q * g.step * unit}));
    };
    for (int f = 1; f <= kCubeFaceCount; ++f) {
        for (int64_t q = 0; q <= r; ++q) {
            for (int64_t p = 0; p <= r; ++p) {
                if (g.nodeOf.emplace(keyAt(f, p, q), static_cast<int64_t>(g.value.size())).second) {
                    const size_t k = static_cast<size_t>(p * g.step + q * g.step * (R + 1));
                    const bool ok = valid[static_cast<size_t>(f - 1)][k] != 0;
                    g.value.push_back(ok ? static_cast<double>(height[static_cast<size_t>(f - 1)][k]) : 0.0);
                    g.fixed.push_back(ok ? 1 : 0);
                    g.first.push_back(FaceSample{f, p, q});
                }
            }
        }
    }
    g.start.assign(g.value.size() + 1, 0);
    for (size_t k = 0; k < g.value.size(); ++k) {
        const FaceSample& at = g.first[k];
        const int64_t steps[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
        const size_t begin = g.neighbours.size();
        for (const auto& d : steps) {
            const int64_t m = g.nodeOf.at(keyAt(at.face, at.x + d[0], at.y + d[1]));
            if (std::find(g.neighbours.begin() + static_cast<std::ptrdiff_t>(begin), g.neighbours.end(), m) ==
                g.neighbours.end()) {
                g.neighbours.push_back(m);
            }
        }
        g.start[k + 1] = static_cast<int64_t>(g.neighbours.size());
    }
    return g;
}

// Over-relaxation sweeps of the free points, in their order.
void relax(CubeGrid& g, int sweeps) {
    const double omega = 2.0 - 3.0 / static_cast<double>(g.r + 1);
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        for (size_t k = 0; k < g.value.size(); ++k) {
            if (g.fixed[k]) {
                continue;
            }
            double around = 0.0;
            for (int64_t j = g.start[k]; j < g.start[k + 1]; ++j) {
                around += g.value[static_cast<size_t>(g.neighbours[static_cast<size_t>(j)])];
            }
            around /= static_cast<double>(g.start[k + 1] - g.start[k]);
            g.value[k] += omega * (around - g.value[k]);
        }
    }
}

} // namespace

std::array<GivenRootFill, kCubeFaceCount> solveSphereRootFill(const GeodeticMap& map, const PlanetBody& body,
                                                              double heightScale, int64_t N, int64_t R,
                                                              std::optional<double> fillHeight, int threads) {
    const FaceGrid grid{N, FaceGridKind::Vertices};
    const int64_t unit = N / R;
    const int64_t side = R + 1 + 2 * kFoldedRootBorder;
    std::vector<FaceSampler> faces;
    std::vector<std::vector<float>> height(kCubeFaceCount);
    std::vector<std::vector<uint8_t>> valid(kCubeFaceCount);
    for (int f = 1; f <= kCubeFaceCount; ++f) {
        faces.emplace_back(map, body, f, grid, heightScale);
        height[static_cast<size_t>(f - 1)].resize(static_cast<size_t>((R + 1) * (R + 1)));
        valid[static_cast<size_t>(f - 1)].resize(static_cast<size_t>((R + 1) * (R + 1)));
        faces.back().sample(0, 0, unit, R + 1, R + 1, height[static_cast<size_t>(f - 1)].data(),
                            valid[static_cast<size_t>(f - 1)].data());
    }
    CubeGrid root = cubeGrid(grid, unit, R, R, height, valid);

    double sum = 0.0;
    int64_t count = 0;
    for (size_t k = 0; k < root.value.size(); ++k) {
        if (root.fixed[k]) {
            sum += root.value[k];
            ++count;
        }
    }
    for (int64_t stride = unit / 2; count == 0 && !fillHeight && stride >= 1; stride /= 2) {
        for (const FaceSampler& face : faces) {
            const auto [s, c] = sumValidHeights(FaceHeights(face), N, stride, threads);
            sum += s;
            count += c;
        }
    }
    const double mean = fillHeight ? *fillHeight : count > 0 ? sum / static_cast<double>(count) : 0.0;
    const bool someFree = std::find(root.fixed.begin(), root.fixed.end(), uint8_t{0}) != root.fixed.end();
    const bool someFixed = std::find(root.fixed.begin(), root.fixed.end(), uint8_t{1}) != root.fixed.end();
    if (someFree && (!someFixed || fillHeight)) {
        for (size_t k = 0; k < root.value.size(); ++k) {
            if (!root.fixed[k]) {
                root.value[k] = mean; // the given height, or nothing to lead it elsewhere
            }
        }
    } else if (someFree) {
        // Coarse to fine: grids of R, R / 2, ... intervals while they halve evenly down to 2;
        // the coarsest starts from the mean, each finer one from the coarser solution
        // interpolated along its faces (bilinearly: an edge point from the edge's points only, so
        // every face gives it the same start), and each is relaxed min(kSweepsPerInterval x r,
        // kMostSweeps) times.
        std::vector<int64_t> sizes{R};
        while (sizes.back() % 2 == 0 && sizes.back() / 2 >= 2) {
            sizes.push_back(sizes.back() / 2);
        }
        std::optional<CubeGrid> coarser;
        for (auto it = sizes.rbegin(); it != sizes.rend(); ++it) {
            CubeGrid g = *it == R ? std::move(root) : cubeGrid(grid, unit, R, *it, height, valid);
            for (size_t k = 0; k < g.value.size(); ++k) {
                if (g.fixed[k]) {
                    continue;
                }
                if (!coarser) {
                    g.value[k] = mean;
                    continue;
                }
                const FaceSample& at = g.first[k];
                double v = 0.0;
                int terms = 0;
                for (const int64_t cy : {at.y / 2, (at.y + 1) / 2}) {
                    for (const int64_t cx : {at.x / 2, (at.x + 1) / 2}) {
                        const CubePoint c = cubePoint(grid, FaceSample{at.face, cx * coarser->step * unit,
                                                                       cy * coarser->step * unit});
                        v += coarser->value[static_cast<size_t>(coarser->nodeOf.at(keyOf(c)))];
                        ++terms;
                    }
                }
                g.value[k] = v / terms;
            }
            relax(g, static_cast<int>(std::min(kSweepsPerInterval * g.r, kMostSweeps)));
            coarser = std::move(g);
        }
        root = std::move(*coarser);
    }

    std::array<GivenRootFill, kCubeFaceCount> fills;
    for (int f = 1; f <= kCubeFaceCount; ++f) {
        GivenRootFill& fill = fills[static_cast<size_t>(f - 1)];
        fill.start = mean;
        fill.value.assign(static_cast<size_t>(side * side), std::numeric_limits<double>::quiet_NaN());
        for (int64_t q = 0; q < side; ++q) {
            for (int64_t p = 0; p < side; ++p) {
                const FaceSample s{f, (p - kFoldedRootBorder) * unit, (q - kFoldedRootBorder) * unit};
                const FaceSample c = canonicalSample(grid, s);
                if (c.x < 0 || c.x > N || c.y < 0 || c.y > N) {
                    continue; // beyond a cube corner: the face's own
                }
                fill.value[static_cast<size_t>(p + q * side)] =
                    root.value[static_cast<size_t>(root.nodeOf.at(keyOf(cubePoint(grid, s))))];
            }
        }
    }
    return fills;
}

} // namespace pyramid
