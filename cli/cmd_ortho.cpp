// `pyramid ortho` / `preprocessOrtho`: imagery in, ortho pyramids out.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "cli/ortho_options.hpp"

namespace pyramid::cli {

CommandRunner setupOrthoCommand(CLI::App& app) {
    auto a = std::make_shared<OrthoArgs>();
    auto target = std::make_shared<PlanarTargetArgs>();
    addOrthoOptions(app, a, "Imagery: 1-4 channels of 8 or 16 bits (any format OpenImageIO reads)",
                    "Output directory: NAME.dat, dxt/NAME.dat, residuals/NAME.dat",
                    "The files' maxLevel (default: the smallest whose tile-size << maxLevel holds the longer side)",
                    true);
    app.add_flag("--stretch", a->options.levels.stretch,
                 "Stretch width and height independently onto the square root quad");
    addPlanarTargetOptions(app, *target);
    addOrthoRunOptions(app, a);
    return [a, target]() {
        OrthoEncodeOptions options = resolveOrthoOptions(*a);
        options.levels.target = target->resolve();
        const std::string sidecar =
            (std::filesystem::path(a->output) / georeferenceSidecarPath(options.name + ".dat")).string();
        const std::filesystem::path directory(a->output);
        const std::string file = options.name + ".dat";
        checkOutputsApart(a->input,
                          {{(directory / file).string(), "an output"},
                           {(directory / "dxt" / file).string(), "an output"},
                           {(directory / "residuals" / file).string(), "an output"},
                           {sidecar, "where the georeference sidecar goes"}},
                          a->report);
        const bool talk = speaks(a->quiet);
        std::unique_ptr<OutputPreflight> preflight;
        std::unique_ptr<Progress> progress;
        options.progress = [&](int64_t, int64_t total) {
            if (!progress) {
                progress = std::make_unique<Progress>("preprocessOrtho", total, !talk);
            }
            progress->advance(1);
        };
        OrthoReport report;
        SplitBuild build;
        build.program = "preprocessOrtho";
        build.directory = a->output;
        build.name = options.name;
        build.format = kOrthoPartFormat;
        build.prepare = [&] { preflight = std::make_unique<OutputPreflight>(a->output, true, a->report); };
        build.encode = [&](const PartContext* part) {
            OrthoEncodeOptions run = options;
            OrthoShare share;
            if (part) {
                share = OrthoShare{part->index, part->count, part->out};
                run.share = &share;
            }
            report = encodeOrtho(a->input.resolve(), a->output, run);
        };
        build.merge = [&](const std::vector<std::string>& parts) {
            const OrthoMergeReport merged = mergeOrthoParts(parts, build.directory, mergeProgress("preprocessOrtho", talk));
            takeMerged(report, merged.pyramids.at(0));
        };
        const BuildRole role = runSplitBuild(a->part, a->quiet, build);
        if (progress) {
            progress->finish();
        }
        if (role == BuildRole::OtherRank) {
            return kExitOk;
        }
        if (talk && role != BuildRole::Part) {
            printOrthoSummary(report);
            printGeoreferenceSummary(report.georeference, sidecar);
        }
        if (!a->report.empty()) {
            writeJson(toJson(report), a->report);
        }
        preflight->keep();
        return kExitOk;
    };
}

} // namespace pyramid::cli
