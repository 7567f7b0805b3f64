// Region sets written by the ortho preprocessors (--max-file-bytes): every output (TIFF, DXT,
// colour residuals) within the limit, each file a valid region file of the format (doc/format.md
// 1.4), the index listing them, and the set serving the single file's tiles byte for byte.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::TempDir;

const std::vector<std::string> kOutputs = {"RGB.dat", "dxt/RGB.dat", "residuals/RGB.dat"};

OrthoEncodeOptions small() {
    OrthoEncodeOptions o;
    o.levels.tileSize = 16; // 20-pixel tiles with their borders
    return o;
}

struct Built {
    std::vector<std::string> regions; // paths, in the index's order
    nlohmann::json index;
};

Built readSet(const std::string& main) {
    std::ifstream in(main + ".regions.json");
    EXPECT_TRUE(in.good()) << main << ".regions.json";
    Built b;
    b.index = nlohmann::json::parse(in);
    const std::string dir = std::filesystem::path(main).parent_path().string();
    for (const auto& r : b.index.at("regions")) {
        b.regions.push_back(dir + "/" + r.at("file").get<std::string>());
    }
    return b;
}

// Every tile of every level, read through the set `main` + `regions`, as the single file holds
// it: the stored bytes and the decoded pixels.
void expectSameTiles(const std::string& single, const std::string& main, const std::vector<std::string>& regions) {
    const auto one = OrthoFileReader::open(single);
    const OrthoProducer set(main, regions);
    ASSERT_EQ(set.maxLevel(), one->header().maxLevel);
    int64_t compared = 0;
    for (int l = 0; l <= one->header().maxLevel; ++l) {
        for (int ty = 0; ty < (1 << l); ++ty) {
            for (int tx = 0; tx < (1 << l); ++tx) {
                ASSERT_EQ(set.rawTile(l, tx, ty), one->readTileBytes(l, tx, ty)) << main << " tile " << l << "," << tx << "," << ty;
                ASSERT_EQ(set.tile(l, tx, ty), one->readTile(l, tx, ty)) << main << " tile " << l << "," << tx << "," << ty;
                ++compared;
            }
        }
    }
    EXPECT_EQ(compared, one->header().tileCount());
}

// No staging directory or temporary is left in `dir` or below.
void expectNoLeftovers(const std::string& dir) {
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        EXPECT_NE(name.rfind(".staging", 0), 0u) << e.path();
        EXPECT_EQ(name.find(".tmp"), std::string::npos) << e.path();
    }
}

