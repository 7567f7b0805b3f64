#include "cli/cli_common.hpp"

#include <malloc.h>

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <thread>

#include <CLI/CLI.hpp>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/temporaries.hpp"
#include "formats/vector_clones.hpp"
#include "libpyramid/api/build_info.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/distribute/team.hpp"
#include "libpyramid/support/parallel.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid::cli {

namespace {

// The preprocessors allocate and free tile-sized and band-sized buffers (hundreds of KB to a
// few MB) over and over, from every thread. glibc serves blocks above its mmap threshold with
// fresh mappings, which the kernel zero-fills page by page and which are unmapped again on
// free: on the benchmarks, 10 to 15 % of the time went to page faults. Keeping such blocks in
// the heap (up to 64 MB each) lets freed buffers be reused; the peak footprint is unchanged,
// as a freed block is reused before the heap grows. The library itself sets no policy: this
// is the programs' choice.
void keepBuffersInTheHeap() {
#ifdef __GLIBC__
    mallopt(M_MMAP_THRESHOLD, 64 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

const char* signalName(int signal) {
    switch (signal) {
    case SIGINT:
        return "SIGINT";
    case SIGTERM:
        return "SIGTERM";
    default:
        return "SIGHUP";
    }
}

// Whether a progress bar's line is on screen without its line end (Progress, ProgressMode::Bar):
// a message then starts on a line of its own.
std::atomic<bool> barLineOpen{false};

// The signals that stop a run go to one thread, whatever the others are doing: it removes the
// temporaries (a commit in progress first ends or rolls back, under the registry's lock, so
// the outputs are the old ones or the new ones, never a mix) and ends the process at once,
// workers and all. Called before any other thread exists: every thread started later (OpenMP
// workers, the ordered writer, GL drivers) inherits the blocked mask.
void stopOnSignals(const std::string& program) {
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);
    std::signal(SIGXFSZ, SIG_IGN);
    std::thread([signals, program] {
        int signal = 0;
        while (sigwait(&signals, &signal) != 0) {
        }
        removeTemporariesForExit();
        std::fprintf(stderr, "%s%s: stopped by %s (temporaries removed)\n", barLineOpen ? "\n" : "",
                     program.c_str(), signalName(signal));
        std::fflush(stderr);
        _exit(128 + signal);
    }).detach();
}

} // namespace

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), lowerAscii);
    return ext;
}

std::string flagName(const std::string& option) {
    // Options whose flag is not their name spelled out.
    static const std::map<std::string, std::string> shortened = {{"cacheMegabytes", "--cache-mb"}};
    if (const auto it = shortened.find(option); it != shortened.end()) {
        return it->second;
    }
    std::string flag = "--";
    for (const char c : option) {
        if (c >= 'A' && c <= 'Z') {
            flag += '-';
            flag += static_cast<char>(c - 'A' + 'a');
        } else {
            flag += c;
        }
    }
    return flag;
}

namespace {

std::vector<std::string>& arguments() {
    static std::vector<std::string> list;
    return list;
}

} // namespace

const std::vector<std::string>& commandArguments() { return arguments(); }

std::string versionText(const std::string& program) {
    std::string text = program + " " + PYRAMID_VERSION_TEXT + " (libpyramid)\n";
    for (const ComponentVersion& c : libraryVersions()) {
        text += "  " + c.name + " " + c.version + "\n";
    }
    const auto yesNo = [](bool on) { return on ? std::string("yes") : std::string("no"); };
#ifdef PYRAMID_CLI_WITH_GL
    const bool gl = true;
#else
    const bool gl = false;
#endif
    text += std::string("  build: ") + PYRAMID_CLI_BUILD_TYPE + ", OpenGL producers " + yesNo(gl) + ", Open MPI " +
            yesNo(teamsSupported()) + ", AVX2 clones " + yesNo(PYRAMID_VECTOR_CLONES_ON != 0);
    return text;
}

// Each command's --report target, for the report of a run that fails (runProgram).
std::map<const CLI::App*, const std::string*>& reportTargets() {
    static std::map<const CLI::App*, const std::string*> targets;
    return targets;
}

