// `pyramid dem` / `preprocessDem`: an elevation raster in, a residual pyramid out.
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "cli/dem_options.hpp"
#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"

namespace pyramid::cli {

CommandRunner setupDemCommand(CLI::App& app) {
    auto args = std::make_shared<DemArgs>();
    auto target = std::make_shared<PlanarTargetArgs>();
    addDemOptions(app, args,
                  "Elevation raster (GeoTIFF, SRTM .hgt, DTED, ERDAS Imagine .img, XYZ text, USGS DEM, ESRI ASCII or .hdr-labelled grid, ENVI "
                  "raster, or any format OpenImageIO reads)",
                  "Residual pyramid file to write (e.g. DEM.dat)",
                  "The file's maxLevel, counted from the root tile (default: the smallest pyramid whose finest level holds "
                  "every input sample); the original tools' dstMaxLevel counts otherwise: see --dst-max-level",
                  true);
    app.add_flag("--stretch", args->options.stretch, "Stretch width and height independently onto the square root quad");
    addPlanarTargetOptions(app, *target);
    return [args, target]() {
        DemEncodeOptions options = resolveDemOptions(*args);
        options.target = target->resolve();
        checkOutputsApart(args->input,
                          {{args->output, "the output"},
                           {georeferenceSidecarPath(args->output), "where the georeference sidecar goes"}},
                          args->report);
        const bool talk = speaks(args->quiet);
        if (talk) {
            options.tileFitChosen = printTileFit;
        }
        std::unique_ptr<OutputPreflight> preflight;
        std::unique_ptr<Progress> progress;
        options.progress = [&](int64_t done, int64_t total) {
            if (!progress || done == 1) { // a new attempt (--scale auto) starts over
                progress = std::make_unique<Progress>("preprocessDem", total, !talk);
            }
            progress->advance(1);
        };
        DemReport report;
        const std::filesystem::path output(args->output);
        SplitBuild build;
        build.program = "preprocessDem";
        build.directory = output.has_parent_path() ? output.parent_path().string() : std::string(".");
        build.name = output.filename().string();
        build.prepare = [&] { preflight = std::make_unique<OutputPreflight>(args->output, false, args->report); };
        build.format = kResidualPartFormat;
        build.encode = [&](const PartContext* part) {
            DemEncodeOptions run = options;
            ResidualShare share;
            if (part) {
                share = ResidualShare{part->index, part->count, part->out, part->agree};
                run.share = &share;
            }
            report = encodeDem(args->input.resolve(), args->output, run);
        };
        build.merge = [&](const std::vector<std::string>& parts) {
            const ResidualMergeReport merged = mergeResidualParts(parts, build.directory, mergeProgress("preprocessDem", talk));
            takeMerged(report, merged.pyramids.at(0));
        };
        const BuildRole role = runSplitBuild(args->part, args->quiet, build);
        if (progress) {
            progress->finish();
        }
        if (role == BuildRole::OtherRank) {
            return kExitOk;
        }
        if (talk && role != BuildRole::Part) {
            printDemSummary(report);
            printValueScaling(report.input, report.inputInfo, report.band);
            if (!options.region) { // a region file has no sidecar of its own: the main file's places it
                printGeoreferenceSummary(report.georeference, georeferenceSidecarPath(args->output));
            }
        }
        if (!args->report.empty()) {
            writeJson(toJson(report), args->report);
        }
        preflight->keep();
        return kExitOk;
    };
}

} // namespace pyramid::cli
