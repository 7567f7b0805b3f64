// What a failed or stopped run leaves (doc/failure.md), on the real programs: SIGINT at about
// 10, 50 and 90 % of a DEM, an ortho and a spherical run, SIGTERM and SIGHUP, a file size limit
// below the output's size, output paths that cannot be written, and the sweep of stale
// temporaries. Each time: no temporary left, the previous outputs byte for byte.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::programPath;

void writeText(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// Every file and directory under `root` (hidden ones included), with the files' bytes.
std::map<std::string, std::string> snapshot(const std::string& root) {
    std::map<std::string, std::string> files;
    if (!fs::exists(root)) {
        return files;
    }
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
        const std::string relative = fs::relative(e.path(), root).generic_string();
        files[relative] = e.is_regular_file() ? test::readFile(e.path().string()) : std::string("<dir>");
    }
    return files;
}

std::string names(const std::map<std::string, std::string>& files) {
    std::string s;
    for (const auto& [name, bytes] : files) {
        s += name + " (" + std::to_string(bytes.size()) + " bytes)\n";
    }
    return s;
}

// Whether `directory` holds a temporary of a run (listed while the run writes into it).
bool hasTemporary(const std::string& directory) {
    std::error_code ec;
    for (fs::directory_iterator it(directory, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.find(".tmp-") != std::string::npos || name.find(".staging-") != std::string::npos) {
            return true;
        }
    }
    return false;
}

// A program running with its stderr on a pipe, read line by line.
class Child {
public:
    explicit Child(const std::vector<std::string>& args, rlim_t fileSizeLimit = RLIM_INFINITY) {
        int fds[2];
        if (::pipe2(fds, O_CLOEXEC) != 0) {
            throw std::runtime_error("pipe");
        }
        std::vector<char*> argv;
        for (const std::string& a : args) {
            argv.push_back(const_cast<char*>(a.c_str()));
        }
        argv.push_back(nullptr);
        pid_ = ::fork();
        if (pid_ == 0) {
            ::dup2(fds[1], 2);
            const int null = ::open("/dev/null", O_WRONLY);
            ::dup2(null, 1);
            if (fileSizeLimit != RLIM_INFINITY) {
                const rlimit limit{fileSizeLimit, fileSizeLimit};
                ::setrlimit(RLIMIT_FSIZE, &limit);
            }
            ::execv(argv[0], argv.data());
            ::_exit(127);
        }
        ::close(fds[1]);
        in_ = ::fdopen(fds[0], "r");
    }
    ~Child() {
        if (pid_ > 0 && !waited_) {
            ::kill(pid_, SIGKILL);
            wait();
        }
        if (in_) {
            std::fclose(in_);
        }
    }

    pid_t pid() const { return pid_; }
    const std::string& err() const { return err_; }

    // The next line of stderr (false at its end).
    bool line(std::string& out) {
        out.clear();
        int c;
        while ((c = std::fgetc(in_)) != EOF) {
            if (c == '\n') {
                err_ += out + "\n";
                return true;
            }
            out += static_cast<char>(c);
        }
        err_ += out;
        return !out.empty();
    }

    // Closes the reading end of stderr, as `2>&1 | head -n 1` does after its line.
    void closeErr() {
        std::fclose(in_);
        in_ = nullptr;
    }

    // Reads stderr to its end and returns the exit status (-signal when killed by one).
    int wait() {
        std::string l;
        while (in_ && line(l)) {
        }
        int status = 0;
        ::waitpid(pid_, &status, 0);
        waited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    }

private:
    pid_t pid_ = -1;
    FILE* in_ = nullptr;
    std::string err_;
    bool waited_ = false;
};

// The percentage of a progress line "LABEL: 42% (1234/2938)", else -1.
int percentOf(const std::string& line) {
    const size_t pc = line.find("% (");
    if (pc == std::string::npos || pc < 3) {
        return -1;
    }
    return std::atoi(line.substr(pc - 3, 3).c_str());
}

struct Stopped {
    int exitCode = -1;
    bool temporarySeen = false;
    std::string err;
};

