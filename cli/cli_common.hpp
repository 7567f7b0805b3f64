// What every command shares: error reporting and exit codes, progress on stderr,
// JSON output (to stdout or atomically to a file).
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "formats/output_paths.hpp"
#include "libpyramid/api/encoders.hpp"

namespace CLI {
class App;
class Option;
}

namespace pyramid::cli {

// Exit codes: 0 success, 1 the data or a file is bad (or a check/verify found a problem),
// 2 the command line is wrong, 128 + the signal's number when SIGINT (130), SIGTERM (143) or
// SIGHUP (129) stopped the run (doc/failure.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// Parses argv into `app` and runs the runner of the (sub)command that was selected.
// Errors thrown as pyramid::Error (or any std::exception) become one line on stderr,
// "PROGRAM: MESSAGE", and exit code 1; command-line errors exit with 2.
struct NamedRunner {
    CLI::App* app;
    CommandRunner run;
};
// An OptionError (the library's words for an option) is printed with the option's flag:
// the library's option names are the flags in camel case ("tileSize" is --tile-size).
// Before anything else (before any thread starts, so that every thread inherits the mask),
// SIGINT, SIGTERM and SIGHUP are blocked and left to one thread that waits for them, removes
// the run's temporaries (formats/temporaries.hpp: after a commit in progress ends) and exits
// with 128 + the signal's number. SIGXFSZ is ignored: a write past the file size limit fails
// with EFBIG, reported as any full disk, instead of killing the process with its temporaries.
// Under mpirun (when built with MPI) the program joins the MPI world for its run
// (libpyramid/distribute/team.hpp).
int runProgram(CLI::App& app, int argc, char** argv, const NamedRunner* runners, int count);

// --version: the program's and libpyramid's version, the libraries it runs on
// (libpyramid/api/build_info.hpp) and the build's options, one per line.
void addVersionFlag(CLI::App& app);
std::string versionText(const std::string& program);

// The command line runProgram was given (after MPI took its own arguments).
const std::vector<std::string>& commandArguments();

// The flag of a library option name: "tileSize" -> "--tile-size" ("cacheMegabytes" ->
// "--cache-mb").
std::string flagName(const std::string& option);

// The extension of an output path, ASCII letters lowered: "a/Tile.PNG" -> ".png" (the format a
// command writes is chosen by it).
std::string lowerExtension(const std::string& path);

// The inputs of a preprocessor: INPUT... (files, directories, globs, GDAL VRTs),
// --input-list FILE and --priority first|last.
struct InputArgs {
    std::vector<std::string> inputs;
    std::string list;
    std::string priority = "first";
    // The files to read, in priority order (libpyramid/input/input_list.hpp; reversed by
    // --priority last). Throws Error naming a missing file, an empty directory, a bad VRT...
    std::vector<std::string> resolve() const;
};
// Declares INPUT... (at least one unless --input-list is given), --input-list and --priority.
void addInputOptions(CLI::App& app, InputArgs& args, const char* inputHelp);

// --crs and --extent of the planar commands (preprocessDem, preprocessOrtho, pyramid verify).
struct PlanarTargetArgs {
    std::string crs;
    std::string extent;
    PlanarTarget resolve() const; // throws OptionError("extent", ...) for a bad extent
};
void addPlanarTargetOptions(CLI::App& app, PlanarTargetArgs& args);

// How progress is shown (--progress): Auto is Bar on a terminal, Lines otherwise.
enum class ProgressMode { Auto, Bar, Lines, Json, None };
// The mode every Progress of this process takes (the --progress of addProgressOption).
ProgressMode& progressMode();
// Declares --progress auto|bar|lines|json|none on `app`.
void addProgressOption(CLI::App& app);

// Progress on stderr, in the mode progressMode() says, nothing when quiet. Thread-safe.
//  * Bar: one line redrawn in place, "LABEL:  42% (1234/2938) 310/s, 0:06 left".
//  * Lines: the same as a line at every 5 % (and at the end).
//  * Json: one JSON object a line, at every 1 % and at least every second, and at the end:
//    {"progress":"LABEL","done":1234,"total":2938,"percent":42.0,"rate":310.2,"eta_seconds":5.5}
//    (rate in items a second; rate and eta null for the first quarter of a second); the last has
//    done == total.
// Inspection commands (check, verify), whose stderr a script reads for the one failure line,
// pass OffTerminal::Silent: in the auto mode they show progress on a terminal only.
class Progress {
public:
    enum class OffTerminal { Lines, Silent };
    Progress(std::string label, int64_t total, bool quiet, OffTerminal offTerminal = OffTerminal::Lines);
    ~Progress();
    void advance(int64_t n = 1);
    void finish();

private:
    void draw(int64_t done, bool final);
    std::string label_;
    int64_t total_;
    bool quiet_;
    ProgressMode mode_;
    std::atomic<int64_t> done_{0};
    std::mutex mutex_;
    std::chrono::steady_clock::time_point start_, last_{};
    int lastStep_ = -1;
    int64_t lastDone_ = -1;
    bool finished_ = false;
};

// The outputs' checks before any work starts (formats/output_paths.hpp): the output, a file
// (`isDirectory` false: its missing parents are made) or a directory, and the report's path
// when one is named. Stale temporaries of earlier runs beside them are swept. Destroyed before
// keep(), the directories it made are removed again when empty.
class OutputPreflight {
public:
    OutputPreflight(const std::string& output, bool isDirectory, const std::string& report);
    void keep();

private:
    OutputParents output_, report_;
};

// JSON output, one spelling for every command: --report FILE|- writes the command's JSON,
// atomically to FILE, or to stdout with '-' in place of the text the command prints there;
// --json is the same as --report - (the inspection commands' spelling before there was one).
void addReportOption(CLI::App& app, std::string& report, const std::string& what);

// The name the running program's messages begin with (`pyramid` for its commands; set by
// runProgram).
std::string& messageProgram();

// --threads N: the worker count (0, the default, is all cores; the library refuses more than
// kMaxThreads). Results never depend on it.
void addThreadsOption(CLI::App& app, int& threads);

// --cache-mb N: the input cache budget in MB (the library refuses less than 1).
void addCacheOption(CLI::App& app, int& cacheMegabytes);

// --tile-size, as the preprocessors take it into `text`: a whole number of `unit` ("pixels",
// "intervals"; its range is the encoder's to check), or "auto" when `autoAllowed` (a planar
// command; cube faces are refused, naming `planarCommand`, which takes it), with `help`.
CLI::Option* addTileSizeOption(CLI::App& app, std::string& text, const std::string& help, const std::string& unit,
                               bool autoAllowed, const std::string& planarCommand);

// Writes a report, `json` (pretty, with a final newline), to `path` atomically; "-" means
// stdout. An object without "ok" gets "ok": true (a failed run's report is runProgram's).
void writeJson(const nlohmann::json& json, const std::string& path);

// Refuses a run that would write over what it reads or write two things to one file: an output
// it writes (`writes`: the pyramid files, their georeference sidecar) naming an input file, or
// the report naming an input or an output. A report so refused is dropped first, so that not
// even the failure report is written there. Throws Error ("-o: ...", "--report: ...").
struct OutputFile {
    std::string path;
    std::string what; // for messages: "the output", "where the georeference sidecar goes"
};
void checkOutputsApart(const InputArgs& input, const std::vector<OutputFile>& writes, std::string& report);
// One line on stderr for a georeferenced input: its CRS and the sidecar written.
void printGeoreferenceSummary(const std::optional<PyramidGeoreference>& georeference, const std::string& sidecar);

// How a build that can be split runs: whole, as part I of N of a batch (--part), or as one rank
// of an MPI run (every rank encodes its share, rank 0 merges).
enum class BuildRole { Whole, Part, Root, OtherRank };

struct SplitBuild {
    const char* program;
    std::string directory; // the outputs' directory
    std::string name;      // part files: partFileName(directory/name, I, N)
    std::string format;    // kResidualPartFormat, kOrthoPartFormat
    std::function<void()> prepare;                             // output checks, before any work
    std::function<void(const PartContext*)> encode;            // the build (null: whole)
    std::function<void(const std::vector<std::string>&)> merge; // rank 0: every part file, in order
};

// Declares --part I/N, bound to `part`.
CLI::Option* addPartOption(CLI::App& app, std::string& part);

// --max-file-bytes [SIZE], as every preprocessor takes it: without SIZE, files just under 4 GiB
// (the residual files' 32-bit offsets; ortho files have 64-bit offsets, but 4 GiB files suit
// FAT32 and byte-range tools).
inline constexpr uint64_t kDefaultMaxFileBytes = 0xFFFFFFFF;
struct MaxFileBytesArgs {
    std::string size; // "" when given without a size
    // Given without a size, the option has no value for a callback to see, only a count.
    const CLI::Option* option = nullptr;
    // 0 when not given; throws Error naming the option for a SIZE that is not one.
    uint64_t resolve() const;
};
// Declares --max-file-bytes on `app`; `what` says what becomes a set.
void addMaxFileBytesOption(CLI::App& app, MaxFileBytesArgs& args, const char* what);

// --region LEVEL,TX,TY and --parent FILE, as every preprocessor takes them.
struct RegionArgs {
    std::string region;
    std::string parent;
    // The request they make (none without --region); throws Error naming the option when the
    // tile is not three whole numbers (whether the pyramid has it is the encoder's check).
    std::optional<RegionRequest> resolve() const;
};
// Declares --region (excluding `part`) and --parent on `app`; `files` says what a region build
// writes, `parentFile` what --parent names.
void addRegionOptions(CLI::App& app, RegionArgs& args, CLI::Option* part, const char* files, const char* parentFile);

// Runs `build` in the role `part` (the --part text, "" without) and the launcher give it; prints
// the line of a part unless quiet. Returns the role.
BuildRole runSplitBuild(const std::string& part, bool quiet, const SplitBuild& build);
// How residual tiles are coded: --compression deflate|smallest|context and --deflate-level N
// (preprocessDem, preprocessSphericalDem, pyramid recode).
struct ResidualCodingArgs {
    std::string compression = "deflate";
    int deflateLevel = 0; // 0: not given
    // The coding asked for; throws Error naming the option for an impossible choice. Warns on
    // stderr, unless quiet, that the original runtime cannot read context-coded tiles.
    ResidualTileCoding resolve(bool quiet) const;
};
void addResidualCodingOptions(CLI::App& app, ResidualCodingArgs& args);

// A library's progress(done, total) shown as a Progress (made at the first call, finished when
// done reaches total); calls must come one at a time.
std::function<void(int64_t, int64_t)> progressCallback(const std::string& label, bool quiet,
                                                      Progress::OffTerminal offTerminal = Progress::OffTerminal::Lines);
// A merge's progress on stderr ("PROGRAM (merging): 42% ..."), when `show`.
std::function<void(int64_t, int64_t)> mergeProgress(const std::string& program, bool show);
// Whether this process prints: not when quiet, nor on the ranks other than 0 of an MPI run.
bool speaks(bool quiet);
// "PROGRAM: warning: WHAT" on stderr, when this process speaks.
void warn(bool quiet, const std::string& what);
// "PROGRAM: WHAT" on stderr, after what stdout holds: the one line of a run that found a
// problem and returns its failure itself (check, verify) instead of throwing.
void sayFailure(const std::string& what);

} // namespace pyramid::cli
