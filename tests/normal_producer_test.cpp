// The CPU normal producer (libpyramid/runtime/normal_producer.hpp, doc/shading.md): a tilted
// plane's normals are the plane's at every level, its coarse normals too; on a sphere of
// constant height the normals are radial on every face and at every level, and where faces
// meet (edges, corners) every face gives a seam vertex the same normal, whatever the heights.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/api/sources.hpp"
#include "libpyramid/runtime/normal_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::TempDir;

constexpr double kRadius = 6378137.0;

// The unit 3-D normal a tile gives at vertex (u, v), in the face's (or plane's) own axes.
std::array<double, 3> localNormal(const NormalTile& t, const NormalGeometry& g, int u, int v, bool coarse = false) {
    const float* p = &t.normals[(static_cast<size_t>(u) + static_cast<size_t>(v) * static_cast<size_t>(t.size)) * 4];
    const double nx = p[coarse ? 2 : 0], ny = p[coarse ? 3 : 1];
    const double nz = std::sqrt(std::max(0.0, 1.0 - nx * nx - ny * ny));
    if (g.deformation == Deformation::Plane) {
        return {nx, ny, nz};
    }
    const std::array<double, 3>&ux = g.ux, &uy = g.uy;
    const std::array<double, 3> up{ux[1] * uy[2] - ux[2] * uy[1], ux[2] * uy[0] - ux[0] * uy[2], ux[0] * uy[1] - ux[1] * uy[0]};
    return {nx * ux[0] + ny * uy[0] + nz * up[0], nx * ux[1] + ny * uy[1] + nz * up[1], nx * ux[2] + ny * uy[2] + nz * up[2]};
}

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

TEST(Normals, ATiltedPlanesNormalsAreThePlanesAtEveryLevel) {
    TempDir dir;
    constexpr int w = 129;
    std::vector<float> heights(static_cast<size_t>(w) * w);
    for (int row = 0; row < w; ++row) {
        for (int x = 0; x < w; ++x) {
            heights[static_cast<size_t>(row) * w + x] = static_cast<float>(100.0 + 0.7 * x + 0.4 * (w - 1 - row));
        }
    }
    test::writeFloatRaster(dir.file("plane.tif"), w, w, heights);
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 32;
    o.scale = 0.01;
    encodeDem(dir.file("plane.tif"), dir.file("plane.dat"), o);
    NormalProducerOptions no;
    no.size = 128.0; // the finest level's samples 1 apart, as the raster's
    NormalProducer normals(openElevationSet(dir.file("plane.dat")), no);
    ASSERT_EQ(normals.tileSize(), 32);
    const double l = std::sqrt(0.7 * 0.7 + 0.4 * 0.4 + 1.0);
    const std::array<double, 3> expected{-0.7 / l, -0.4 / l, 1.0 / l};
    // The heights' quantization (0.01 over 2 samples) moves a slope by up to 0.005.
    constexpr double tolerance = 0.006;
    int checked = 0;
    for (int level = 0; level <= 2; ++level) {
        const int tiles = 1 << level;
        for (int ty = 0; ty < tiles; ++ty) {
            for (int tx = 0; tx < tiles; ++tx) {
                const auto t = normals.tile(level, tx, ty);
                ASSERT_EQ(t->size, 33);
                const NormalGeometry g = normalGeometry(Deformation::Plane, 128.0, 32, level, tx, ty);
                for (int v = 0; v <= 32; ++v) {
                    for (int u = 0; u <= 32; ++u) {
                        const int x = tx * 32 + u, y = ty * 32 + v;
                        if (x == 0 || y == 0 || x == tiles * 32 || y == tiles * 32) {
                            continue; // the map's edge: its border holds what the encoder filled
                        }
                        ASSERT_LT(distance(localNormal(*t, g, u, v), expected), tolerance) << level << " " << x << "," << y;
                        // Coarse normals mix the parent's at its mesh vertices (2 samples apart
                        // here): away from the map's edge by one mesh cell.
                        if (level > 0 && x >= 2 && y >= 2 && x <= tiles * 32 - 2 && y <= tiles * 32 - 2) {
                            ASSERT_LT(distance(localNormal(*t, g, u, v, true), expected), tolerance)
                                << "coarse " << level << " " << x << "," << y;
                        }
                        ++checked;
                    }
                }
            }
        }
    }
    EXPECT_GT(checked, 16000);
    // Without a size the geometry is unknown.
    EXPECT_THROW(NormalProducer(openElevationSet(dir.file("plane.dat")), NormalProducerOptions{}), Error);
}

