// All-or-nothing commits of file sets (formats/staging_directory.hpp): a commit that fails at
// the 4th of 6 files leaves the 6 old files as they were, and the next run rolls back a commit
// that a crash interrupted.
#include <unistd.h>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/staging_directory.hpp"
#include "formats/temporaries.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;

void writeText(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

const std::vector<std::string> kFiles = {"A1.dat", "A2.dat", "A3.dat", "dxt/A4.dat", "dxt/A5.dat", "residuals/A6.dat"};

std::map<std::string, std::string> contents(const std::string& root) {
    std::map<std::string, std::string> files;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
        files[fs::relative(e.path(), root).generic_string()] =
            e.is_regular_file() ? test::readFile(e.path().string()) : std::string("<dir>");
    }
    return files;
}

class StagingCommit : public ::testing::Test {
protected:
    test::TempDir dir;
    std::string out = dir.file("out");

    void SetUp() override {
        fs::create_directories(out + "/dxt");
        fs::create_directories(out + "/residuals");
        for (const std::string& f : kFiles) {
            writeText(out + "/" + f, "old " + f);
        }
    }
    void TearDown() override { StagingDirectory::failRenameForTesting(-1); }

    // Stages the 6 new files (and `extra`, which has no old file) and commits them.
    void stageAndCommit(const std::vector<std::string>& extra = {}) {
        StagingDirectory staging(out);
        for (const std::string& f : kFiles) {
            writeText(staging.path(f), "new " + f);
        }
        for (const std::string& f : extra) {
            writeText(staging.path(f), "new " + f);
        }
        staging.commit();
    }
};

TEST_F(StagingCommit, CommitsTheWholeSet) {
    stageAndCommit({"A0.dat"});
    for (const std::string& f : kFiles) {
        EXPECT_EQ(test::readFile(out + "/" + f), "new " + f);
    }
    EXPECT_EQ(contents(out).size(), kFiles.size() + 3); // dxt/, residuals/, A0.dat
}

TEST_F(StagingCommit, AFailedFourthRenameLeavesTheOldFiles) {
    const auto before = contents(out);
    StagingDirectory::failRenameForTesting(3); // "A0.dat", "A1.dat", "A2.dat", then "A3.dat" fails
    try {
        stageAndCommit({"A0.dat"});
        FAIL() << "the commit succeeded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("A3.dat: cannot move the new output into place"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("old outputs are unchanged"), std::string::npos) << e.what();
    }
    // The old files byte for byte, the new file without an old one gone, no staging left.
    EXPECT_EQ(contents(out), before);
}

// An output replaces the files an earlier run named after it (its region index, the region
// files the index lists, its georeference sidecar): those it does not write again go in the
// same commit, and come back with the old output when the commit fails.
TEST_F(StagingCommit, FilesNamedAfterAnOutputGoWithTheCommit) {
    writeText(out + "/A1.dat.regions.json",
              R"({"format": "libpyramid region set", "version": 1, "kind": "residual", "main": "A1.dat",)"
              R"( "regions": [{"file": "A1-L1-0-1.dat", "root": [1, 0, 1]}, {"file": "A1-L1-1-1.dat", "root": [1, 1, 1]}]})");
    writeText(out + "/A1-L1-0-1.dat", "old region");
    writeText(out + "/A1-L1-1-1.dat", "old region");
    writeText(out + "/A1.dat.georef.json", "old sidecar");
    writeText(out + "/A1-L1-0-0.dat", "not listed: another file"); // named like a region, not the index's
    const auto before = contents(out);
    // A failure after the first file's rename: everything back, the named files too.
    StagingDirectory::failRenameForTesting(2);
    EXPECT_THROW(stageAndCommit(), Error);
    EXPECT_EQ(contents(out), before);
    StagingDirectory::failRenameForTesting(-1);
    // The new A1.dat with its new region A1-L1-1-1.dat: the index, the other region and the
    // sidecar go; the file the index did not list stays.
    stageAndCommit({"A1-L1-1-1.dat"});
    auto after = before;
    for (const std::string& f : kFiles) {
        after[f] = "new " + f;
    }
    after["A1-L1-1-1.dat"] = "new A1-L1-1-1.dat";
    after.erase("A1.dat.regions.json");
    after.erase("A1-L1-0-1.dat");
    after.erase("A1.dat.georef.json");
    EXPECT_EQ(contents(out), after);
}

TEST_F(StagingCommit, ADirectoryInTheWayOfTheFourthFileChangesNothing) {
    fs::remove(out + "/dxt/A4.dat");
    fs::create_directories(out + "/dxt/A4.dat/inside");
    const auto before = contents(out);
    try {
        stageAndCommit();
        FAIL() << "the commit succeeded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("dxt/A4.dat: cannot replace it with the new output: it is a directory"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_EQ(contents(out), before);
}

TEST_F(StagingCommit, TheNextRunRollsBackACommitACrashInterrupted) {
    const auto before = contents(out);
    // A commit that died after its 4th rename, as the disk has it: the journal, the backups
    // of the old files, 4 new files in place and 2 still staged, from a process that is gone.
    const pid_t gone = ::fork();
    if (gone == 0) {
        ::_exit(0);
    }
    ::waitpid(gone, nullptr, 0);
    const std::string staging = out + "/.staging-" + std::to_string(gone) + "-00c0ffee";
    std::string journal;
    for (size_t i = 0; i < kFiles.size(); ++i) {
        const std::string& f = kFiles[i];
        fs::create_directories(fs::path(staging + "/.old/" + f).parent_path());
        fs::create_hard_link(out + "/" + f, staging + "/.old/" + f);
        journal += "old " + f + "\n";
        fs::create_directories(fs::path(staging + "/" + f).parent_path());
        writeText(staging + "/" + f, "new " + f);
        if (i < 4) {
            fs::rename(staging + "/" + f, out + "/" + f);
        }
    }
    writeText(staging + "/.commit", journal);
    EXPECT_EQ(test::readFile(out + "/dxt/A4.dat"), "new dxt/A4.dat");
    EXPECT_EQ(sweepStaleTemporaries(out), 1);
    EXPECT_EQ(contents(out), before);
}

TEST_F(StagingCommit, StagedFilesAreNamedAsTheOutputsInMessages) {
    EXPECT_EQ(outputName("out/.staging-12-ab34cd56/dxt/RGB.dat"), "out/dxt/RGB.dat");
    EXPECT_EQ(outputName("out/.staging-x/RGB.dat"), "out/.staging-x/RGB.dat");
    EXPECT_EQ(outputName("DEM.dat"), "DEM.dat");
}

// A file staged for a commit is known as such (its own rename needs no directory flush: the
// commit flushes the directories it ends up in); a name that merely looks like one is not.
TEST_F(StagingCommit, StagedFilesAreToldFromOthers) {
    EXPECT_TRUE(insideStagingDirectory("out/.staging-12-ab34cd56/dxt/RGB.dat"));
    EXPECT_TRUE(insideStagingDirectory(".staging-12-ab34cd56/DEM.dat"));
    EXPECT_FALSE(insideStagingDirectory("out/.staging-x/RGB.dat"));
    EXPECT_FALSE(insideStagingDirectory("out//dxt/RGB.dat"));
    EXPECT_FALSE(insideStagingDirectory("./DEM.dat"));
    EXPECT_FALSE(insideStagingDirectory("DEM.dat.tmp-12-ab34cd56"));
}

} // namespace
} // namespace pyramid