void addReportOption(CLI::App& app, std::string& report, const std::string& what) {
    reportTargets()[&app] = &report;
    CLI::Option* file = app.add_option("--report", report, "Write " + what + " as JSON to this file ('-' for stdout)");
    app.add_flag_callback("--json", [&report] { report = "-"; }, "The same as --report -")->excludes(file);
}

std::string& messageProgram() {
    static std::string name = "libpyramid";
    return name;
}

void addThreadsOption(CLI::App& app, int& threads) {
    app.add_option("--threads", threads,
                   "Worker threads, 1 to " + std::to_string(kMaxThreads) +
                       ", or 0 for all cores (the default); results do not depend on it");
}

void addCacheOption(CLI::App& app, int& cacheMegabytes) {
    app.add_option("--cache-mb", cacheMegabytes, "Input cache budget in MB, at least 1")->capture_default_str();
}

void addVersionFlag(CLI::App& app) {
    const std::string program = app.get_name();
    app.set_version_flag("--version", [program] { return versionText(program); },
                         "Print the version, the libraries' versions and the build options, then exit");
}

namespace {

// What a command-line mistake prints: with no arguments at all (or only a command's name), the
// help of the program (or command), for a newcomer; otherwise one line in the project's words
// (CLI11's own are kept where they already read well), pointing to --help.
std::string usageError(CLI::App& app, int argc, char** argv, const CLI::ParseError& e) {
    const std::string program = app.get_name();
    CLI::App* command = nullptr;
    if (argc >= 2 && argv[1][0] != '-' && !app.get_subcommands({}).empty()) {
        try {
            command = app.get_subcommand(argv[1]);
        } catch (const CLI::OptionNotFound&) {
            std::string names;
            for (const CLI::App* c : app.get_subcommands({})) {
                names += (names.empty() ? "" : ", ") + c->get_name();
            }
            return program + ": '" + argv[1] + "' is not a command (" + names + ")\n";
        }
    }
    if (argc == 1 || (argc == 2 && command != nullptr)) {
        return command != nullptr ? command->help(program) : app.help(); // "Usage: pyramid info ..."
    }
    const std::string hint = " (see " + program + (command != nullptr ? " " + command->get_name() : "") + " --help)\n";
    std::string what = e.what();
    const auto after = [&what](const std::string& prefix) {
        return what.rfind(prefix, 0) == 0 ? std::optional<std::string>(what.substr(prefix.size())) : std::nullopt;
    };
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
        // In the command line's order (CLI11's message lists them last first).
        std::string extras;
        int count = 0;
        for (const std::string& extra : (command != nullptr ? command : &app)->remaining()) {
            extras += (count++ == 0 ? "" : " ") + extra;
        }
        return program + ": unexpected argument" + (count > 1 ? "s: " : ": ") + extras + hint;
    }
    if (const auto conversion = after("Could not convert: ")) { // "NAME = VALUE"
        const auto equals = conversion->find(" = ");
        if (equals != std::string::npos) {
            const std::string name = conversion->substr(0, equals);
            const CLI::Option* option = (command != nullptr ? command : &app)->get_option_no_throw(name);
            const std::string type = option != nullptr ? option->get_type_name() : "";
            const std::string kind = type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0 ? "a whole number"
                                     : type.rfind("FLOAT", 0) == 0                            ? "a number"
                                                                                              : "a valid value";
            return program + ": " + name + ": '" + conversion->substr(equals + 3) + "' is not " + kind + hint;
        }
    }
    if (const auto range = what.find(": Value "); range != std::string::npos && what.find(" not in range ") != std::string::npos) {
        // "NAME: Value X not in range A to B"
        std::string rest = what.substr(range + 8);
        rest.replace(rest.find(" not in range "), 14, " is not ");
        return program + ": " + what.substr(0, range) + ": " + rest + hint;
    }
    if (const auto member = what.find(" not in {"); member != std::string::npos && what.back() == '}') {
        // "NAME: VALUE not in {A,B,C}"
        const auto colon = what.find(": ");
        std::string choices = what.substr(member + 9, what.size() - member - 10);
        const auto last = choices.rfind(',');
        if (last != std::string::npos) {
            choices.replace(last, 1, " or ");
        }
        for (size_t comma = choices.find(','); comma != std::string::npos; comma = choices.find(',', comma + 2)) {
            choices.replace(comma, 1, ", ");
        }
        if (colon != std::string::npos && colon < member) {
            return program + ": " + what.substr(0, colon) + ": '" + what.substr(colon + 2, member - colon - 2) +
                   "' is not " + choices + hint;
        }
    }
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr && endsWithNoCase(what, " missing")) {
        return program + ": " + what.substr(0, what.find(": ")) + ": needs a value" + hint; // "NAME: 1 required TYPE missing"
    }
    return program + ": " + what + hint;
}

} // namespace