// Runs `args`, sends `signal` once a progress line reaches `percent` (or at once when
// `percent` < 0), and waits for the exit.
Stopped stopAt(const std::vector<std::string>& args, int percent, int signal, const std::string& outputDir) {
    Child child(args);
    std::string line;
    Stopped s;
    while (child.line(line)) {
        const int p = percentOf(line);
        if (percent < 0 || (p >= percent && p < 100)) {
            s.temporarySeen = hasTemporary(outputDir);
            ::kill(child.pid(), signal);
            s.exitCode = child.wait();
            s.err = child.err();
            return s;
        }
    }
    s.exitCode = child.wait();
    s.err = "the run ended before " + std::to_string(percent) + "%:\n" + child.err();
    return s;
}

int runToEnd(const std::vector<std::string>& args, std::string* err = nullptr, rlim_t limit = RLIM_INFINITY) {
    Child child(args, limit);
    const int code = child.wait();
    if (err) {
        *err = child.err();
    }
    return code;
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
}

class Failure : public ::testing::Test {
protected:
    test::TempDir dir;
    std::string out = dir.file("out");

    // Builds with `previous`, then stops runs with `next` at about 10, 30 and 50 %: each leaves
    // the previous outputs as they were, and nothing else. `next` builds a finer pyramid than
    // `previous` (another maxLevel in every header), so a replaced output cannot go unseen; it
    // takes about a second with 2 threads in a Release build, and the previous one less.
    void expectInterruptionsLeaveNothing(const std::vector<std::string>& previous, const std::vector<std::string>& next,
                                         const std::string& outputDir) {
        std::string err;
        ASSERT_EQ(runToEnd(previous, &err), 0) << err;
        const auto before = snapshot(outputDir);
        ASSERT_FALSE(before.empty());
        // (50 %, not later: the test reads the child's progress through a pipe, and on a loaded
        // machine it may read a line late. Half the run is the margin, 0.4 s and more: the last
        // quarter of an ortho run's tiles, the coarse levels, reach the writer in a few ms.)
        for (const int percent : {10, 30, 50}) {
            const Stopped s = stopAt(next, percent, SIGINT, outputDir);
            EXPECT_EQ(s.exitCode, 130) << percent << "%\n" << s.err;
            // Stopped where it was: no tile after the signal took it to the end.
            EXPECT_EQ(s.err.find("100% ("), std::string::npos) << percent << "%\n" << s.err;
            EXPECT_TRUE(s.temporarySeen) << percent << "%: the run had no temporary to remove yet";
            EXPECT_NE(s.err.find("stopped by SIGINT"), std::string::npos) << s.err;
            EXPECT_EQ(s.err.find("\n\n"), std::string::npos) << s.err; // no empty line: no bar was open
            const auto after = snapshot(outputDir);
            EXPECT_EQ(names(after), names(before)) << percent << "%";
            EXPECT_TRUE(after == before) << percent << "%: the previous outputs changed";
        }
    }
};

TEST_F(Failure, SigintDuringADemRunLeavesThePreviousFile) {
    const std::vector<std::string> base = {programPath("preprocessDem"), test::samplePath("dem.tif"), "-o",
                                           out + "/DEM.dat", "--threads", "2"};
    expectInterruptionsLeaveNothing(with(base, {"--max-level", "6"}), with(base, {"--max-level", "9"}), out);
}

TEST_F(Failure, SigintDuringAnOrthoRunLeavesThePreviousFiles) {
    const std::vector<std::string> base = {programPath("preprocessOrtho"), test::samplePath("bluemarble.png"), "-o",
                                           out, "--threads", "2"};
    expectInterruptionsLeaveNothing(with(base, {"--max-level", "2"}), with(base, {"--max-level", "6"}), out);
}

TEST_F(Failure, SigintDuringASphericalRunLeavesThePreviousFaces) {
    const std::vector<std::string> base = {programPath("preprocessSphericalDem"), test::samplePath("srtm.png"), "-o",
                                           out, "--threads", "2"};
    expectInterruptionsLeaveNothing(with(base, {"--max-level", "3"}), with(base, {"--max-level", "6"}), out);
}

