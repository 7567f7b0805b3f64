// Ortho region sets (doc/format.md 1.5): an ortho pyramid split into a main file and regions
// serves the single file's tiles through the set producer and `pyramid tile`, verifies against its
// source as the single file does, and a region whose tiles differ from the main file's (channels,
// border, DXT) breaks the set.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/verify/ortho_verify.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"
#include "tests/support/region_sets.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::expectProblem;
using test::programPath;
using test::run;
using test::shellQuoted;

// An ortho pyramid of levels 0..2 written tile by tile, and the same split into a main file of
// level 0 and four regions rooted at level 1: tiles from the set are the single file's.
TEST(RegionSet, OrthoSetServesTheSingleFilesTiles) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 2;
    h.tileSize = 4;
    h.channels = 3;
    const int pixels = h.tilePixels();
    const auto tileOf = [&](int l, int x, int y) {
        std::vector<uint8_t> p(static_cast<size_t>(pixels * pixels * 3));
        for (size_t k = 0; k < p.size(); ++k) {
            p[k] = static_cast<uint8_t>(k * 7 + static_cast<size_t>(l * 31 + x * 11 + y * 5));
        }
        return p;
    };
    const std::string single = dir.file("RGB1.dat");
    {
        OrthoFileWriter w(single, h);
        for (int l = 0; l <= 2; ++l) {
            for (int y = 0; y < (1 << l); ++y) {
                for (int x = 0; x < (1 << l); ++x) {
                    w.writeTile(l, x, y, tileOf(l, x, y));
                }
            }
        }
        w.commit();
    }
    fs::create_directories(dir.file("set"));
    const std::string main = dir.file("set/RGB.dat");
    const auto reader = OrthoFileReader::open(single);
    {
        OrthoHeader m = h;
        m.maxLevel = 0;
        OrthoFileWriter w(main, m);
        w.writeTileBytes(0, 0, 0, reader->readTileBytes(0, 0, 0));
        w.commit();
    }
    std::vector<RegionRoot> roots;
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 2; ++x) {
            OrthoHeader r = h;
            r.maxLevel = 1;
            r.rootLevel = 1;
            r.rootTx = x;
            r.rootTy = y;
            OrthoFileWriter w(regionFilePath(main, {1, x, y}), r);
            w.writeTileBytes(0, 0, 0, reader->readTileBytes(1, x, y));
            for (int k = 0; k < 4; ++k) {
                w.writeTileBytes(1, k % 2, k / 2, reader->readTileBytes(2, 2 * x + k % 2, 2 * y + k / 2));
            }
            w.commit();
            roots.push_back({1, x, y});
        }
    }
    writeRegionIndex(regionIndexPath(main), makeRegionIndex(main, PyramidKind::Ortho, roots));
    const auto set = openOrthoSet(dir.file("set"));
    EXPECT_EQ(set->maxLevel(), 2);
    for (int l = 0; l <= 2; ++l) {
        for (int y = 0; y < (1 << l); ++y) {
            for (int x = 0; x < (1 << l); ++x) {
                EXPECT_EQ(set->tile(l, x, y), reader->readTile(l, x, y)) << l << "," << x << "," << y;
            }
        }
    }
    EXPECT_THROW(openResidualSet(dir.file("set")), Error);
    const std::string pyramid = programPath("pyramid");
    auto r = run(pyramid + " tile " + shellQuoted(single) + " 2 3 1 -o " + shellQuoted(dir.file("a.u8")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = run(pyramid + " tile " + shellQuoted(main) + " 2 3 1 -o " + shellQuoted(dir.file("b.u8")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(test::readFile(dir.file("a.u8")), test::readFile(dir.file("b.u8")));
    r = run(pyramid + " check " + shellQuoted(dir.file("set")));
    EXPECT_EQ(r.exitCode, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("ortho set of 5 files"), std::string::npos) << r.out;
    // Regions whose tiles differ from the main file's: channels, border, DXT.
    const std::string r00 = regionFilePath(main, {1, 0, 0});
    const auto rewrite = [&](int channels, uint32_t flags) {
        OrthoHeader o = h;
        o.maxLevel = 0;
        o.rootLevel = 1;
        o.channels = channels;
        o.flags = flags;
        fs::remove(r00);
        OrthoFileWriter w(r00, o);
        w.writeTile(0, 0, 0, std::vector<uint8_t>(static_cast<size_t>(o.tilePixels() * o.tilePixels() * channels), 9));
        w.commit();
        return pyramidSetProblems(resolvePyramidSet(main));
    };
    expectProblem(rewrite(4, 0), r00, "4 channels, the main file's has 3");
    expectProblem(rewrite(3, OrthoHeader::kFlagNoBorder), r00, "border 0, the main file's is 2");
    expectProblem(rewrite(3, OrthoHeader::kFlagDxt), r00, "DXT tiles, the main file's are not DXT");
}

// Copies ortho tiles as copyResidual does: tile (l, x, y) of the new file is the single file's
// tile (rootLevel + l, from.tx 2^l + x, from.ty 2^l + y) (`from`: the header's root unless given).
void copyOrtho(const OrthoFileReader& single, const std::string& path, const OrthoHeader& h, RegionRoot from) {
    OrthoFileWriter w(path, h);
    for (int l = 0; l <= h.maxLevel; ++l) {
        for (int y = 0; y < (1 << l); ++y) {
            for (int x = 0; x < (1 << l); ++x) {
                w.writeTileBytes(l, x, y, single.readTileBytes(h.rootLevel + l, (from.tx << l) + x, (from.ty << l) + y));
            }
        }
    }
    w.commit();
}

// An ortho pyramid encoded from an image (levels 0..2) and split into a main file of level 0 and
// four regions of levels 1..2 verifies against the image as the single file does; a region
// holding another subtree's tiles fails.
TEST(RegionSet, OrthoSetVerifiesAgainstTheSource) {
    test::TempDir dir;
    const int W = 64;
    std::vector<uint16_t> px(static_cast<size_t>(W * W * 3));
    for (size_t k = 0; k < px.size(); ++k) {
        px[k] = static_cast<uint16_t>((k * 37 + k / 191) % 251);
    }
    test::writeImage(dir.file("in.png"), W, W, 3, px, false);
    OrthoEncodeOptions o;
    o.levels.tileSize = 16;
    o.levels.colourSpace = ColourSpace::Linear;
    o.writeDxt = o.writeResiduals = false;
    encodeOrtho(dir.file("in.png"), dir.file("out"), o);
    const std::string single = dir.file("out/RGB.dat");
    const auto reader = OrthoFileReader::open(single);
    fs::create_directories(dir.file("set"));
    const std::string main = dir.file("set/RGB.dat");
    OrthoHeader m = reader->header();
    m.maxLevel = 0;
    copyOrtho(*reader, main, m, {0, 0, 0});
    std::vector<RegionRoot> roots;
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 2; ++x) {
            OrthoHeader r = reader->header();
            r.maxLevel = 1;
            r.rootLevel = 1;
            r.rootTx = x;
            r.rootTy = y;
            copyOrtho(*reader, regionFilePath(main, {1, x, y}), r, {1, x, y});
            roots.push_back({1, x, y});
        }
    }
    writeRegionIndex(regionIndexPath(main), makeRegionIndex(main, PyramidKind::Ortho, roots));
    OrthoVerifyOptions vo;
    vo.colourSpace = ColourSpace::Linear;
    const OrthoVerifyReport one = verifyOrtho(single, dir.file("in.png"), vo);
    ASSERT_TRUE(one.ok);
    for (const std::string& path : {main, regionIndexPath(main), dir.file("set")}) {
        const OrthoVerifyReport many = verifyOrtho(path, dir.file("in.png"), vo);
        EXPECT_TRUE(many.ok) << path;
        nlohmann::json a = toJson(one), b = toJson(many);
        a.erase("file");
        b.erase("file");
        EXPECT_EQ(a, b) << path;
    }
    const auto cli = run(programPath("pyramid") + " verify " + shellQuoted(dir.file("set")) + " --source " +
                         shellQuoted(dir.file("in.png")) + " --colour-space linear");
    EXPECT_EQ(cli.exitCode, 0) << cli.err << cli.out;
    // Region (1,0,0) holding the tiles of (1,1,0): the set no longer matches its source.
    OrthoHeader r = reader->header();
    r.maxLevel = 1;
    r.rootLevel = 1;
    fs::remove(regionFilePath(main, {1, 0, 0}));
    copyOrtho(*reader, regionFilePath(main, {1, 0, 0}), r, {1, 1, 0});
    EXPECT_FALSE(verifyOrtho(main, dir.file("in.png"), vo).ok);
}

} // namespace
} // namespace pyramid
