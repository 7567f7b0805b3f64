// Cube face geometry: the face table, and seamless borders (every border sample of every face
// is its neighbour's sample at the same point, quarter turns included, at every level).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <tuple>

#include "formats/error.hpp"
#include "libpyramid/sphere/cube_faces.hpp"

namespace pyramid {
namespace {

using Dir = std::array<double, 3>;

TEST(CubeFaces, DirectionTablePinned) {
    EXPECT_EQ(faceDirection(1, 0.5, -0.25), (Dir{0.5, -0.25, 1.0}));
    EXPECT_EQ(faceDirection(2, 0.5, -0.25), (Dir{0.5, -1.0, -0.25}));
    EXPECT_EQ(faceDirection(3, 0.5, -0.25), (Dir{1.0, 0.5, -0.25}));
    EXPECT_EQ(faceDirection(4, 0.5, -0.25), (Dir{-0.5, 1.0, -0.25}));
    EXPECT_EQ(faceDirection(5, 0.5, -0.25), (Dir{-1.0, -0.5, -0.25}));
    EXPECT_EQ(faceDirection(6, 0.5, -0.25), (Dir{0.5, 0.25, -1.0}));
    EXPECT_EQ(faceDirection(6, -1.0, 1.0), (Dir{-1.0, -1.0, -1.0}));
    EXPECT_EQ(faceDirection(1, 1.0, 1.0), (Dir{1.0, 1.0, 1.0}));
    EXPECT_THROW(faceDirection(0, 0.0, 0.0), Error);
    EXPECT_THROW(faceDirection(7, 0.0, 0.0), Error);
}

TEST(CubeFaces, GridSamplesFollowTheTable) {
    for (FaceGridKind kind : {FaceGridKind::Vertices, FaceGridKind::PixelCentres}) {
        const FaceGrid g{8, kind};
        const double offset = kind == FaceGridKind::Vertices ? 0.0 : 0.5;
        for (int face = 1; face <= 6; ++face) {
            for (int64_t y = 0; y < 8; ++y) {
                for (int64_t x = 0; x < 8; ++x) {
                    const Dir d = direction(cubePoint(g, {face, x, y}));
                    const Dir e = faceDirection(face, (x + offset) / 8.0 * 2 - 1, (y + offset) / 8.0 * 2 - 1);
                    for (int k = 0; k < 3; ++k) {
                        EXPECT_EQ(d[k] / 8.0, e[k]) << face << " " << x << " " << y;
                    }
                }
            }
        }
    }
    // DEM vertex (0, 0) of face 3 is the cube corner (1, -1, -1); pixel (0, 0) is half a cell in.
    EXPECT_EQ(cubePoint(FaceGrid{4, FaceGridKind::Vertices}, {3, 0, 0}), (CubePoint{4, -4, -4}));
    EXPECT_EQ(cubePoint(FaceGrid{4, FaceGridKind::PixelCentres}, {3, 0, 0}), (CubePoint{4, -3, -3}));
}

// The integer range of a face's own samples.
int64_t lastSample(const FaceGrid& g) {
    return g.kind == FaceGridKind::Vertices ? g.n : g.n - 1;
}
bool onFace(const FaceGrid& g, const FaceSample& s) {
    return s.x >= 0 && s.y >= 0 && s.x <= lastSample(g) && s.y <= lastSample(g);
}
// The sample mirrored across the face edge nearest to it (distance d outside <-> d inside).
FaceSample mirrored(const FaceGrid& g, FaceSample s, bool acrossX) {
    int64_t& c = acrossX ? s.x : s.y;
    const int64_t last = lastSample(g);
    const int64_t edgeTwice = g.kind == FaceGridKind::Vertices ? 0 : -1; // 2 * edge on the low side
    if (2 * c < last) {
        c = edgeTwice - c;
    } else {
        c = 2 * last - edgeTwice - c;
    }
    return s;
}

TEST(CubeFaces, BorderSamplesAreTheNeighboursSamples) {
    const int border = 2;
    for (FaceGridKind kind : {FaceGridKind::Vertices, FaceGridKind::PixelCentres}) {
        for (int64_t n : {4, 8, 32}) {
            const FaceGrid g{n, kind};
            std::map<std::pair<int, int>, int> edgeSamples; // (face, neighbour) -> border samples
            for (int face = 1; face <= 6; ++face) {
                for (int64_t y = -border; y <= lastSample(g) + border; ++y) {
                    for (int64_t x = -border; x <= lastSample(g) + border; ++x) {
                        const FaceSample s{face, x, y};
                        const bool outX = x < 0 || x > lastSample(g);
                        const bool outY = y < 0 || y > lastSample(g);
                        const FaceSample t = canonicalSample(g, s);
                        if (outX == outY) {
                            EXPECT_EQ(t, s); // on the face, or beyond a corner
                            continue;
                        }
                        ASSERT_NE(t.face, face);
                        ASSERT_TRUE(onFace(g, t)) << face << " " << x << " " << y;
                        EXPECT_EQ(cubePoint(g, s), cubePoint(g, t));
                        ++edgeSamples[{face, t.face}];
                        // The mirror image holds too: across one of t's axes, t's own border
                        // sample is the point of s mirrored back inside face `face`.
                        // (Away from the cube corners, where the nearest edge is ambiguous.)
                        const int64_t along = outX ? y : x;
                        if (n < 8 || along <= border || along >= lastSample(g) - border) {
                            continue;
                        }
                        const CubePoint inside = cubePoint(g, mirrored(g, s, outX));
                        EXPECT_TRUE(cubePoint(g, mirrored(g, t, true)) == inside ||
                                    cubePoint(g, mirrored(g, t, false)) == inside)
                            << face << " " << x << " " << y;
                    }
                }
            }
            // Each face borders exactly four others, the opposite face never.
            ASSERT_EQ(edgeSamples.size(), 24u);
            for (const auto& [faces, count] : edgeSamples) {
                const int opposite[7] = {0, 6, 4, 5, 2, 3, 1}; // 1/6 poles, 2/4 = -y/+y, 3/5 = +x/-x
                EXPECT_NE(opposite[faces.first], faces.second) << faces.first << "/" << faces.second;
                EXPECT_EQ(count, border * (lastSample(g) + 1));
            }
        }
    }
}

TEST(CubeFaces, BorderRotationsAreQuarterTurns) {
    // Adjacent border samples map to adjacent neighbour samples (an isometry of the grids).
    const FaceGrid g{16, FaceGridKind::Vertices};
    for (int face = 1; face <= 6; ++face) {
        for (int64_t y = 0; y < 16; ++y) {
            const FaceSample a = canonicalSample(g, {face, 17, y});
            const FaceSample b = canonicalSample(g, {face, 17, y + 1});
            const FaceSample c = canonicalSample(g, {face, 18, y});
            EXPECT_EQ(a.face, b.face);
            EXPECT_EQ(std::llabs(a.x - b.x) + std::llabs(a.y - b.y), 1);
            EXPECT_EQ(std::llabs(a.x - c.x) + std::llabs(a.y - c.y), 1);
        }
    }
    // Face 1 beyond its east edge (x > n) is face 3 below its top edge: (n + k, y) -> (y, n - k).
    EXPECT_EQ(canonicalSample(g, {1, 18, 5}), (FaceSample{3, 5, 14}));
    // Face 3 beyond its top edge is face 1 west of its east edge.
    EXPECT_EQ(canonicalSample(g, {3, 5, 18}), (FaceSample{1, 14, 5}));
    // Face 2 beyond its west edge is face 5 (longitude 180 side), east part.
    EXPECT_EQ(canonicalSample(g, {2, -1, 7}).face, 5);
    // Ortho pixels: face 1 pixel (n + k, y) -> face 3 pixel (y, n - 1 - k).
    EXPECT_EQ(canonicalSample(FaceGrid{16, FaceGridKind::PixelCentres}, {1, 17, 5}), (FaceSample{3, 5, 14}));
}

TEST(CubeFaces, EdgeAndCornerVerticesAreShared) {
    const FaceGrid g{8, FaceGridKind::Vertices};
    std::map<std::tuple<int64_t, int64_t, int64_t>, std::set<int>> facesAt;
    for (int face = 1; face <= 6; ++face) {
        for (int64_t y = 0; y <= 8; ++y) {
            for (int64_t x = 0; x <= 8; ++x) {
                const CubePoint p = cubePoint(g, {face, x, y});
                facesAt[{p.x, p.y, p.z}].insert(face);
            }
        }
    }
    int corners = 0, edges = 0;
    for (const auto& [p, faces] : facesAt) {
        const int onBoundary = (std::llabs(std::get<0>(p)) == 8) + (std::llabs(std::get<1>(p)) == 8) +
                               (std::llabs(std::get<2>(p)) == 8);
        EXPECT_EQ(static_cast<int>(faces.size()), onBoundary);
        corners += onBoundary == 3;
        edges += onBoundary == 2;
    }
    EXPECT_EQ(corners, 8);
    EXPECT_EQ(edges, 12 * 7); // 12 cube edges, 7 inner vertices each
}

TEST(CubeFaces, FoldsCommuteWithCoarserLevels) {
    // DEM levels are point samples of the finest grid: folding a coarse sample and scaling it
    // gives the fold of the scaled sample. Ortho levels are 2x2 averages: the four fine pixels
    // of a coarse border pixel fold onto the four fine pixels of the folded coarse pixel.
    const FaceGrid coarseV{8, FaceGridKind::Vertices}, fineV{32, FaceGridKind::Vertices};
    const FaceGrid coarseP{8, FaceGridKind::PixelCentres}, fineP{16, FaceGridKind::PixelCentres};
    for (int face = 1; face <= 6; ++face) {
        for (int64_t y = 0; y <= 8; ++y) {
            for (int64_t x : {-2, -1, 9, 10}) {
                const FaceSample c = canonicalSample(coarseV, {face, x, y});
                EXPECT_EQ(canonicalSample(fineV, {face, 4 * x, 4 * y}), (FaceSample{c.face, 4 * c.x, 4 * c.y}));
            }
        }
        for (int64_t y = 0; y < 8; ++y) {
            for (int64_t x : {-2, -1, 8, 9}) {
                const FaceSample c = canonicalSample(coarseP, {face, x, y});
                std::set<std::pair<int64_t, int64_t>> expected, folded;
                for (int64_t dy = 0; dy < 2; ++dy) {
                    for (int64_t dx = 0; dx < 2; ++dx) {
                        expected.insert({2 * c.x + dx, 2 * c.y + dy});
                        const FaceSample f = canonicalSample(fineP, {face, 2 * x + dx, 2 * y + dy});
                        EXPECT_EQ(f.face, c.face);
                        folded.insert({f.x, f.y});
                    }
                }
                EXPECT_EQ(folded, expected);
            }
        }
    }
}

TEST(CubeFaces, BeyondCornerSamplesExtendThePlane) {
    const FaceGrid g{8, FaceGridKind::Vertices};
    // (10, 10) on face 1 is u = v = 1.5: the ray through (1.5, 1.5, 1).
    EXPECT_EQ(cubePoint(g, {1, 10, 10}), (CubePoint{12, 12, 8}));
    EXPECT_EQ(canonicalSample(g, {1, 10, 10}), (FaceSample{1, 10, 10}));
    EXPECT_THROW(cubePoint(g, {1, 20, 4}), Error); // farther beyond the edge than a face
}

// The one check of a face list, for every spherical encoder: the option and the value named.
TEST(CubeFaces, FaceListCheck) {
    EXPECT_NO_THROW(checkFaceList({1, 2, 3, 4, 5, 6}));
    EXPECT_NO_THROW(checkFaceList({6, 2}));
    const auto problem = [](const std::vector<int>& faces) -> std::string {
        try {
            checkFaceList(faces);
        } catch (const OptionError& e) {
            EXPECT_EQ(e.option(), "faces");
            return e.problem();
        }
        return "no error";
    };
    EXPECT_EQ(problem({}), "selects no face");
    EXPECT_EQ(problem({1, 7}), "7 is not a face number (1..6)");
    EXPECT_EQ(problem({0}), "0 is not a face number (1..6)");
    EXPECT_EQ(problem({2, 3, 2}), "face 2 is named twice");
}

} // namespace
} // namespace pyramid
