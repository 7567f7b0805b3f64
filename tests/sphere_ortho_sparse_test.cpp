// Ortho sparse sets (doc/format.md 1.5, "Sparse sets"; doc/spherical.md, "Files where the map
// is"): a small map on a planet writes, for each output, the files that hold its data. Tile for
// tile they are the dense build's: every tile a sparse set holds has the dense file's bytes, and
// every tile it leaves out is blank in the dense file (colour residuals: 128, so the colour
// producer rebuilds the same colours). The build is deterministic, verifies against the map, and
// writes a small fraction of the dense bytes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/verify/ortho_verify.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

constexpr int kTile = 32, kLevels = 7;

// 160 x 120 pixels of 0.01 degree at 10..11.6 E, 45.5..44.3 N: across the edge between faces 1
// and 3 (at about 44.6 N there), colours that vary everywhere (no pixel black).
std::string writeMap(const test::TempDir& dir) {
    const int w = 160, h = 120;
    std::vector<uint8_t> rgb(static_cast<size_t>(w) * h * 3);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            uint8_t* p = &rgb[(static_cast<size_t>(y) * w + x) * 3];
            p[0] = static_cast<uint8_t>(40 + (x * 7) % 200);
            p[1] = static_cast<uint8_t>(30 + (y * 5 + x) % 210);
            p[2] = static_cast<uint8_t>(128 + 100 * std::sin(x * 0.21) * std::cos(y * 0.17));
        }
    }
    const std::string path = dir.file("map.tif");
    test::writeGeoTiffRgb(path, w, h, rgb, test::geographicTags(4326, 10.0, 45.5, 0.01));
    return path;
}

SphericalOrthoReport build(const std::string& map, const std::string& out, PyramidLayout layout, int threads = 2) {
    SphericalOrthoOptions o;
    o.ortho.levels.tileSize = kTile;
    o.ortho.levels.maxLevel = kLevels;
    o.ortho.levels.threads = threads;
    o.ortho.layout = layout;
    return encodeSphericalOrtho(map, out, o);
}

std::vector<char> contents(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The decoded samples of a stored tile are all `value`.
bool all(const std::vector<uint8_t>& samples, uint8_t value) {
    return std::all_of(samples.begin(), samples.end(), [value](uint8_t v) { return v == value; });
}

class SphereOrthoSparse : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir();
        map_ = writeMap(*dir_);
        sparse_ = new SphericalOrthoReport(build(map_, dir_->file("sparse"), PyramidLayout::Sparse));
        dense_ = new SphericalOrthoReport(build(map_, dir_->file("dense"), PyramidLayout::Dense));
    }
    static void TearDownTestSuite() {
        delete sparse_;
        delete dense_;
        delete dir_;
    }
    static test::TempDir* dir_;
    static std::string map_;
    static SphericalOrthoReport* sparse_;
    static SphericalOrthoReport* dense_;
};
test::TempDir* SphereOrthoSparse::dir_ = nullptr;
std::string SphereOrthoSparse::map_;
SphericalOrthoReport* SphereOrthoSparse::sparse_ = nullptr;
SphericalOrthoReport* SphereOrthoSparse::dense_ = nullptr;

TEST_F(SphereOrthoSparse, EveryTileIsTheDenseBuildsOrBlank) {
    int64_t held = 0, left = 0, data = 0;
    for (const std::string sub : {"", "dxt", "residuals"}) {
        for (const int face : {1, 3, 5}) { // the map's faces and one it does not reach
            SCOPED_TRACE(sub + " face " + std::to_string(face));
            const auto sparse = openOrthoSet(faceFilePath(dir_->file("sparse/" + sub), "RGB", face));
            const auto dense = openOrthoSet(faceFilePath(dir_->file("dense/" + sub), "RGB", face));
            ASSERT_EQ(dense->maxLevel(), kLevels);
            ASSERT_LE(sparse->maxLevel(), kLevels);
            const bool residuals = sub == "residuals";
            for (int l = 0; l <= kLevels; ++l) {
                for (int ty = 0; ty < (1 << l); ++ty) {
                    for (int tx = 0; tx < (1 << l); ++tx) {
                        const std::vector<uint8_t> want = dense->rawTile(l, tx, ty);
                        if (sparse->hasTile(l, tx, ty)) {
                            ++held;
                            const std::vector<uint8_t> got = sparse->rawTile(l, tx, ty);
                            ASSERT_TRUE(got == want) << "tile (" << l << "," << tx << "," << ty << ")";
                        } else {
                            ++left;
                            // Left out: no tile (TIFF, DXT) where the dense tile is blank, or
                            // residual 128 where the dense residuals are all 128.
                            ASSERT_TRUE(all(dense->tile(l, tx, ty), residuals ? 128 : 0))
                                << "tile (" << l << "," << tx << "," << ty << ") left out";
                        }
                        data += !residuals && l == kLevels && !all(dense->tile(l, tx, ty), 0);
                    }
                }
            }
        }
    }
    EXPECT_GT(data, 20);        // the map reaches level 7 on two faces
    EXPECT_GT(left, 10 * held); // and most of the planet is left out
}