// `pyramid tile --normals`: the producer's tile, raw (.f32) or as RGBA8 (.png, (v + 1) / 2 * 255,
// north up); a plane's size must be given when no georeference sidecar says it.
TEST(Normals, ThePyramidTileCommandWritesTheProducersTile) {
    TempDir dir;
    std::vector<float> heights(65 * 65);
    for (size_t k = 0; k < heights.size(); ++k) {
        heights[k] = static_cast<float>(50.0 + 3.0 * std::sin(static_cast<double>(k % 65) * 0.3) + 0.2 * static_cast<double>(k / 65));
    }
    test::writeFloatRaster(dir.file("hills.tif"), 65, 65, heights);
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 32;
    o.autoScale = true;
    encodeDem(dir.file("hills.tif"), dir.file("hills.dat"), o);
    const std::string tile = test::programPath("pyramid") + " tile " + dir.file("hills.dat") + " 1 1 0 --normals ";
    ASSERT_EQ(test::run(tile + "--size 640 -o " + dir.file("n.f32")).exitCode, 0);
    NormalProducerOptions no;
    no.size = 640.0;
    NormalProducer normals(openElevationSet(dir.file("hills.dat")), no);
    const auto expected = normals.tile(1, 1, 0);
    const std::string raw = test::readFile(dir.file("n.f32"));
    ASSERT_EQ(raw.size(), expected->normals.size() * sizeof(float));
    EXPECT_EQ(std::memcmp(raw.data(), expected->normals.data(), raw.size()), 0);
    const test::RunResult png = test::run(tile + "--size 640 -o " + dir.file("n.png"));
    ASSERT_EQ(png.exitCode, 0) << png.err;
    OIIO::ImageSpec config; // the channels as stored: no premultiplication by the 4th
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(dir.file("n.png"), &config);
    ASSERT_TRUE(in);
    ASSERT_EQ(in->spec().width, 33);
    ASSERT_EQ(in->spec().nchannels, 4);
    std::vector<uint8_t> pixels(33 * 33 * 4);
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, pixels.data()));
    for (int y = 0; y < 33; ++y) {
        for (int x = 0; x < 33; ++x) {
            for (int c = 0; c < 4; ++c) {
                const double v = expected->normals[(static_cast<size_t>(x) + static_cast<size_t>(32 - y) * 33) * 4 + c];
                ASSERT_EQ(pixels[(static_cast<size_t>(y) * 33 + x) * 4 + c], std::lround((v + 1.0) / 2.0 * 255.0))
                    << x << "," << y << " channel " << c;
            }
        }
    }
    const test::RunResult unknown = test::run(tile + "-o " + dir.file("u.f32"));
    EXPECT_EQ(unknown.exitCode, 1);
    EXPECT_NE(unknown.err.find("give --size"), std::string::npos) << unknown.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("u.f32")));
    EXPECT_EQ(test::run(tile + "--residual -o " + dir.file("r.f32")).exitCode, 1);
}

// The six faces of a planet of `height(latitude, longitude)` metres, 4 levels of 16-interval tiles.
std::string planet(const TempDir& dir, const std::string& name, std::function<double(double, double)> height) {
    SphericalDemOptions o;
    o.dem.tileSize = 16;
    o.dem.rootTileSize = 16;
    o.dem.maxLevel = 3;
    o.dem.autoScale = true;
    o.body = "sphere";
    encodeSphericalDem(PlanetFunction(std::move(height), 512), dir.file(name), o);
    return dir.file(name);
}