TEST(OrthoSetWriter, SmallLimitSplitsEveryOutputIntoRegionsThatServeTheSingleFilesTiles) {
    TempDir dir;
    const int w = 128; // 16 << 3: levels 0..3
    test::writeImage(dir.file("in.png"), w, w, 3, test::texturedColours(w, w), false);
    OrthoEncodeOptions o = small();
    const OrthoReport single = encodeOrtho(dir.file("in.png"), dir.file("one"), o);
    ASSERT_EQ(single.maxLevel, 3);
    EXPECT_TRUE(single.files.size() == 3 && single.files[0].empty()) << "no sets without the limit";
    const uint64_t cap = 2500;
    o.maxFileBytes = cap;
    const OrthoReport split = encodeOrtho(dir.file("in.png"), dir.file("set"), o);
    ASSERT_EQ(split.files.size(), kOutputs.size());
    ASSERT_EQ(split.bytes.size(), kOutputs.size());

    bool nested = false;
    for (size_t k = 0; k < kOutputs.size(); ++k) {
        const std::string main = dir.file("set/" + kOutputs[k]);
        const Built set = readSet(main);
        EXPECT_EQ(set.index.at("format"), "libpyramid region set");
        EXPECT_EQ(set.index.at("kind"), "ortho");
        EXPECT_EQ(set.index.at("main"), "RGB.dat");
        ASSERT_GT(set.regions.size(), 4u) << kOutputs[k];
        ASSERT_EQ(split.files[k].size(), set.regions.size() + 1) << kOutputs[k];
        EXPECT_EQ(split.files[k][0].first, kOutputs[k]);

        // Every file within the limit; the report's sizes are the files', its total theirs.
        uint64_t total = 0;
        for (const auto& [name, bytes] : split.files[k]) {
            EXPECT_LE(std::filesystem::file_size(dir.file("set/" + name)), cap) << name;
            EXPECT_EQ(std::filesystem::file_size(dir.file("set/" + name)), bytes) << name;
            total += bytes;
        }
        EXPECT_EQ(split.bytes[k], total);

        // The main file: the top levels, rooted at (0, 0, 0); each region the main file's tile size,
        // channels and flags, its root in its name and in the index, and valid alone.
        const OrthoHeader mh = OrthoFileReader::open(main)->header();
        const OrthoHeader oh = OrthoFileReader::open(dir.file("one/" + kOutputs[k]))->header();
        EXPECT_EQ(mh.rootLevel, 0);
        EXPECT_LT(mh.maxLevel, oh.maxLevel);
        for (size_t r = 0; r < set.regions.size(); ++r) {
            const OrthoHeader rh = OrthoFileReader::open(set.regions[r])->header();
            const auto& root = set.index.at("regions")[r].at("root");
            EXPECT_EQ(rh.tileSize, oh.tileSize);
            EXPECT_EQ(rh.channels, oh.channels);
            EXPECT_EQ(rh.flags, oh.flags);
            EXPECT_EQ(rh.rootLevel, root[0].get<int>());
            EXPECT_EQ(rh.rootTx, root[1].get<int>());
            EXPECT_EQ(rh.rootTy, root[2].get<int>());
            EXPECT_EQ(std::filesystem::path(set.regions[r]).filename().string(),
                      regionFilePath("RGB.dat", RegionRoot{rh.rootLevel, rh.rootTx, rh.rootTy}));
            EXPECT_LE(rh.rootLevel + rh.maxLevel, oh.maxLevel);
            nested = nested || rh.rootLevel > mh.maxLevel + 1;
        }
        // A region file alone is a valid file (the program checks the first and the last; the
        // set's own check below covers every file).
        for (const std::string& region : {set.regions.front(), set.regions.back()}) {
            const test::RunResult alone = test::run(test::programPath("pyramid") + " check " + region);
            EXPECT_EQ(alone.exitCode, 0) << region << ": " << alone.out << alone.err;
        }
        EXPECT_TRUE(pyramidSetProblems(resolvePyramidSet(main)).empty()) << kOutputs[k];
        const test::RunResult check = test::run(test::programPath("pyramid") + " check " + main);
        EXPECT_EQ(check.exitCode, 0) << main << ": " << check.out << check.err;
        expectSameTiles(dir.file("one/" + kOutputs[k]), main, set.regions);
    }
    EXPECT_TRUE(nested) << "a limit this small nests regions";
    // The single build's shared tiles are the set's: the same pyramid was written.
    EXPECT_EQ(split.sharedTiles, single.sharedTiles);
    expectNoLeftovers(dir.file("set"));

    // The program writes the same sets (the same bytes) with --max-file-bytes, and its report
    // lists the files.
    const test::RunResult run = test::run(test::programPath("preprocessOrtho") + " -q " + dir.file("in.png") + " -o " +
                                          dir.file("cli") + " --tile-size 16 --max-file-bytes 2500 --report " +
                                          dir.file("report.json"));
    ASSERT_EQ(run.exitCode, 0) << run.err;
    size_t listed = 0;
    for (size_t k = 0; k < kOutputs.size(); ++k) {
        for (const auto& [name, bytes] : split.files[k]) {
            EXPECT_EQ(test::readFile(dir.file("cli/" + name)), test::readFile(dir.file("set/" + name))) << name;
            ++listed;
        }
        EXPECT_EQ(test::readFile(dir.file("cli/" + kOutputs[k] + ".regions.json")),
                  test::readFile(dir.file("set/" + kOutputs[k] + ".regions.json")));
    }
    std::ifstream in(dir.file("report.json"));
    const nlohmann::json report = nlohmann::json::parse(in);
    ASSERT_EQ(report.at("files").size(), listed);
    EXPECT_EQ(report.at("files")[0].at("file"), "RGB.dat");
    EXPECT_EQ(report.at("files")[0].at("bytes").get<uint64_t>(), split.files[0][0].second);
}