TEST_F(Failure, SigtermAndSighupExitWith143And129) {
    const std::vector<std::string> args = {programPath("preprocessDem"), test::samplePath("dem.tif"), "-o",
                                           out + "/sub/DEM.dat", "--threads", "2", "--max-level", "8"};
    for (const auto& [signal, code] : {std::pair{SIGTERM, 143}, std::pair{SIGHUP, 129}}) {
        const Stopped s = stopAt(args, 0, signal, out + "/sub");
        EXPECT_EQ(s.exitCode, code) << s.err;
        EXPECT_TRUE(s.temporarySeen);
        // The directories the run made for its output are gone too.
        EXPECT_FALSE(fs::exists(out)) << names(snapshot(out));
    }
}

TEST_F(Failure, AFileSizeLimitIsAFullDiskThatLeavesNothing) {
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, 513, 513, test::syntheticHeights(513, 513, 3000.0f));
    std::string err;
    // preprocessDem into directories it makes: the limit (64 KB) is below the file's size.
    EXPECT_EQ(runToEnd({programPath("preprocessDem"), input, "-o", out + "/a/b/DEM.dat", "-q"}, &err, 64 << 10), 1);
    EXPECT_NE(err.find("DEM.dat: cannot write: file too large"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(out)) << names(snapshot(out));
    // preprocessSphericalOrtho into an existing directory with a previous build.
    fs::create_directories(out);
    const std::vector<std::string> ortho = {programPath("preprocessSphericalOrtho"), test::samplePath("bluemarble.png"),
                                            "-o", out, "--max-level", "2", "-q"};
    ASSERT_EQ(runToEnd(with(ortho, {"--deflate-level", "1"}), &err), 0) << err;
    const auto before = snapshot(out);
    EXPECT_EQ(runToEnd(ortho, &err, 64 << 10), 1);
    EXPECT_NE(err.find("file too large"), std::string::npos) << err;
    EXPECT_EQ(err.find(".staging-"), std::string::npos) << "the message names the output, not its temporary: " << err;
    EXPECT_TRUE(snapshot(out) == before) << names(snapshot(out));
}

TEST_F(Failure, AReaderOfStderrThatGoesAwayEndsNothingHalfWay) {
    // stderr on a pipe closed after the first progress line: the run writes the rest into the
    // closed pipe and still ends with its whole output, the same bytes as a quiet run, and no
    // temporaries (before SIGPIPE was ignored, it died at its next line, leaving them).
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, 1025, 1025, test::syntheticHeights(1025, 1025, 3000.0f));
    fs::create_directories(out);
    Child child({programPath("preprocessDem"), input, "-o", out + "/DEM.dat"});
    std::string line;
    ASSERT_TRUE(child.line(line));
    child.closeErr();
    EXPECT_EQ(child.wait(), 0);
    EXPECT_FALSE(hasTemporary(out)) << names(snapshot(out));
    std::string err;
    ASSERT_EQ(runToEnd({programPath("preprocessDem"), input, "-o", out + "/quiet.dat", "-q"}, &err), 0)
        << err;
    EXPECT_TRUE(fs::exists(out + "/DEM.dat") && test::readFile(out + "/DEM.dat") == test::readFile(out + "/quiet.dat"));
}

TEST_F(Failure, OutputsThatCannotBeWrittenFailBeforeAnyWork) {
    // An encode of many tiles (--max-level 9): the refusals come before any of them, so no
    // progress line comes before the error (stderr is not a terminal: a line per step).
    const std::string input = test::samplePath("dem.tif");
    fs::create_directories(out);
    writeText(out + "/file", "a file");
    const auto before = snapshot(out);
    struct Case {
        std::vector<std::string> args;
        std::string mention;
    };
    const std::vector<Case> cases = {
        {{programPath("preprocessDem"), input, "-o", out, "--max-level", "9"}, "is a directory"},
        {{programPath("preprocessDem"), input, "-o", out + "/file/DEM.dat", "--max-level", "9"}, "is not a directory"},
        {{programPath("preprocessDem"), input, "-o", out + "/DEM.dat", "--report", out, "--max-level", "9"},
         "is a directory"},
        {{programPath("preprocessOrtho"), input, "-o", out + "/file"}, "is not a directory"},
        {{programPath("preprocessSphericalDem"), input, "-o", out + "/file/x"}, "is not a directory"},
        {{programPath("preprocessSphericalOrtho"), input, "-o", out + "/file"}, "is not a directory"},
    };
    for (const Case& c : cases) {
        std::string err;
        EXPECT_EQ(runToEnd(c.args, &err), 1) << err;
        EXPECT_EQ(err.find('%'), std::string::npos) << "work began: " << err;
        EXPECT_NE(err.find(c.mention), std::string::npos) << err;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
        EXPECT_TRUE(snapshot(out) == before) << names(snapshot(out));
    }
}