int runProgram(CLI::App& app, int argc, char** argv, const NamedRunner* runners, int count) {
    keepBuffersInTheHeap();
    stopOnSignals(app.get_name());
    // After the signals are blocked: MPI's own threads inherit the mask.
    TeamScope team(argc, argv);
    arguments().assign(argv, argv + argc);
    messageProgram() = app.get_name();
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << usageError(app, argc, argv, e);
        return kExitUsage;
    }
    const CLI::App* command = nullptr;
    std::string error;
    try {
        for (int i = 0; i < count; ++i) {
            if (runners[i].app->parsed()) {
                command = runners[i].app;
                return runners[i].run();
            }
        }
        std::cerr << app.get_name() << ": no command given (see --help)\n";
        return kExitUsage;
    } catch (const TeamFailed&) {
        return kExitFailure; // another rank of an MPI run failed: rank 0 says why, once
    } catch (const OptionError& e) {
        error = flagName(e.option()) + ": " + e.problem();
    } catch (const std::exception& e) { // Error and the rest
        error = e.what();
    }
    std::cerr << app.get_name() << ": " << error << "\n";
    // A script reading the report sees the failure too: {"ok": false, ...} where the report goes.
    const auto target = reportTargets().find(command);
    if (target != reportTargets().end() && !target->second->empty() && worldTeam().rank() == 0) {
        try {
            OutputParents parents; // a report directory not made yet, as a run that succeeds makes it
            if (*target->second != "-") {
                prepareOutputFile(*target->second, parents);
            }
            writeJson({{"ok", false}, {"exit_code", kExitFailure}, {"error", error}}, *target->second);
            parents.keep();
        } catch (const std::exception&) {
            // the report's own path failed: the line above has said why the run did
        }
    }
    return kExitFailure;
}

ProgressMode& progressMode() {
    static ProgressMode mode = ProgressMode::Auto;
    return mode;
}

void addProgressOption(CLI::App& app) {
    app.add_option_function<std::string>(
           "--progress",
           [](const std::string& text) {
               static const std::map<std::string, ProgressMode> modes = {{"auto", ProgressMode::Auto},
                                                                        {"bar", ProgressMode::Bar},
                                                                        {"lines", ProgressMode::Lines},
                                                                        {"json", ProgressMode::Json},
                                                                        {"none", ProgressMode::None}};
               const auto it = modes.find(text);
               if (it == modes.end()) {
                   throw CLI::ValidationError("--progress", "'" + text + "' is not auto, bar, lines, json or none");
               }
               progressMode() = it->second;
           },
           "Progress on stderr: auto (bar on a terminal, else lines), bar, lines (every 5 %), json (JSON "
           "lines), none")
        ->type_name("MODE");
}

Progress::Progress(std::string label, int64_t total, bool quiet, OffTerminal offTerminal)
    : label_(std::move(label)),
      total_(total > 0 ? total : 1),
      quiet_(quiet || progressMode() == ProgressMode::None ||
             (progressMode() == ProgressMode::Auto && offTerminal == OffTerminal::Silent && isatty(2) == 0)),
      mode_(progressMode() == ProgressMode::Auto ? (isatty(2) != 0 ? ProgressMode::Bar : ProgressMode::Lines)
                                                 : progressMode()),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { finish(); }