TEST(OrthoSetWriter, OutputsThatFitAreTheSingleFilesAndAnIndex) {
    TempDir dir;
    test::writeImage(dir.file("in.png"), 64, 64, 3, test::texturedColours(64, 64), false);
    OrthoEncodeOptions o = small();
    encodeOrtho(dir.file("in.png"), dir.file("one"), o);
    o.maxFileBytes = 0xFFFFFFFF;
    const OrthoReport r = encodeOrtho(dir.file("in.png"), dir.file("set"), o);
    // The program's --max-file-bytes without a size: the same (just under 4 GiB).
    const test::RunResult run = test::run(test::programPath("preprocessOrtho") + " -q " + dir.file("in.png") + " -o " +
                                          dir.file("cli") + " --tile-size 16 --max-file-bytes");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    ASSERT_EQ(r.files.size(), kOutputs.size());
    for (size_t k = 0; k < kOutputs.size(); ++k) {
        const std::string one = test::readFile(dir.file("one/" + kOutputs[k]));
        EXPECT_EQ(test::readFile(dir.file("set/" + kOutputs[k])), one) << kOutputs[k];
        EXPECT_EQ(test::readFile(dir.file("cli/" + kOutputs[k])), one) << kOutputs[k];
        ASSERT_EQ(r.files[k].size(), 1u);
        EXPECT_EQ(r.files[k][0].first, kOutputs[k]);
        EXPECT_EQ(r.files[k][0].second, one.size());
        EXPECT_EQ(r.bytes[k], one.size());
        for (const char* d : {"set/", "cli/"}) {
            const Built set = readSet(dir.file(std::string(d) + kOutputs[k]));
            EXPECT_TRUE(set.regions.empty()) << d << kOutputs[k];
            EXPECT_EQ(set.index.at("kind"), "ortho");
        }
    }
    expectNoLeftovers(dir.file("set"));
}

TEST(OrthoSetWriter, ALimitBelowTheRootTileIsRefusedAndLeavesNothing) {
    TempDir dir;
    test::writeImage(dir.file("in.png"), 64, 64, 3, test::texturedColours(64, 64), false);
    OrthoEncodeOptions o = small();
    o.maxFileBytes = 100;
    try {
        encodeOrtho(dir.file("in.png"), dir.file("out"), o);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("pass the file size limit of 100 bytes"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind(dir.file("out/RGB.dat") + ": ", 0), 0u) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("out")));
    // The program says so in one line and exits 1; a size that is not one is refused.
    const std::string base = test::programPath("preprocessOrtho") + " -q " + dir.file("in.png") + " -o " +
                             dir.file("cli") + " --tile-size 16 --max-file-bytes ";
    const test::RunResult tooSmall = test::run(base + "100");
    EXPECT_EQ(tooSmall.exitCode, 1) << tooSmall.err;
    EXPECT_NE(tooSmall.err.find("pass the file size limit of 100 bytes"), std::string::npos) << tooSmall.err;
    const test::RunResult bad = test::run(base + "12Q");
    EXPECT_EQ(bad.exitCode, 1) << bad.err;
    EXPECT_NE(bad.err.find("--max-file-bytes"), std::string::npos) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("cli")));
}

TEST(OrthoSetWriter, SphericalFacesSplitEachIntoTheirOwnSets) {
    TempDir dir;
    test::writeImage(dir.file("globe.png"), 256, 128, 3, test::texturedColours(256, 128), false);
    SphericalOrthoOptions o;
    o.ortho.levels.tileSize = 16;
    o.ortho.levels.maxLevel = 3;
    o.faces = {2, 5};
    encodeSphericalOrtho(dir.file("globe.png"), dir.file("one"), o);
    const uint64_t cap = 2500;
    o.ortho.maxFileBytes = cap;
    const SphericalOrthoReport r = encodeSphericalOrtho(dir.file("globe.png"), dir.file("set"), o);
    ASSERT_EQ(r.faces.size(), 2u);
    for (size_t f = 0; f < o.faces.size(); ++f) {
        const std::string name = "RGB" + std::to_string(o.faces[f]) + ".dat";
        for (const std::string& sub : {std::string(), std::string("dxt/"), std::string("residuals/")}) {
            const Built set = readSet(dir.file("set/" + sub + name));
            ASSERT_FALSE(set.regions.empty()) << sub << name;
            for (const std::string& region : set.regions) {
                EXPECT_LE(std::filesystem::file_size(region), cap) << region;
                EXPECT_EQ(std::filesystem::path(region).filename().string().rfind(name.substr(0, 4) + "-L", 0), 0u)
                    << region;
            }
            EXPECT_LE(std::filesystem::file_size(dir.file("set/" + sub + name)), cap);
            expectSameTiles(dir.file("one/" + sub + name), dir.file("set/" + sub + name), set.regions);
        }
        ASSERT_EQ(r.faces[f].ortho.files.size(), 3u);
        EXPECT_GT(r.faces[f].ortho.files[0].size(), 1u);
        EXPECT_EQ(r.faces[f].ortho.files[0][0].first, name);
    }
    expectNoLeftovers(dir.file("set"));
}

} // namespace
} // namespace pyramid
