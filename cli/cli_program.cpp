// A program's run (cli_common.hpp, runProgram): the heap's policy, the stop on a signal, the
// command line kept, its mistakes in the project's words, a failure's line, exit code and
// report, --version, and the lines a run prints besides its progress.
#include "cli/cli_common.hpp"

#include <malloc.h>
#include <sys/mman.h>

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <map>
#include <optional>
#include <thread>

#include <CLI/CLI.hpp>

#include "cli/progress_line.hpp"
#include "formats/error.hpp"
#include "formats/temporaries.hpp"
#include "formats/vector_clones.hpp"
#include "libpyramid/api/build_info.hpp"
#include "libpyramid/distribute/team.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid::cli {

namespace {

// The preprocessors allocate and free tile-sized and band-sized buffers (hundreds of KB to a
// few MB) over and over, from every thread. glibc serves blocks above its mmap threshold with
// fresh mappings, which the kernel zero-fills page by page and which are unmapped again on
// free: on the benchmarks, 10 to 15 % of the time went to page faults. Keeping such blocks in
// the heap (up to 64 MB each) lets freed buffers be reused; the peak footprint is unchanged,
// as a freed block is reused before the heap grows.
//
// What is left is the heap's first touch of its peak, one page fault per 4 KB (about 7 us each
// on a virtual machine): 6,300 faults on a 2700 x 1350 image. So every thread allocates from
// the one heap (M_ARENA_MAX 1: a thread of its own would take a heap of its own, out of reach of
// the next step), and its first 180 MB are asked for as transparent huge pages: the heap is
// grown once by three blocks below the mmap threshold, their range given MADV_HUGEPAGE, and
// the blocks freed again (under the trim threshold, they stay in the heap). A first touch then
// costs one fault per 2 MB: about 400 faults on that image, 0.77 of the wall time, a few MB more
// peak RSS (memory is resident by 2 MB). Only address space is reserved, never memory; where
// the kernel gives no huge page the memory is what it was. The library itself sets no policy:
// this is the programs' choice.
//
// Under a sanitizer, whose allocator replaces glibc's, none of this applies: the blocks would
// only cost shadow memory.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define PYRAMID_GLIBC_HEAP 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define PYRAMID_GLIBC_HEAP 0
#endif
#endif
#if !defined(PYRAMID_GLIBC_HEAP) && defined(__GLIBC__)
#define PYRAMID_GLIBC_HEAP 1
#endif
void keepBuffersInTheHeap() {
#if PYRAMID_GLIBC_HEAP
    mallopt(M_MMAP_THRESHOLD, 64 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    mallopt(M_ARENA_MAX, 1);
    constexpr size_t kBlock = size_t{60} << 20, kHugePage = size_t{1} << 21;
    void* blocks[3] = {};
    uintptr_t lo = UINTPTR_MAX, hi = 0;
    for (void*& b : blocks) {
        b = std::malloc(kBlock); // not touched: no memory is used
        if (b) {
            lo = std::min(lo, reinterpret_cast<uintptr_t>(b));
            hi = std::max(hi, reinterpret_cast<uintptr_t>(b) + kBlock);
        }
    }
    lo = (lo + kHugePage - 1) & ~(kHugePage - 1);
    hi &= ~(kHugePage - 1);
    if (lo < hi) {
        (void)madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE); // a hint: ignored where THP is off
    }
    for (int k = 2; k >= 0; --k) {
        std::free(blocks[k]);
    }
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
    // A reader of stdout or stderr that goes away (`2>&1 | head`) must not kill the run
    // half-way, leaving its temporaries: its writes fail (EPIPE) and the run goes on.
    std::signal(SIGPIPE, SIG_IGN);
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
    std::optional<TeamScope> team;
    try {
        team.emplace(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << app.get_name() << ": " << e.what() << "\n";
        return kExitFailure;
    }
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

} // namespace pyramid::cli