void Progress::advance(int64_t n) {
    const int64_t done = done_.fetch_add(n) + n;
    if (!quiet_) {
        draw(done, false);
    }
}

void Progress::finish() {
    if (quiet_ || finished_) {
        return;
    }
    draw(done_.load(), true);
    finished_ = true;
}

namespace {

// "0:42", "12:05", "3:02:17".
std::string clockText(double seconds) {
    const auto s = static_cast<long long>(std::llround(std::max(0.0, seconds)));
    char text[32];
    if (s >= 3600) {
        std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
    } else {
        std::snprintf(text, sizeof text, "%lld:%02lld", s / 60, s % 60);
    }
    return text;
}

} // namespace

void Progress::draw(int64_t counted, bool final) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) {
        return;
    }
    // The count as it stands now, read under the lock: threads that counted in one order may
    // draw in another, and the lines must still rise.
    const int64_t done = std::max(counted, done_.load());
    const auto now = std::chrono::steady_clock::now();
    const double percent = 100.0 * static_cast<double>(done) / static_cast<double>(total_);
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0.0 ? static_cast<double>(done) / elapsed : 0.0;
    // A rate only once it means something (not from the first item's microseconds).
    const bool timed = rate > 0.0 && done > 0 && elapsed >= 0.25;
    const bool complete = final || done >= total_;
    const double eta = timed ? static_cast<double>(total_ - done) / rate : 0.0;
    const auto line = [&] {
        char text[64];
        std::snprintf(text, sizeof text, "%3d%% (%lld/%lld)", static_cast<int>(percent), static_cast<long long>(done),
                      static_cast<long long>(total_));
        std::string s = label_ + ": " + text;
        if (timed) {
            std::snprintf(text, sizeof text, " %.0f/s", rate);
            s += text;
            s += complete ? ", " + clockText(elapsed) : ", " + clockText(eta) + " left";
        }
        return s;
    };
    switch (mode_) {
    case ProgressMode::Bar: {
        if (!final && now - last_ < std::chrono::milliseconds(200)) {
            return;
        }
        last_ = now;
        // Padded so that a shorter line covers a longer one.
        std::fprintf(stderr, "\r%-78s%s", line().c_str(), final ? "\n" : "");
        barLineOpen = !final;
        break;
    }
    case ProgressMode::Lines: {
        const int step = static_cast<int>(percent) / 5;
        if (step == lastStep_) {
            return; // this line is already on screen (and the final one too)
        }
        lastStep_ = step;
        std::fprintf(stderr, "%s\n", line().c_str());
        break;
    }
    case ProgressMode::Json: {
        const int step = static_cast<int>(percent);
        if ((!final && step == lastStep_ && now - last_ < std::chrono::seconds(1)) || done == lastDone_) {
            return; // (a final line already out as the last one)
        }
        lastDone_ = done;
        lastStep_ = step;
        last_ = now;
        const nlohmann::ordered_json j = {{"progress", label_},
                                  {"done", done},
                                  {"total", total_},
                                  {"percent", std::round(percent * 10.0) / 10.0},
                                  {"rate", timed ? nlohmann::ordered_json(std::round(rate * 10.0) / 10.0)
                                                 : nlohmann::ordered_json()},
                                  {"eta_seconds", timed ? nlohmann::ordered_json(std::round(eta * 10.0) / 10.0)
                                                        : nlohmann::ordered_json()}};
        std::fprintf(stderr, "%s\n", j.dump().c_str());
        break;
    }
    case ProgressMode::Auto:
    case ProgressMode::None:
        return;
    }
    std::fflush(stderr);
}

OutputPreflight::OutputPreflight(const std::string& output, bool isDirectory, const std::string& report) {
    if (isDirectory) {
        prepareOutputDirectory(output);
    } else {
        prepareOutputFile(output, output_);
    }
    if (!report.empty() && report != "-") {
        prepareOutputFile(report, report_);
    }
}