TEST_F(Failure, PreprocessDemMakesTheMissingParentsOfItsOutput) {
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, 65, 65, test::syntheticHeights(65, 65, 1000.0f));
    std::string err;
    EXPECT_EQ(runToEnd({programPath("preprocessDem"), input, "-o", out + "/a/b/DEM.dat", "-q", "--report",
                        out + "/reports/r.json"},
                       &err),
              0)
        << err;
    EXPECT_TRUE(fs::is_regular_file(out + "/a/b/DEM.dat"));
    EXPECT_TRUE(fs::is_regular_file(out + "/reports/r.json"));
    // A failing run removes the directories it made.
    EXPECT_EQ(runToEnd({programPath("preprocessDem"), input, "-o", out + "/c/d/DEM.dat", "--band", "5"}, &err), 1);
    EXPECT_FALSE(fs::exists(out + "/c")) << err;
}

TEST_F(Failure, StaleTemporariesOfGoneRunsAreSweptAndNothingElse) {
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, 65, 65, test::syntheticHeights(65, 65, 1000.0f));
    // A pid that no longer exists: a child that has ended and been waited for.
    const pid_t gone = ::fork();
    if (gone == 0) {
        ::_exit(0);
    }
    ::waitpid(gone, nullptr, 0);
    const std::string dead = std::to_string(gone), alive = std::to_string(::getpid());
    fs::create_directories(out + "/.staging-" + dead + "-0badc0de/dxt");
    // Temporaries named for a writer that chooses the format by the extension (pyramid tile -o T.tif)
    // end with it.
    const std::vector<std::string> stale = {"DEM.dat.tmp-" + dead + "-0123abcd", ".staging-" + dead + "-0badc0de/dxt/RGB.dat",
                                            "other.dat.tmp-" + dead + "-ffffffff", "t.tif.tmp-" + dead + "-0123abcd.tif"};
    const std::vector<std::string> kept = {"DEM.dat.tmp-" + alive + "-0123abcd", "DEM.dat.tmp-12345678",
                                           "notes.tmp-" + dead, "DEM.dat.tmp-" + dead + "-XYZ", ".staging-x",
                                           "t.tif.tmp-" + alive + "-0123abcd.tif", "t.tif.tmp-" + dead + "-0123abc.tif"};
    for (const std::string& f : stale) {
        writeText(out + "/" + f, f);
    }
    for (const std::string& f : kept) {
        writeText(out + "/" + f, f);
    }
    std::string err;
    ASSERT_EQ(runToEnd({programPath("preprocessDem"), input, "-o", out + "/DEM.dat", "-q"}, &err), 0) << err;
    EXPECT_FALSE(fs::exists(out + "/.staging-" + dead + "-0badc0de"));
    for (const std::string& f : stale) {
        EXPECT_FALSE(fs::exists(out + "/" + f)) << f;
    }
    for (const std::string& f : kept) {
        EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
    }
    // The directory commands sweep their directory too.
    fs::create_directories(out + "/.staging-" + dead);
    ASSERT_EQ(runToEnd({programPath("preprocessSphericalDem"), test::samplePath("srtm.png"), "-o", out, "-q",
                        "--max-level", "3"},
                       &err),
              0)
        << err;
    EXPECT_FALSE(fs::exists(out + "/.staging-" + dead));
    EXPECT_TRUE(fs::exists(out + "/DEM1.dat"));
}

} // namespace
} // namespace pyramid
