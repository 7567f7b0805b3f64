// The GL elevation producer against the CPU producer on the original tools' DEM.dat: every
// tile of every level, for each elevation tile size (and its delta) and for render grids
// coarser than the tile, bit for bit on zf, zc and zm.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

#include "formats/residual_file.hpp"
#include "libpyramid/encode/residual/residual_recode.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/gl/gl_elevation_producer.hpp"
#include "tests/support/gl_test_context.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

std::string demPath() { return test::dataPath("proland/DEM.dat"); }

std::shared_ptr<const ResidualProducer> residualsFor(int n, const std::string& path = demPath()) {
    return openResidualsForElevations(path, n);
}

// Samples whose bits differ.
size_t differingSamples(const std::vector<float>& a, const std::vector<float>& b) {
    size_t count = 0;
    for (size_t s = 0; s < a.size(); ++s) {
        count += std::bit_cast<uint32_t>(a[s]) != std::bit_cast<uint32_t>(b[s]) ? 1 : 0;
    }
    return count;
}

// The GL producer over `glFile` against the CPU producer over the original file.
void expectSameTiles(int n, int gridSize, int deepestLevel, const std::string& glFile = demPath()) {
    ElevationProducerOptions o;
    o.tileSize = n;
    o.gridSize = gridSize;
    ElevationProducer cpu(residualsFor(n), o);
    GlElevationProducer gl(residualsFor(n, glFile), o);
    ASSERT_EQ(gl.maxLevel(), cpu.maxLevel());
    const int last = std::min(deepestLevel, cpu.maxLevel());
    int tiles = 0;
    for (int level = 0; level <= last; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                auto c = cpu.tile(level, tx, ty);
                const GlElevationTexels g = GlElevationProducer::read(*gl.tile(level, tx, ty));
                ASSERT_EQ(g.size, c->size);
                ASSERT_EQ(differingSamples(c->zf, g.zf), 0u) << "zf of (" << level << "," << tx << "," << ty << ") n " << n;
                ASSERT_EQ(differingSamples(c->zc, g.zc), 0u) << "zc of (" << level << "," << tx << "," << ty << ") n " << n;
                ASSERT_EQ(differingSamples(c->zm(), g.zm), 0u) << "zm of (" << level << "," << tx << "," << ty << ") n " << n;
                ++tiles;
            }
        }
    }
    EXPECT_GT(tiles, 1);
}

TEST(GlElevationProducer, EveryTileSizeMatchesTheCpuProducer) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    expectSameTiles(192, 0, 30); // delta 3: levels 0..2
    expectSameTiles(96, 0, 30);  // delta 2
    expectSameTiles(48, 0, 3);   // delta 1 (every level: gl_verify_test)
    expectSameTiles(24, 0, 3);   // delta 0, the file's own levels below minLevel
}

// The original file recoded with context coding (formats/residual_context.hpp): the GL producer
// over it rebuilds, bit for bit, what the CPU producer rebuilds from the original tools' file.
TEST(GlElevationProducer, ContextCodedFilesMatchTheOriginalsCpuTiles) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    test::TempDir dir;
    ResidualRecodeOptions ro;
    ro.tiles.codec = ResidualCodec::Context;
    const ResidualRecodeReport r = recodeResidualFile(demPath(), dir.file("DEM.dat"), ro);
    EXPECT_LT(r.bytes, r.inputBytes);
    expectSameTiles(192, 0, 30, dir.file("DEM.dat"));
    expectSameTiles(48, 0, 3, dir.file("DEM.dat"));
}

TEST(GlElevationProducer, CoarseRenderGridsMatchTheCpuProducer) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    expectSameTiles(192, 64, 2); // 6 samples per mesh cell: 1/6 is inexact
    expectSameTiles(96, 2, 2);   // one quad per child
    expectSameTiles(24, 8, 3);
}

TEST(GlElevationProducer, ZcDiffersFromZfWhereTheParentMeshIsCoarse) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    auto residuals = residualsFor(96);
    ElevationProducerOptions o;
    o.tileSize = 96;
    GlElevationProducer gl(residuals, o);
    const GlElevationTexels t = GlElevationProducer::read(*gl.tile(2, 1, 2));
    size_t differing = 0;
    for (size_t s = 0; s < t.zf.size(); ++s) {
        differing += t.zf[s] != t.zc[s] ? 1 : 0;
        ASSERT_EQ(t.zf[s], t.zm[s]);
    }
    EXPECT_GT(differing, t.zf.size() / 4); // odd samples interpolate, they do not predict
    // A sample on a parent mesh vertex copies the parent's zm: child (0, 0) of quadrant (1, 0)
    // is parent sample (2 + 48, 2).
    const GlElevationTexels parent = GlElevationProducer::read(*gl.tile(1, 0, 1));
    EXPECT_EQ(t.zc[2 + 2 * 101], parent.zm[50 + 2 * 101]);
}

TEST(GlElevationProducer, RejectsTileSizesWithoutDelta) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    ElevationProducerOptions o;
    o.tileSize = 96;
    EXPECT_THROW(GlElevationProducer(residualsFor(192), o), Error);
}

} // namespace
} // namespace pyramid