void OutputPreflight::keep() {
    output_.keep();
    report_.keep();
}

void writeJson(const nlohmann::json& json, const std::string& path) {
    nlohmann::json report = json;
    if (report.is_object() && !report.contains("ok")) {
        report["ok"] = true; // every report says whether its run succeeded
    }
    const std::string text = report.dump(2) + "\n";
    if (path == "-") {
        std::fwrite(text.data(), 1, text.size(), stdout);
        std::fflush(stdout);
        return;
    }
    AtomicFile out(path);
    out.writeAt(0, text.data(), text.size());
    out.commit();
}

void checkOutputsApart(const InputArgs& input, const std::vector<OutputFile>& writes, std::string& report) {
    namespace fs = std::filesystem;
    // The same file: the same inode when both exist, else the same path once resolved.
    const auto same = [](const std::string& a, const std::string& b) {
        std::error_code ec, ed;
        if (fs::exists(a, ec) && fs::exists(b, ed)) {
            return fs::equivalent(a, b, ec) && !ec;
        }
        return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ed) && !ec && !ed;
    };
    std::vector<std::string> inputs = input.inputs;
    if (!input.list.empty()) {
        inputs.push_back(input.list);
    }
    std::error_code ec;
    const auto reportNames = [&](const std::string& what) {
        // Not even the failure report goes there.
        const std::string named = report;
        report.clear();
        fail("--report", "'" + named + "' is " + what + "; name the report otherwise");
    };
    for (const std::string& in : inputs) {
        if (!fs::is_regular_file(in, ec)) {
            continue; // a directory or a glob: its files are not outputs' names
        }
        if (!report.empty() && report != "-" && same(report, in)) {
            reportNames("an input");
        }
        for (const OutputFile& out : writes) {
            if (same(out.path, in)) {
                fail("-o", "'" + out.path + "' is an input; name the output otherwise");
            }
        }
    }
    for (const OutputFile& out : writes) {
        if (!report.empty() && report != "-" && same(report, out.path)) {
            reportNames(out.what);
        }
    }
}

void printGeoreferenceSummary(const std::optional<PyramidGeoreference>& georeference, const std::string& sidecar) {
    if (georeference) {
        std::fprintf(stderr, "%s: placement in %s\n", sidecar.c_str(), georeference->crs.crsText().c_str());
    }
}

std::vector<std::string> InputArgs::resolve() const {
    std::vector<std::string> paths = expandInputs(inputs, list).paths;
    if (priority == "last") {
        std::reverse(paths.begin(), paths.end());
    }
    return paths;
}

PlanarTarget PlanarTargetArgs::resolve() const {
    PlanarTarget target;
    target.crs = crs;
    if (!extent.empty()) {
        target.extent = PlanarTarget::parseExtent(extent);
    }
    return target;
}

void addPlanarTargetOptions(CLI::App& app, PlanarTargetArgs& args) {
    app.add_option("--crs", args.crs,
                   "EPSG:N: resample the inputs into this CRS (default: the first input's CRS, and files in it on "
                   "their own grid are read as they are)");
    app.add_option("--extent", args.extent,
                   "MINX,MINY,MAXX,MAXY in the CRS's units: the ground the pyramid covers (default: the union of "
                   "the inputs'); outside the inputs is nodata");
}

void addInputOptions(CLI::App& app, InputArgs& args, const char* inputHelp) {
    app.add_option("INPUT", args.inputs,
                   std::string(inputHelp) +
                       ". Several inputs make a mosaic, each file placed by its own georeferencing: files, "
                       "directories (their .tif and .hgt files), globs, GDAL VRT mosaics (.vrt)");
    app.add_option("--input-list", args.list,
                   "A text file naming more inputs, one per line (# comments; paths relative to the list)");
    app.add_option("--priority", args.priority,
                   "Where mosaic inputs of one resolution overlap: 'first' (the first listed wins) or 'last'")
        ->check(CLI::IsMember({"first", "last"}))
        ->capture_default_str();
    app.callback([&app, &args] {
        (void)app;
        if (args.inputs.empty() && args.list.empty()) {
            throw CLI::RequiredError("INPUT (or --input-list)");
        }
    });
}