// Each face's normals at `level`, every vertex, in world axes (sphere/cube_faces.hpp's face
// table), keyed by the vertex's cube point: a seam vertex gets one entry per face.
std::map<std::array<int64_t, 3>, std::vector<std::array<double, 3>>> worldNormals(const std::string& directory, int level,
                                                                                 double* radialError) {
    std::map<std::array<int64_t, 3>, std::vector<std::array<double, 3>>> out;
    for (int face = 1; face <= 6; ++face) {
        NormalProducerOptions no;
        no.deformation = Deformation::Sphere;
        no.size = kRadius;
        NormalProducer normals(openElevationSet(directory + "/DEM" + std::to_string(face) + ".dat"), no);
        const int n = normals.tileSize(), tiles = 1 << level;
        const FaceGrid grid{int64_t{n} * tiles, FaceGridKind::Vertices};
        // Face-local axes to world axes: the columns of the face table's linear map.
        const auto o = faceDirection(face, 0, 0), ex = faceDirection(face, 1, 0), ey = faceDirection(face, 0, 1);
        const std::array<double, 3> ax{ex[0] - o[0], ex[1] - o[1], ex[2] - o[2]}, ay{ey[0] - o[0], ey[1] - o[1], ey[2] - o[2]};
        for (int ty = 0; ty < tiles; ++ty) {
            for (int tx = 0; tx < tiles; ++tx) {
                const auto t = normals.tile(level, tx, ty);
                const NormalGeometry g = normalGeometry(Deformation::Sphere, kRadius, n, level, tx, ty);
                for (int v = 0; v <= n; ++v) {
                    for (int u = 0; u <= n; ++u) {
                        const auto local = localNormal(*t, g, u, v);
                        const int64_t X = int64_t{tx} * n + u, Y = int64_t{ty} * n + v;
                        if (radialError) {
                            const double x = -1.0 + 2.0 * static_cast<double>(X) / static_cast<double>(grid.n);
                            const double y = -1.0 + 2.0 * static_cast<double>(Y) / static_cast<double>(grid.n);
                            const double r = std::sqrt(x * x + y * y + 1.0);
                            *radialError = std::max(*radialError, distance(local, {x / r, y / r, 1.0 / r}));
                        }
                        const std::array<double, 3> world{local[0] * ax[0] + local[1] * ay[0] + local[2] * o[0],
                                                          local[0] * ax[1] + local[1] * ay[1] + local[2] * o[1],
                                                          local[0] * ax[2] + local[1] * ay[2] + local[2] * o[2]};
                        const CubePoint p = cubePoint(grid, FaceSample{face, X, Y});
                        out[{p.x, p.y, p.z}].push_back(world);
                    }
                }
            }
        }
    }
    return out;
}

TEST(Normals, OnASphereOfConstantHeightTheyAreRadialOnEveryFace) {
    TempDir dir;
    const std::string faces = planet(dir, "round", [](double, double) { return 100.0; });
    for (int level = 0; level <= 3; ++level) {
        double radial = 0.0;
        const auto normals = worldNormals(faces, level, &radial);
        // Central differences on the cube's grid, whose spacing varies across a face: off
        // radial by the second order of the spacing, 6.1e-3 at level 0 (16 intervals a face),
        // a quarter of it a level deeper.
        EXPECT_LT(radial, 6.2e-3 / (1 << (2 * level)) + 1e-6) << "level " << level;
        // Faces that share a vertex agree on its normal.
        int seams = 0;
        for (const auto& [point, list] : normals) {
            for (const auto& other : list) {
                ASSERT_LT(distance(other, list[0]), 1e-6) << "level " << level;
            }
            seams += list.size() > 1;
        }
        const int N = 16 << level;
        EXPECT_GE(seams, 12 * (N - 1) + 8) << "every vertex of the cube's edges (tiles share vertices too)";
    }
}

TEST(Normals, FacesAgreeAtTheirSeamsWhateverTheHeights) {
    TempDir dir;
    const std::string faces = planet(dir, "hilly", [](double latitude, double longitude) {
        return 3000.0 + 2500.0 * std::sin(latitude * 0.21) * std::cos(longitude * 0.13);
    });
    const auto normals = worldNormals(faces, 3, nullptr);
    double worst = 0.0, tilt = 0.0;
    for (const auto& [point, list] : normals) {
        for (const auto& other : list) {
            worst = std::max(worst, distance(other, list[0]));
        }
        const double r = std::sqrt(double(point[0]) * point[0] + double(point[1]) * point[1] + double(point[2]) * point[2]);
        tilt = std::max(tilt, distance(list[0], {point[0] / r, point[1] / r, point[2] / r}));
    }
    // Every face places a seam's samples at the same points; their heights are each face's own
    // reconstruction of the same samples, within the scale of each other: at level 3 (128
    // intervals a face, 78 km apart) that tilts a normal by 2 scale / spacing at most.
    const double scale = ResidualFileReader::readHeader(faces + "/DEM1.dat").scale;
    const double spacing = 2.0 * kRadius / 128.0;
    EXPECT_LT(worst, 2.0 * scale / spacing + 1e-6) << "scale " << scale;
    EXPECT_GT(tilt, 1e-3) << "the heights tilt the normals: the agreement is not the radial one";
}

} // namespace
} // namespace pyramid
