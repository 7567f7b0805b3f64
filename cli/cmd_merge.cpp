// `pyramid merge`: the part files of a split build (--part I/N) into the files one run writes.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"

namespace pyramid::cli {

CommandRunner setupMergeCommand(CLI::App& app) {
    struct Args {
        std::vector<std::string> parts;
        std::string directory;
        std::string report;
        bool keep = false;
        bool quiet = false;
    };
    auto args = std::make_shared<Args>();
    app.add_option("parts", args->parts, "Every part file of the build (OUTPUT.part-I-of-N), in any order")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("-o,--output", args->directory,
                   "Directory to write the pyramids into (default: the parts' directory)");
    app.add_flag("--keep-parts", args->keep, "Keep the part files (default: removed once the pyramids are in place)");
    app.add_option("--report", args->report, "Write a JSON report to this file ('-' for stdout)");
    app.add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
    return [args]() {
        std::string directory = args->directory;
        if (directory.empty()) {
            const std::filesystem::path first(args->parts.front());
            directory = first.has_parent_path() ? first.parent_path().string() : std::string(".");
        }
        prepareOutputDirectory(directory);
        std::unique_ptr<Progress> progress;
        const ResidualMergeReport report =
            mergeResidualParts(args->parts, directory, [&](int64_t, int64_t total) {
                if (!progress) {
                    progress = std::make_unique<Progress>("pyramid merge", total, args->quiet);
                }
                progress->advance(1);
            });
        if (progress) {
            progress->finish();
        }
        if (!args->keep) {
            for (const std::string& part : args->parts) {
                std::error_code ec;
                std::filesystem::remove(part, ec);
            }
        }
        if (!args->quiet) {
            for (size_t k = 0; k < report.pyramids.size(); ++k) {
                const ResidualPyramidReport& p = report.pyramids[k];
                std::fprintf(stderr, "%s: %lld tiles (%lld shared), %llu bytes%s\n", report.outputs[k].c_str(),
                             static_cast<long long>(p.tiles), static_cast<long long>(p.sharedTiles),
                             static_cast<unsigned long long>(p.bytes),
                             p.files.size() > 1 ? (", a region set of " + std::to_string(p.files.size()) + " files").c_str()
                                                : "");
            }
            std::fprintf(stderr, "merged %d parts in %.1f s%s\n", report.parts, report.seconds,
                         args->keep ? "" : "; the parts are removed");
        }
        if (!args->report.empty()) {
            writeJson(toJson(report), args->report);
        }
        return kExitOk;
    };
}

} // namespace pyramid::cli