namespace {

// The build's identity in its part files: the command line without what does not change the
// files (the part, threads, cache, report, quiet, progress).
nlohmann::json buildIdentity(const char* program) {
    std::vector<std::string> kept;
    const std::vector<std::string>& all = commandArguments();
    for (size_t i = 1; i < all.size(); ++i) {
        const std::string& a = all[i];
        if (a == "-q" || a == "--quiet" || a == "--json") {
            continue;
        }
        bool dropped = false;
        for (const std::string flag : {"--part", "--threads", "--cache-mb", "--report", "--progress"}) {
            if (a == flag) {
                ++i; // and its value
                dropped = true;
                break;
            }
            if (a.rfind(flag + "=", 0) == 0) {
                dropped = true;
                break;
            }
        }
        if (!dropped) {
            kept.push_back(a);
        }
    }
    return {{"program", program}, {"arguments", kept}};
}

} // namespace

CLI::Option* addPartOption(CLI::App& app, std::string& part) {
    return app.add_option("--part", part,
                   "Encode only part I of N (0 <= I < N) into OUTPUT.part-I-of-N, for batch schedulers; "
                   "'pyramid merge' assembles the parts into the files one run writes")
        ->type_name("I/N");
}

uint64_t MaxFileBytesArgs::resolve() const {
    if (!option || option->count() == 0) {
        return 0;
    }
    return size.empty() ? kDefaultMaxFileBytes : parseByteSize(size, "--max-file-bytes");
}

void addMaxFileBytesOption(CLI::App& app, MaxFileBytesArgs& args, const char* what) {
    args.option = app.add_option("--max-file-bytes", args.size,
                                 std::string("Write ") + what +
                                     " of files of at most SIZE bytes each (K, M, G, T: powers of 1024) and its index "
                                     "FILE.regions.json; without SIZE, just under 4 GiB")
                       ->expected(0, 1);
}

std::optional<RegionRequest> RegionArgs::resolve() const {
    if (region.empty()) {
        return std::nullopt;
    }
    RegionRoot root;
    int* fields[3] = {&root.level, &root.tx, &root.ty};
    std::string_view rest(region);
    for (int k = 0; k < 3; ++k) {
        const size_t comma = k < 2 ? rest.find(',') : rest.size();
        const auto value = comma == std::string_view::npos ? std::nullopt : readWholeNumber<int>(rest.substr(0, comma));
        if (!value) {
            fail("--region", "must be LEVEL,TX,TY (a tile: three whole numbers), not '" + region + "'");
        }
        *fields[k] = *value;
        rest.remove_prefix(std::min(rest.size(), comma + 1));
    }
    return RegionRequest{root, parent};
}

void addRegionOptions(CLI::App& app, RegionArgs& args, CLI::Option* part, const char* files, const char* parentFile) {
    app.add_option("--region", args.region,
                   std::string("Write only the sub-pyramid rooted at tile (LEVEL, TX, TY), as ") + files +
                       " whose tiles are the whole pyramid's")
        ->type_name("LEVEL,TX,TY")
        ->excludes(part);
    app.add_option("--parent", args.parent,
                   std::string("With --region: ") + parentFile +
                       " of the same build, whose reconstruction the region's residuals are against, instead of "
                       "encoding the levels above it from the input")
        ->type_name("FILE")
        ->needs("--region");
}

std::function<void(int64_t, int64_t)> progressCallback(const std::string& label, bool quiet,
                                                      Progress::OffTerminal offTerminal) {
    struct State {
        std::unique_ptr<Progress> progress;
        int64_t shown = 0;
    };
    auto state = std::make_shared<State>();
    return [state, label, quiet, offTerminal](int64_t done, int64_t total) {
        if (!state->progress) {
            state->progress = std::make_unique<Progress>(label, total, quiet, offTerminal);
        }
        state->progress->advance(done - state->shown);
        state->shown = done;
        if (done >= total) {
            state->progress->finish();
        }
    };
}

