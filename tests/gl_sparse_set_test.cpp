// A sparse residual set (formats/sparse_set.hpp) read by every runtime: the CPU elevation
// producer over the set against the one over the dense file of the same build, the C API over
// both, and the GL producer against the CPU, bit for bit, inside the files, at their edges and
// beyond them (where the set has no more resolution and the dense file holds residual 0).
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "libpyramid/capi/pyramid.h"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"
#include "libpyramid/gl/gl_elevation_producer.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "tests/support/gl_test_context.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sparse_sets.hpp"

namespace pyramid {
namespace {

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    if (a.size() != b.size()) {
        return false;
    }
    for (size_t s = 0; s < a.size(); ++s) {
        if (std::bit_cast<uint32_t>(a[s]) != std::bit_cast<uint32_t>(b[s])) {
            return false;
        }
    }
    return true;
}

struct Built {
    test::TempDir dir;
    std::string dense, sparse;
};

// N = 4096 (levels 0..10 of 32-tiles), heights in a 300-sample patch; the sparse set is a main
// file and regions nested where the square is.
void build(Built& r) {
    ResidualPyramidJob job;
    job.header.tileSize = 32;
    job.header.minLevel = 3;
    job.header.maxLevel = 10;
    job.input = "square";
    const test::Patch heights(1500, 900, 1800, 1200, true);
    job.heights = &heights;
    ResidualEncodeOptions o;
    o.scale = 0.25;
    r.dense = r.dir.file("dense.dat");
    r.sparse = r.dir.file("sparse.dat");
    ResidualPyramidReport report;
    o.layout = PyramidLayout::Dense;
    encodeResidualPyramid(job, r.dense, o, report);
    o.layout = PyramidLayout::Sparse;
    encodeResidualPyramid(job, r.sparse, o, report);
    EXPECT_GE(report.files.size(), 2u);
}

const Built& built() {
    static Built b;
    static const bool made = (build(b), true);
    (void)made;
    return b;
}

// Tiles of level 10 inside the square, on its edges, and far beyond it; and of coarser levels.
std::vector<std::array<int, 3>> someTiles() {
    return {{10, 51, 32}, {10, 46, 28}, {10, 56, 37}, {10, 57, 38}, {10, 45, 27}, {10, 120, 5}, {10, 0, 127},
            {9, 25, 16}, {9, 60, 60},   {8, 12, 8},   {7, 6, 4},    {6, 3, 2},    {5, 1, 1},    {4, 0, 0}};
}

TEST(SparseSetReaders, CpuAndCApiRebuildTheDenseFilesElevations) {
    const Built& b = built();
    ElevationProducer dense(openResidualsForElevations(b.dense, 0), {});
    const std::shared_ptr<ElevationProducer> sparse = openElevationSet(b.sparse);
    pyramid_elevation* capi = nullptr;
    ASSERT_EQ(pyramid_elevation_open(b.sparse.c_str(), 0, 0, 16, &capi), PYRAMID_OK) << pyramid_last_error();
    const int side = pyramid_elevation_side(capi);
    std::vector<float> zf(static_cast<size_t>(side) * side);
    for (const auto& [l, tx, ty] : someTiles()) {
        const int level = l - 3; // the producers' levels: file level minus minLevel
        const auto d = dense.tile(level, tx, ty);
        EXPECT_TRUE(sameBits(sparse->tile(level, tx, ty)->zf, d->zf)) << l << "," << tx << "," << ty;
        ASSERT_EQ(pyramid_elevation_tile(capi, level, tx, ty, zf.data(), nullptr, nullptr, zf.size()), PYRAMID_OK);
        EXPECT_TRUE(sameBits(zf, d->zf)) << "C API " << l << "," << tx << "," << ty;
    }
    // Heights: the deepest level with residuals at the point, the same as the dense file's there.
    double inside = 0.0, outside = 0.0;
    ASSERT_EQ(pyramid_elevation_height(capi, -1, 1650.0 / 4096, 1050.0 / 4096, &inside), PYRAMID_OK);
    EXPECT_EQ(inside, heightAt(dense, 1650.0 / 4096, 1050.0 / 4096).height);
    ASSERT_EQ(pyramid_elevation_height(capi, -1, 0.9, 0.1, &outside), PYRAMID_OK);
    const PointHeight beyond = heightAt(*sparse, 0.9, 0.1);
    EXPECT_LT(beyond.level, 7);
    EXPECT_EQ(outside, beyond.height);
    EXPECT_EQ(outside, heightAt(dense, 0.9, 0.1, beyond.level).height);
    pyramid_elevation_close(capi);
}

TEST(SparseSetReaders, GlRebuildsTheCpusElevations) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    const Built& b = built();
    ElevationProducer cpu(openResidualsForElevations(b.sparse, 0), {});
    GlElevationProducer gl(openResidualsForElevations(b.sparse, 0), {});
    ASSERT_EQ(gl.maxLevel(), cpu.maxLevel());
    for (const auto& [l, tx, ty] : someTiles()) {
        const int level = l - 3;
        const auto c = cpu.tile(level, tx, ty);
        const GlElevationTexels g = GlElevationProducer::read(*gl.tile(level, tx, ty));
        EXPECT_TRUE(sameBits(g.zf, c->zf)) << l << "," << tx << "," << ty;
        EXPECT_TRUE(sameBits(g.zc, c->zc)) << l << "," << tx << "," << ty;
    }
}

} // namespace
} // namespace pyramid
