// The GL normal producer against the CPU normal producer: every tile of every level, planar
// and on a sphere (including every face of a planet, whose tile borders beyond the face edges
// fold onto the neighbouring faces), for fine and coarse render grids, bit for bit on the
// normals and the coarse normals (llvmpipe rounds float32 and float64 division and square roots
// correctly, as the CPU does).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>

#include "libpyramid/api/encoders.hpp"
#include "libpyramid/api/sources.hpp"
#include "libpyramid/gl/gl_elevation_producer.hpp"
#include "libpyramid/gl/gl_normal_producer.hpp"
#include "libpyramid/runtime/normal_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "tests/support/gl_test_context.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

size_t differingValues(const std::vector<float>& a, const std::vector<float>& b) {
    size_t count = 0;
    for (size_t s = 0; s < a.size(); ++s) {
        count += std::bit_cast<uint32_t>(a[s]) != std::bit_cast<uint32_t>(b[s]) ? 1 : 0;
    }
    return count;
}

// Every tile of levels 0..deepest of `file`, CPU against GL; returns the tiles compared.
int expectSameNormals(const std::string& file, int n, int gridSize, int deepest, const NormalProducerOptions& no) {
    ElevationProducerOptions eo;
    eo.tileSize = n;
    eo.gridSize = gridSize;
    NormalProducer cpu(std::make_shared<ElevationProducer>(openResidualsForElevations(file, n), eo), no);
    GlNormalProducer gl(std::make_shared<GlElevationProducer>(openResidualsForElevations(file, n), eo), no);
    int tiles = 0;
    for (int level = 0; level <= deepest; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                const auto c = cpu.tile(level, tx, ty);
                const NormalTile g = GlNormalProducer::read(*gl.tile(level, tx, ty));
                EXPECT_EQ(g.size, c->size);
                EXPECT_EQ(differingValues(c->normals, g.normals), 0u)
                    << file << " (" << level << "," << tx << "," << ty << ") n " << n << " grid " << gridSize;
                ++tiles;
            }
        }
    }
    return tiles;
}

TEST(GlNormalProducer, PlanarNormalsMatchTheCpuProducer) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    const std::string dem = test::dataPath("proland/DEM.dat");
    NormalProducerOptions no;
    no.size = 50000.0;
    EXPECT_EQ(expectSameNormals(dem, 192, 0, 2, no), 21);
    EXPECT_EQ(expectSameNormals(dem, 48, 0, 3, no), 85);
    EXPECT_EQ(expectSameNormals(dem, 96, 32, 3, no), 85); // 6 samples a mesh cell: 1/6 is inexact
}

TEST(GlNormalProducer, SphericalNormalsMatchTheCpuProducerOnEveryFace) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    NormalProducerOptions no;
    no.deformation = Deformation::Sphere;
    no.size = 6378137.0;
    // The original tools' file as a face (no fold: a root tile's borders lie beyond its edges).
    EXPECT_EQ(expectSameNormals(test::dataPath("proland/DEM.dat"), 48, 0, 3, no), 85);
    // A planet, whose faces' borders fold onto their neighbours.
    test::TempDir dir;
    SphericalDemOptions o;
    o.dem.tileSize = 16;
    o.dem.rootTileSize = 16;
    o.dem.maxLevel = 2;
    o.dem.autoScale = true;
    encodeSphericalDem(PlanetFunction([](double lat, double lon) { return 2000.0 + 1500.0 * std::sin(lat * 0.2) * std::cos(lon * 0.1); }, 256),
                       dir.file("planet"), o);
    for (int face = 1; face <= 6; ++face) {
        EXPECT_EQ(expectSameNormals(dir.file("planet/DEM" + std::to_string(face) + ".dat"), 16, 4, 2, no), 21);
    }
}

} // namespace
} // namespace pyramid
