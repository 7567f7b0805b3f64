// `pyramid merge`: the part files of a split build (--part I/N) into the files one run writes.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"
#include "formats/part_file.hpp"
#include "libpyramid/api/encoders.hpp"

namespace pyramid::cli {

namespace {

// ", a region set of N files" for a set, "" for one file.
std::string setText(size_t files) {
    return files > 1 ? ", a region set of " + std::to_string(files) + " files" : std::string();
}

} // namespace

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
        ->required();
    app.add_option("-o,--output", args->directory,
                   "Directory to write the pyramids into (default: the parts' directory)");
    app.add_flag("--keep-parts", args->keep, "Keep the part files (default: removed once the pyramids are in place)");
    addReportOption(app, args->report, "the report");
    app.add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
    addProgressOption(app);
    return [args]() {
        std::string directory = args->directory;
        if (directory.empty()) {
            const std::filesystem::path first(args->parts.front());
            directory = first.has_parent_path() ? first.parent_path().string() : std::string(".");
        }
        prepareOutputDirectory(directory);
        const bool show = !args->quiet;
        nlohmann::json json;
        std::vector<std::string> lines;
        int parts = 0;
        double seconds = 0.0;
        if (partFileFormat(args->parts.front()) == kOrthoPartFormat) {
            const OrthoMergeReport report = mergeOrthoParts(args->parts, directory, mergeProgress("pyramid merge", show));
            for (const OrthoReport& p : report.pyramids) {
                for (size_t i = 0; i < p.outputs.size(); ++i) {
                    lines.push_back(p.outputs[i] + ": " + std::to_string(p.tiles) + " tiles (" +
                                    std::to_string(p.sharedTiles[i]) + " shared), " + std::to_string(p.bytes[i]) +
                                    " bytes" + setText(p.files[i].size()));
                }
            }
            json = toJson(report);
            parts = report.parts;
            seconds = report.seconds;
        } else {
            const ResidualMergeReport report =
                mergeResidualParts(args->parts, directory, mergeProgress("pyramid merge", show));
            for (size_t k = 0; k < report.pyramids.size(); ++k) {
                const ResidualPyramidReport& p = report.pyramids[k];
                lines.push_back(report.outputs[k] + ": " + std::to_string(p.tiles) + " tiles (" +
                                std::to_string(p.sharedTiles) + " shared), " + std::to_string(p.bytes) + " bytes" +
                                setText(p.files.size()));
            }
            json = toJson(report);
            parts = report.parts;
            seconds = report.seconds;
        }
        if (!args->keep) {
            for (const std::string& part : args->parts) {
                std::error_code ec;
                std::filesystem::remove(part, ec);
            }
        }
        if (show) {
            for (const std::string& line : lines) {
                std::fprintf(stderr, "%s\n", line.c_str());
            }
            std::fprintf(stderr, "merged %d parts in %.1f s%s\n", parts, seconds, args->keep ? "" : "; the parts are removed");
        }
        if (!args->report.empty()) {
            writeJson(json, args->report);
        }
        return kExitOk;
    };
}

} // namespace pyramid::cli
