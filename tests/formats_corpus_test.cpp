// Every file of the broken-file corpus (tests/corpus, written by make_corpus.py) is rejected
// with a pyramid::Error whose one-line message names the file and says what is wrong; the
// valid files the corpus derives from decode completely, which proves each broken file is
// broken by its own mutation only.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_file.hpp"
#include "formats/tiff_tile.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

struct CorpusEntry {
    std::string file;     // relative to tests/corpus
    std::string decoder;  // "residual", "ortho", "residual-tiff S", "ortho-tiff S C", "dxt1 W H", ...
    std::string expected; // "ok", or a fragment of the expected error message
};

// Test names and failures show the file, not the bytes of the struct.
void PrintTo(const CorpusEntry& e, std::ostream* os) { *os << e.file; }

std::vector<CorpusEntry> loadManifest() {
    std::vector<CorpusEntry> entries;
    std::ifstream in(test::corpusPath("MANIFEST"));
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') {
            continue;
        }
        const size_t a = line.find('\t');
        const size_t b = line.find('\t', a + 1);
        if (a == std::string::npos || b == std::string::npos) {
            throw std::runtime_error("MANIFEST: malformed line: " + line);
        }
        entries.push_back({line.substr(0, a), line.substr(a + 1, b - a - 1), line.substr(b + 1)});
    }
    return entries;
}

std::vector<uint8_t> readBytes(const std::string& path) {
    const std::string s = test::readFile(path);
    return std::vector<uint8_t>(s.begin(), s.end());
}

template <class Reader, class TilesPerSide>
void readEveryTile(const Reader& reader, int maxLevel, TilesPerSide tilesPerSide) {
    for (int level = 0; level <= maxLevel; ++level) {
        const int side = static_cast<int>(tilesPerSide(level));
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                reader.readTile(level, tx, ty);
            }
        }
    }
}

// Opens or decodes `path` the way `decoder` says, reading every tile of pyramid files.
void decode(const std::string& path, const std::string& decoder) {
    std::istringstream words(decoder);
    std::string kind;
    int a = 0, b = 0;
    words >> kind >> a >> b;
    if (kind == "residual") {
        auto reader = ResidualFileReader::open(path);
        const ResidualHeader& h = reader->header();
        readEveryTile(*reader, h.maxLevel, [&](int level) { return h.tilesPerSide(level); });
    } else if (kind == "ortho") {
        auto reader = OrthoFileReader::open(path);
        readEveryTile(*reader, reader->header().maxLevel, [](int level) { return int64_t{1} << level; });
    } else if (kind == "tiff") {
        decodeTiff(readBytes(path), a, b, path);
    } else if (kind == "residual-tiff") {
        decodeResidualTiff(readBytes(path), a, path);
    } else if (kind == "residual-tile") {
        decodeResidualBlob(readBytes(path), a, path);
    } else if (kind == "ortho-tiff") {
        decodeOrthoTiff(readBytes(path), a, b, path);
    } else if (kind == "dxt1" || kind == "dxt5") {
        decodeDxt(readBytes(path), a, b, kind == "dxt1" ? DxtFormat::Dxt1 : DxtFormat::Dxt5, path);
    } else {
        throw std::runtime_error("MANIFEST: unknown decoder " + decoder);
    }
}

void expectGoodMessage(const std::string& what, const std::string& path, const std::string& fragment) {
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << "the message does not start with the file name: " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << "expected \"" << fragment << "\" in: " << what;
}

class Corpus : public testing::TestWithParam<CorpusEntry> {};

TEST_P(Corpus, RejectedWithAnErrorNamingTheFile) {
    const CorpusEntry& e = GetParam();
    const std::string path = test::corpusPath(e.file);
    ASSERT_TRUE(test::fileExists(path)) << path;
    ASSERT_FALSE(e.expected.empty()) << "MANIFEST: no expected message for " << e.file;
    if (e.expected == "ok") {
        EXPECT_NO_THROW(decode(path, e.decoder));
        return;
    }
    bool openFailed = false;
    try {
        decode(path, e.decoder);
        ADD_FAILURE() << e.file << " was accepted";
    } catch (const Error& error) {
        expectGoodMessage(error.what(), path, e.expected);
        if (e.decoder == "residual") {
            try {
                ResidualFileReader::open(path);
            } catch (const Error&) {
                openFailed = true;
            }
        } else if (e.decoder == "ortho") {
            try {
                OrthoFileReader::open(path);
            } catch (const Error&) {
                openFailed = true;
            }
        }
    } catch (const std::exception& other) {
        ADD_FAILURE() << e.file << ": not a pyramid::Error: " << other.what();
    }
    // A file its own reader cannot open is never detected as that kind.
    if (openFailed) {
        const PyramidKind own = e.decoder == "residual" ? PyramidKind::Residual : PyramidKind::Ortho;
        try {
            EXPECT_NE(detectPyramidKind(path), own) << e.file;
        } catch (const Error& error) {
            expectGoodMessage(error.what(), path, "");
        }
    }
}

std::string testName(const testing::TestParamInfo<CorpusEntry>& info) {
    std::string name = info.param.file;
    for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) {
            c = '_';
        }
    }
    return name;
}

INSTANTIATE_TEST_SUITE_P(Files, Corpus, testing::ValuesIn(loadManifest()), testName);

TEST(CorpusManifest, ListsEveryFileAndOnlyExistingOnes) {
    const auto entries = loadManifest();
    std::set<std::string> listed;
    size_t broken = 0;
    for (const CorpusEntry& e : entries) {
        listed.insert(e.file);
        broken += e.expected != "ok";
    }
    EXPECT_EQ(listed.size(), entries.size()) << "a file is listed twice";
    EXPECT_GE(broken, 100u) << "the corpus lost files";
    std::set<std::string> present;
    for (const char* dir : {"valid", "residual", "ortho", "tiff", "context", "dxt"}) {
        for (const auto& f : std::filesystem::directory_iterator(test::corpusPath(dir))) {
            present.insert(std::string(dir) + "/" + f.path().filename().string());
        }
    }
    EXPECT_EQ(present, listed);
}

TEST(CorpusPaths, DirectoryAndMissingFileAreErrorsNamingThem) {
    for (const std::string& path : {test::corpusPath("residual"), test::corpusPath("no-such-file.dat")}) {
        for (int which = 0; which < 3; ++which) {
            try {
                if (which == 0) {
                    ResidualFileReader::open(path);
                } else if (which == 1) {
                    OrthoFileReader::open(path);
                } else {
                    detectPyramidKind(path);
                }
                ADD_FAILURE() << path << " was opened";
            } catch (const Error& error) {
                expectGoodMessage(error.what(), path, "");
            }
        }
    }
}

} // namespace
} // namespace pyramid
