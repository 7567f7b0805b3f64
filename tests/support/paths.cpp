#include "tests/support/paths.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "formats/error.hpp"

namespace pyramid::test {

std::string dataPath(const std::string& relative) { return std::string(PYRAMID_TEST_DATA) + "/" + relative; }
std::string corpusPath(const std::string& relative) { return std::string(PYRAMID_TEST_CORPUS) + "/" + relative; }
std::string samplePath(const std::string& relative) { return std::string(PYRAMID_SAMPLES) + "/" + relative; }
std::string programPath(const std::string& name) { return std::string(PYRAMID_BIN_DIR) + "/" + name; }
std::string sharedFixturePath(const std::string& relative) {
    const std::string path = std::string(PYRAMID_SHARED_FIXTURES) + "/" + relative;
    return fileExists(path) ? path : std::string();
}

TempDir::TempDir() {
    std::random_device rd;
    const auto base = std::filesystem::temp_directory_path();
    for (int attempt = 0; attempt < 100; ++attempt) {
        auto candidate = base / ("pyramid-test-" + std::to_string(rd()));
        if (std::filesystem::create_directory(candidate)) {
            path_ = candidate.string();
            return;
        }
    }
    throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

RunResult run(const std::string& commandLine) {
    TempDir dir;
    const std::string out = dir.file("stdout");
    const std::string err = dir.file("stderr");
    const std::string full = commandLine + " >" + out + " 2>" + err;
    const int status = std::system(full.c_str());
    RunResult r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = readFile(out);
    r.err = readFile(err);
    return r;
}

std::string shellQuoted(const std::string& s) { return "'" + s + "'"; }

size_t lines(const std::string& s) { return static_cast<size_t>(std::count(s.begin(), s.end(), '\n')); }

bool fileExists(const std::string& path) { return std::filesystem::exists(path); }

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<uint8_t> bytesOf(const std::string& path) {
    const std::string text = readFile(path);
    return std::vector<uint8_t>(text.begin(), text.end());
}

std::map<std::string, std::string> filesUnder(const std::string& root) {
    std::map<std::string, std::string> files;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
        if (e.is_regular_file()) {
            files[std::filesystem::relative(e.path(), root).string()] = readFile(e.path().string());
        }
    }
    return files;
}

uint64_t bytesUnder(const std::string& root) {
    uint64_t bytes = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
        bytes += e.is_regular_file() ? e.file_size() : 0;
    }
    return bytes;
}

std::string errorMessage(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace pyramid::test
