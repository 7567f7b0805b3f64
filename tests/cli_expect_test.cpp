// The command line's words, pinned: each tests/cli_expect/*.case runs one command in a fresh
// directory and holds its exact exit code, stdout, stderr and the files it leaves, so that a
// changed message or a file left behind is a deliberate change (tests/cli_expect/README.md).
//
// PYRAMID_UPDATE_CLI_EXPECT=1 rewrites the cases' expectations from what the programs print.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;

const fs::path kCases = PYRAMID_CLI_EXPECT_DIR;

struct Case {
    std::string head;               // comments, setup and the command, as written
    std::vector<std::string> setup; // "+ LINE": run first, must succeed
    std::string command;            // "$ LINE": the command pinned
    std::string expected;           // "? EXIT", "1 STDOUT LINE", "2 STDERR LINE", "@ FILE LEFT" lines
};

Case readCase(const fs::path& path) {
    std::ifstream in(path);
    Case c;
    bool inHead = true;
    for (std::string line; std::getline(in, line);) {
        if (inHead && (line.empty() || line[0] == '#' || line.rfind("+ ", 0) == 0 || line.rfind("$ ", 0) == 0)) {
            c.head += line + "\n";
            if (line.rfind("+ ", 0) == 0) {
                c.setup.push_back(line.substr(2));
            } else if (line.rfind("$ ", 0) == 0) {
                c.command = line.substr(2);
            }
            continue;
        }
        inHead = false;
        c.expected += line + "\n";
    }
    return c;
}

// One shell line in `dir`, the built programs first on PATH, the test data as $DATA and the
// samples as $SAMPLES.
test::RunResult runIn(const std::string& dir, const std::string& line) {
    test::TempDir scriptDir;
    const std::string script = scriptDir.file("line.sh");
    std::ofstream(script) << line << "\n";
    const std::string bin = fs::path(test::programPath("pyramid")).parent_path().string();
    return test::run("cd '" + dir + "' && PATH='" + bin + "':\"$PATH\" DATA='" + test::dataPath("") + "' SAMPLES='" +
                     test::samplePath("") + "' LC_ALL=C sh '" + script + "'");
}

// A line's closing duration (" 0.1 s", the summaries' elapsed time), which no run repeats,
// written " # s".
std::string withoutDuration(std::string line) {
    if (line.size() < 4 || line.compare(line.size() - 2, 2, " s") != 0) {
        return line;
    }
    size_t begin = line.size() - 2;
    while (begin > 0 && (std::isdigit(static_cast<unsigned char>(line[begin - 1])) || line[begin - 1] == '.')) {
        --begin;
    }
    if (begin == line.size() - 2 || begin == 0 || line[begin - 1] != ' ') {
        return line;
    }
    return line.replace(begin, line.size() - 2 - begin, "#");
}

std::string prefixed(char stream, const std::string& text) {
    std::string lines;
    size_t start = 0;
    while (start < text.size()) {
        const size_t end = text.find('\n', start);
        const std::string line =
            withoutDuration(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
        lines += std::string(1, stream) + (line.empty() ? "" : " " + line) + "\n";
        if (end == std::string::npos) {
            lines += std::string(1, stream) + " (no newline at the end)\n";
            break;
        }
        start = end + 1;
    }
    return lines;
}

// The files under `dir`, sorted, directories with a final '/'.
std::string filesLeft(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        names.push_back(fs::relative(entry.path(), dir).string() + (entry.is_directory() ? "/" : ""));
    }
    std::sort(names.begin(), names.end());
    std::string lines;
    for (const std::string& name : names) {
        lines += "@ " + name + "\n";
    }
    return lines;
}

std::vector<std::string> caseNames() {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(kCases)) {
        if (entry.path().extension() == ".case") {
            names.push_back(entry.path().stem().string());
        }
    }
    std::sort(names.begin(), names.end());
    return names;
}

class CliExpect : public testing::TestWithParam<std::string> {};

TEST_P(CliExpect, PrintsExactlyWhatItsCaseHolds) {
    const fs::path path = kCases / (GetParam() + ".case");
    const Case c = readCase(path);
    ASSERT_FALSE(c.command.empty()) << path << ": no '$ COMMAND' line";
    test::TempDir dir;
    for (const std::string& line : c.setup) {
        const auto r = runIn(dir.path(), line);
        ASSERT_EQ(r.exitCode, 0) << path << ": setup failed: " << line << "\n" << r.out << r.err;
    }
    const auto r = runIn(dir.path(), c.command);
    const std::string actual = "? " + std::to_string(r.exitCode) + "\n" + prefixed('1', r.out) + prefixed('2', r.err) +
                               filesLeft(dir.path());
    if (std::getenv("PYRAMID_UPDATE_CLI_EXPECT") != nullptr) {
        std::ofstream(path) << c.head << actual;
        return;
    }
    EXPECT_EQ(c.expected, actual) << path << "\n(PYRAMID_UPDATE_CLI_EXPECT=1 rewrites it, if the change is meant)";
}

std::string caseTestName(const testing::TestParamInfo<std::string>& info) {
    std::string name = info.param;
    std::replace_if(name.begin(), name.end(), [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)); }, '_');
    return name;
}

INSTANTIATE_TEST_SUITE_P(Cases, CliExpect, testing::ValuesIn(caseNames()), caseTestName);

// The cases must exist: an empty folder would pin nothing.
TEST(CliExpectCases, AreThere) { EXPECT_GE(caseNames().size(), 20u); }

} // namespace
} // namespace pyramid
