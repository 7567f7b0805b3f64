// The elevation upsample against values computed by hand from doc/format.md, stored residuals
// added as their served floats bit for bit, and the coarse mesh's rows (CoarseMesh::mixRow)
// against its definition vertex by vertex.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "libpyramid/filters/coarse_mesh.hpp"

#include "libpyramid/filters/elevation_upsample.hpp"

namespace pyramid {
namespace {

TEST(ElevationUpsample, OneDimensionalFilterOrder) {
    EXPECT_EQ(interpolate4(0.0f, 16.0f, 16.0f, 0.0f), 18.0f);   // ((16+16)*9 - 0)/16
    EXPECT_EQ(interpolate4(1.0f, 2.0f, 3.0f, 4.0f), 2.5f);       // linear data stays linear
    EXPECT_EQ(interpolate4(0.1f, 0.2f, 0.3f, 0.4f), ((0.2f + 0.3f) * 9.0f - (0.1f + 0.4f)) / 16.0f);
}

TEST(ElevationUpsample, CopiesEvenSamplesAndInterpolatesOthers) {
    const int n = 4;       // child interior 4x4, tiles 9x9
    const int side = n + 5;
    std::vector<float> parent(side * side);
    for (int j = 0; j < side; ++j) {
        for (int i = 0; i < side; ++i) {
            parent[i + j * side] = static_cast<float>(i * i + 10 * j); // quadratic in x, linear in y
        }
    }
    std::vector<float> child(side * side, 0.0f);
    const int px = quadrantOffset(1, n), py = quadrantOffset(0, n);
    EXPECT_EQ(px, 3);
    EXPECT_EQ(py, 1);
    upsampleAndAdd(parent.data(), side, n, px, py, child.data(), side);
    // Even (i, j): the parent sample (i/2+px, j/2+py).
    EXPECT_EQ(child[2 + 4 * side], parent[(1 + 3) + (2 + 1) * side]);
    // Odd i, even j: the cubic filter reproduces x^2 at the midpoint minus the filter's bias
    // (-1,9,9,-1)/16 on x^2 at x = a+0.5 gives (a+0.5)^2 - 1/8 ... computed here directly.
    const float* row = &parent[(0 + 1) * side];
    EXPECT_EQ(child[1 + 0 * side], ((row[3] + row[4]) * 9.0f - (row[2] + row[5])) / 16.0f);
    // Odd j, even i: linear in y, exact midpoint.
    EXPECT_EQ(child[0 + 1 * side], parent[3 + 1 * side] + 5.0f);
}

TEST(ElevationUpsample, AddsResidualAfterPrediction) {
    const int n = 2, side = n + 5;
    std::vector<float> parent(side * side, 100.0f);
    std::vector<float> child(side * side, 0.5f);
    upsampleAndAdd(parent.data(), side, n, 1, 1, child.data(), side);
    for (float v : child) {
        EXPECT_EQ(v, 100.5f);
    }
}

// mixRow gives, bit for bit, coarseMix at each at(u, v): every render grid a tile of 192 allows,
// both quadrants, values whose sums round (so another order of operations would show).
// Stored residuals added as the producer serves them (upsampleAndAddResiduals) give upsampleAndAdd
// of the served floats bit for bit: whole windows and windows cut short on the right and at the
// top (zeros there), negative scales (whose zero residuals serve -0.0), none at all, and
// predictions of -0.0 (+0.0 once a zero is added).
TEST(ElevationUpsample, StoredResidualsAddAsTheirServedFloats) {
    for (const int n : {4, 24, 192}) {
        const int side = n + 5;
        const auto s = static_cast<size_t>(side);
        std::vector<float> parent(s * s);
        uint32_t seed = 12345;
        const auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
        for (size_t k = 0; k < parent.size(); ++k) {
            parent[k] = k % 7 == 0 ? -0.0f : static_cast<float>(static_cast<int>(next() >> 20) - 2048) * 0.37f;
        }
        const int tile = side + 3; // the stored tile, wider than the window
        std::vector<int16_t> stored(static_cast<size_t>(tile) * static_cast<size_t>(tile));
        for (int16_t& r : stored) {
            r = static_cast<int16_t>(static_cast<int>(next() >> 16) % 2001 - 1000);
        }
        for (size_t k = 0; k < stored.size(); k += 5) {
            stored[k] = 0;
        }
        struct Case {
            int columns, rows;
            float scale;
        };
        for (const Case& c : {Case{side, side, 0.25f}, Case{side - 3, side, -1.5f}, Case{side, side - 2, 3.0f},
                              Case{1, 7, -0.1f}, Case{0, 0, 1.0f}}) {
            SCOPED_TRACE(testing::Message() << "n " << n << " columns " << c.columns << " rows " << c.rows);
            const ResidualWindow w{&stored[2 + 1 * static_cast<size_t>(tile)], static_cast<size_t>(tile), c.columns,
                                   c.rows, c.scale};
            std::vector<float> served(s * s, 0.0f);
            for (int j = 0; j < c.rows; ++j) {
                for (int i = 0; i < c.columns; ++i) {
                    served[static_cast<size_t>(i) + static_cast<size_t>(j) * s] =
                        static_cast<float>(w.first[static_cast<size_t>(i) + static_cast<size_t>(j) * w.stride]) * c.scale;
                }
            }
            const int px = quadrantOffset(1, n), py = quadrantOffset(1, n);
            upsampleAndAdd(parent.data(), s, n, px, py, served.data(), s);
            std::vector<float> fused(s * s, 7.0f); // nothing of it is read
            upsampleAndAddResiduals(parent.data(), s, n, px, py, w, fused.data(), s);
            ASSERT_EQ(std::memcmp(fused.data(), served.data(), s * s * sizeof(float)), 0);
        }
    }
}

TEST(CoarseMesh, RowsAreTheMeshAtEachVertex) {
    const int n = 192, side = n + 5;
    std::vector<float> zm(static_cast<size_t>(side) * side);
    for (size_t k = 0; k < zm.size(); ++k) {
        zm[k] = 1000.0f + 0.1f * static_cast<float>(k % 977) + 3.3f * std::sin(static_cast<float>(k));
    }
    int rows = 0;
    for (const int grid : {192, 96, 64, 48, 24, 12, 2}) {
        for (const int tx : {0, 1}) {
            for (const int ty : {0, 1}) {
                const CoarseMesh mesh(n, grid, tx, ty);
                std::vector<float> row(static_cast<size_t>(n) + 1);
                for (int v = 0; v <= n; ++v) {
                    mesh.mixRow(v, zm.data(), static_cast<size_t>(side), row.data());
                    for (int u = 0; u <= n; ++u) {
                        const CoarseMesh::At a = mesh.at(u, v);
                        const auto z = [&](int x, int y) { return zm[static_cast<size_t>(x + y * side)]; };
                        const float want = coarseMix(a, z(a.x0, a.y0), z(a.x1, a.y0), z(a.x0, a.y1), a.lower ? 0.0f : z(a.x1, a.y1));
                        ASSERT_EQ(std::memcmp(&row[static_cast<size_t>(u)], &want, sizeof want), 0)
                            << "grid " << grid << " tile " << tx << "," << ty << " vertex " << u << "," << v;
                    }
                    ++rows;
                }
            }
        }
    }
    EXPECT_EQ(rows, 7 * 4 * 193);
}

} // namespace
} // namespace pyramid
