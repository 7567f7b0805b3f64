// A planet's root nodata, filled once for the six faces as one surface (doc/spherical.md,
// "Nodata"): the faces' root grids share their edges and corners on the cube, so a hole that
// crosses a cube edge is filled smoothly across it, and a face the map does not reach takes the
// heights its neighbours lead to instead of a constant of its own.
#pragma once
#include <array>
#include <cstdint>
#include <optional>

#include "libpyramid/encode/residual/root_fill.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

// Sweeps of over-relaxation of each grid of the joint fill (below): per interval, and at most.
inline constexpr int64_t kSweepsPerInterval = 16;
inline constexpr int64_t kMostSweeps = 512;

// For each face (index face - 1), the root values of its nodata samples: the vertex grid of N
// intervals per face, root samples every N / R of them, borders of kFoldedRootBorder root
// intervals beyond every edge. Every root sample on the cube (a face's own, or a border sample beyond one edge,
// which is the neighbour's own) takes the joint solution; border samples beyond a cube corner
// are left NaN for the face to solve with its other samples fixed.
//
// The unknowns are the distinct cube points of the six (R + 1)^2 root grids; each is the mean
// of its distinct neighbours on the cube (4, or 3 at a cube corner), the valid ones fixed. They
// are solved coarse to fine, on grids of R, R / 2, R / 4, ... intervals per face while R halves
// evenly down to 2 (24: 3, 6, 12, 24), each grid's points every R / r-th root sample: the
// coarsest starts from the start value, each finer one from the coarser solution interpolated
// bilinearly along its faces, and each takes min(kSweepsPerInterval x r, kMostSweeps) sweeps of
// over-relaxation (omega = 2 - 3 / (r + 1); faces 1 to 6, rows south to north, each west to
// east; in double precision). With the default 24-interval root the result is within 1 m of
// the converged fill of a continent-sized map. The start value is the mean of the valid root
// samples; when none is valid, the mean of the valid samples of the coarsest level that has any
// (every face's samples at that level, sampled in blocks of 256 x 256 on `threads`, summed in
// a fixed order), which then stays everywhere; when no level has any, 0. With `fillHeight`,
// every nodata root sample takes that height instead (no solve). Deterministic: the same values
// for any thread count and face subset.
std::array<GivenRootFill, kCubeFaceCount> solveSphereRootFill(const GeodeticMap& map, const PlanetBody& body,
                                                              double heightScale, int64_t N, int64_t R,
                                                              std::optional<double> fillHeight, int threads);

} // namespace pyramid