std::function<void(int64_t, int64_t)> mergeProgress(const std::string& program, bool show) {
    return progressCallback(program + " (merging)", !show);
}

void addResidualCodingOptions(CLI::App& app, ResidualCodingArgs& args) {
    app.add_option("--compression", args.compression,
                   "Residual tiles: deflate (as the original tools write them), smallest (per tile the smallest "
                   "TIFF the original runtime reads; slower), or context (the smallest files; libpyramid's readers "
                   "only, not the original runtime)")
        ->capture_default_str()
        ->check(CLI::IsMember({"deflate", "smallest", "context"}));
    app.add_option("--deflate-level", args.deflateLevel,
                   "Deflate level of TIFF tiles: 1 (fastest) to 12 (smallest); default 2, or 12 with "
                   "--compression smallest")
        ->check(CLI::Range(1, 12));
}

ResidualTileCoding ResidualCodingArgs::resolve(bool quiet) const {
    const std::optional<ResidualCodec> codec = parseResidualCodec(compression);
    if (!codec) {
        fail("--compression", "'" + compression + "' is not deflate, smallest or context");
    }
    if (*codec == ResidualCodec::Context && deflateLevel != 0) {
        fail("--deflate-level", "applies to TIFF tiles, not to --compression context");
    }
    if (*codec == ResidualCodec::Context) {
        warn(quiet, "--compression context: the original Proland runtime cannot read these tiles (libpyramid's "
                    "readers can)");
    }
    return ResidualTileCoding{*codec, deflateLevel};
}

bool speaks(bool quiet) { return !quiet && worldTeam().rank() == 0; }

void sayFailure(const std::string& what) {
    std::fflush(stdout);
    std::fprintf(stderr, "%s: %s\n", messageProgram().c_str(), what.c_str());
}

void warn(bool quiet, const std::string& what) {
    if (speaks(quiet)) {
        std::fprintf(stderr, "%s: warning: %s\n", messageProgram().c_str(), what.c_str());
    }
}

BuildRole runSplitBuild(const std::string& part, bool quiet, const SplitBuild& build) {
    Team& team = worldTeam();
    if (!part.empty()) {
        const size_t slash = part.find('/');
        const std::string_view text(part);
        const auto index = slash == std::string::npos ? std::nullopt : readWholeNumber<int64_t>(text.substr(0, slash));
        const auto count = slash == std::string::npos ? std::nullopt : readWholeNumber<int64_t>(text.substr(slash + 1));
        if (!index || !count) {
            fail("--part", "must be I/N (part I of N, from 0), not " + part);
        }
        if (*count < 1 || *count > 1000000 || *index < 0 || *index >= *count) {
            fail("--part", "must be I/N with 0 <= I < N, not " + part);
        }
        if (team.size() > 1) {
            fail("--part", "splits a build for batch jobs; under mpirun the ranks split it themselves");
        }
        build.prepare();
        const std::string base = (std::filesystem::path(build.directory) / build.name).string();
        const std::string path = runPart(static_cast<int>(*index), static_cast<int>(*count), base, build.format,
                                         buildIdentity(build.program),
                                         [&](const PartContext& share) { build.encode(&share); });
        if (!quiet) {
            std::fprintf(stderr, "%s: part %lld of %lld written to %s; 'pyramid merge' assembles the parts\n",
                         build.program, static_cast<long long>(*index), static_cast<long long>(*count), path.c_str());
        }
        return BuildRole::Part;
    }
    if (team.size() == 1) {
        build.prepare();
        build.encode(nullptr);
        return BuildRole::Whole;
    }
    runTeam(team, build.directory, build.name, build.format, buildIdentity(build.program), build.prepare,
            [&](const PartContext& share) { build.encode(&share); },
            [&](const std::vector<std::string>& parts) { build.merge(parts); });
    return team.rank() == 0 ? BuildRole::Root : BuildRole::OtherRank;
}

} // namespace pyramid::cli
