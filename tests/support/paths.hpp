// Where the tests find their data and the programs they run, and small helpers to run them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace pyramid::test {

std::string dataPath(const std::string& relative);    // tests/data/RELATIVE
std::string corpusPath(const std::string& relative);  // tests/corpus/RELATIVE
std::string samplePath(const std::string& relative);  // samples/RELATIVE
std::string programPath(const std::string& name);     // the built CLI program NAME
// The real inputs shared beside the checkout (../shared/fixtures/RELATIVE, e.g.
// "inputs/mt_rainier_90m.tif"); empty when that folder is not there.
std::string sharedFixturePath(const std::string& relative);

// A fresh empty directory under the system temporary directory, removed at exit of scope.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return path_; }
    std::string file(const std::string& name) const { return path_ + "/" + name; }

private:
    std::string path_;
};

struct RunResult {
    int exitCode = -1;
    std::string out; // stdout
    std::string err; // stderr
};
// Runs a shell command line, capturing stdout and stderr.
RunResult run(const std::string& commandLine);
// `s` in single quotes: one word of a shell command line (a path without a quote in it).
std::string shellQuoted(const std::string& s);
// How many lines a program wrote (the newlines in `s`).
size_t lines(const std::string& s);

bool fileExists(const std::string& path);
// The message of the pyramid::Error (or OptionError) that `f` throws; "" when it throws none.
std::string errorMessage(const std::function<void()>& f);
std::string readFile(const std::string& path);
std::vector<uint8_t> bytesOf(const std::string& path); // readFile's bytes
// Every regular file under `root` (hidden ones included), by its path relative to `root`, with
// its bytes: two builds compare equal when they wrote the same files, byte for byte.
std::map<std::string, std::string> filesUnder(const std::string& root);
// The bytes of every regular file under `root`.
uint64_t bytesUnder(const std::string& root);

} // namespace pyramid::test