TEST_F(SphereOrthoSparse, ColourProducersRebuildTheDenseColours) {
    for (const int face : {1, 3, 5}) {
        ColourProducer sparse(openOrthoSet(faceFilePath(dir_->file("sparse/residuals"), "RGB", face)), 4096);
        ColourProducer dense(openOrthoSet(faceFilePath(dir_->file("dense/residuals"), "RGB", face)), 4096);
        for (int ty = 0; ty < (1 << kLevels); ++ty) {
            for (int tx = 0; tx < (1 << kLevels); ++tx) {
                ASSERT_TRUE(*sparse.tile(kLevels, tx, ty) == *dense.tile(kLevels, tx, ty))
                    << "face " << face << " tile (" << kLevels << "," << tx << "," << ty << ")";
            }
        }
    }
}

TEST_F(SphereOrthoSparse, FilesWhereTheMapIsAndVerifyPasses) {
    const uint64_t sparseBytes = test::bytesUnder(dir_->file("sparse")), denseBytes = test::bytesUnder(dir_->file("dense"));
    EXPECT_LT(sparseBytes * 20, denseBytes) << sparseBytes << " against " << denseBytes;
    // A face the map does not reach is its root tile and the index: a few KB per output.
    for (const std::string sub : {"", "dxt/", "residuals/"}) {
        const std::string main = dir_->file("sparse/" + sub + "RGB5.dat");
        EXPECT_LT(std::filesystem::file_size(main), 8192u) << main;
        EXPECT_TRUE(readRegionIndex(regionIndexPath(main)).regions.empty());
    }
    EXPECT_FALSE(readRegionIndex(regionIndexPath(dir_->file("sparse/RGB3.dat"))).regions.empty());
    for (const bool residuals : {false, true}) {
        SphericalOrthoVerifyOptions v;
        v.colourResiduals = residuals;
        for (const auto& r : verifySphericalOrtho(dir_->file(residuals ? "sparse/residuals" : "sparse"), {map_}, v)) {
            EXPECT_TRUE(r.ok) << r.file;
            EXPECT_EQ(r.levels.size(), static_cast<size_t>(kLevels) + 1) << r.file;
        }
    }
}

TEST_F(SphereOrthoSparse, SameBytesWhateverTheThreads) {
    const std::string one = dir_->file("one-thread");
    build(map_, one, PyramidLayout::Sparse, 1);
    size_t files = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir_->file("sparse"))) {
        if (!e.is_regular_file()) {
            continue;
        }
        const auto relative = std::filesystem::relative(e.path(), dir_->file("sparse"));
        ASSERT_TRUE(std::filesystem::exists(std::filesystem::path(one) / relative)) << relative;
        EXPECT_TRUE(contents(e.path()) == contents(std::filesystem::path(one) / relative)) << relative;
        ++files;
    }
    size_t oneFiles = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(one)) {
        oneFiles += e.is_regular_file();
    }
    EXPECT_EQ(files, oneFiles);
}

// A build split into parts (--part I/N, then pyramid merge) writes the single run's sparse sets,
// byte for byte, in both walk orders (with colour residuals and TIFF or DXT: two walks; colour
// residuals alone: top levels first; without them: subtrees first).
TEST_F(SphereOrthoSparse, PartsMergeIntoTheSingleRunsSets) {
    for (const std::string outputs : {"tiff,dxt,residuals", "residuals", "tiff"}) {
        const std::string cmd = test::programPath("preprocessSphericalOrtho") + " " + map_ + " --outputs " + outputs +
                                " --tile-size 32 --max-level 7 --faces 1,3,5 -q -o ";
        const std::string one = dir_->file("one-" + outputs);
        ASSERT_EQ(test::run(cmd + one).exitCode, 0);
        ASSERT_TRUE(std::filesystem::exists(regionIndexPath(faceFilePath(one, "RGB", 3))) ||
                    std::filesystem::exists(regionIndexPath(faceFilePath(one + "/residuals", "RGB", 3))));
        for (const int count : {2, 3}) {
            const std::string parts = dir_->file("p" + std::to_string(count) + "-" + outputs);
            for (int i = 0; i < count; ++i) {
                const test::RunResult r =
                    test::run(cmd + parts + " --threads " + std::to_string(1 + i % 2) + " --part " + std::to_string(i) +
                              "/" + std::to_string(count));
                ASSERT_EQ(r.exitCode, 0) << r.err;
            }
            const test::RunResult m = test::run(test::programPath("pyramid") + " merge -q " + parts + "/RGB.part-*");
            ASSERT_EQ(m.exitCode, 0) << m.err;
            auto merged = test::filesUnder(parts);
            std::erase_if(merged, [](const auto& f) { return f.first.find(".part-") != std::string::npos; });
            EXPECT_TRUE(merged == test::filesUnder(one)) << outputs << ", " << count << " parts";
        }
    }
}

} // namespace
} // namespace pyramid
