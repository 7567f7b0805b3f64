// `pyramid ortho` / `preprocessOrtho`: imagery in, ortho pyramids out.
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "cli/ortho_options.hpp"

namespace pyramid::cli {

CommandRunner setupOrthoCommand(CLI::App& app) {
    auto a = std::make_shared<OrthoArgs>();
    auto target = std::make_shared<PlanarTargetArgs>();
    addOrthoOptions(app, a, "Imagery: 1-4 channels of 8 or 16 bits (any format OpenImageIO reads)",
                    "Output directory: NAME.dat, dxt/NAME.dat, residuals/NAME.dat",
                    "The files' maxLevel (default: the smallest whose tile-size << maxLevel holds the longer side)");
    app.add_flag("--stretch", a->options.levels.stretch,
                 "Stretch width and height independently onto the square root quad");
    addPlanarTargetOptions(app, *target);
    addOrthoRunOptions(app, a);
    return [a, target]() {
        OrthoEncodeOptions options = resolveOrthoOptions(*a);
        options.levels.target = target->resolve();
        const std::string sidecar =
            (std::filesystem::path(a->output) / georeferenceSidecarPath(options.name + ".dat")).string();
        checkReportIsNotSidecar(a->report, sidecar);
        OutputPreflight preflight(a->output, true, a->report);
        std::unique_ptr<Progress> progress;
        options.progress = [&](int64_t, int64_t total) {
            if (!progress) {
                progress = std::make_unique<Progress>("preprocessOrtho", total, a->quiet);
            }
            progress->advance(1);
        };
        const OrthoReport report = encodeOrtho(a->input.resolve(), a->output, options);
        if (progress) {
            progress->finish();
        }
        if (!a->quiet) {
            printOrthoSummary(report);
            printGeoreferenceSummary(report.georeference, sidecar);
        }
        if (!a->report.empty()) {
            writeJson(toJson(report), a->report);
        }
        preflight.keep();
        return kExitOk;
    };
}

} // namespace pyramid::cli
