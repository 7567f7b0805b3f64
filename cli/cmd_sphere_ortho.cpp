// `pyramid sphere-ortho` / `preprocessSphericalOrtho`: a global image in, six cube-face ortho
// pyramids out (each with its dxt/ and residuals/ variants).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "cli/ortho_options.hpp"
#include "cli/sphere_options.hpp"
#include "libpyramid/api/encoders.hpp"

namespace pyramid::cli {

CommandRunner setupSphereOrthoCommand(CLI::App& app) {
    auto a = std::make_shared<OrthoArgs>();
    auto sphere = std::make_shared<SphereArgs>();
    addOrthoOptions(app, a,
                    "Imagery (1-4 channels of 8 or 16 bits): a GeoTIFF where its georeferencing places it, else "
                    "equirectangular with column 0 at longitude -180 (or the extent's west), row 0 at the north; "
                    "pixel centres",
                    "Output directory: NAME1..6.dat, dxt/NAME1..6.dat, residuals/NAME1..6.dat",
                    "maxLevel of every face (default: the smallest whose faces are as fine as the map at the equator)");
    addSphereOptions(app, sphere);
    addOrthoRunOptions(app, a, true);
    return [a, sphere]() {
        SphericalOrthoOptions options;
        options.ortho = resolveOrthoOptions(*a);
        const SphereChoice choice = resolveSphereOptions(*sphere);
        options.extent = choice.extent;
        options.body = choice.body;
        options.faces = choice.faces;
        const bool quiet = a->quiet;
        options.warning = [quiet](const std::string& what) { warn(quiet, what); };
        checkOutputsApart(a->input, {}, a->report); // the faces go into a directory
        const bool talk = speaks(a->quiet);
        std::unique_ptr<OutputPreflight> preflight;
        std::unique_ptr<Progress> progress;
        int64_t shown = 0;
        options.ortho.progress = [&](int64_t done, int64_t total) {
            if (!progress) {
                progress = std::make_unique<Progress>("preprocessSphericalOrtho", total, !talk);
            }
            progress->advance(done - shown);
            shown = done;
        };
        SphericalOrthoReport report;
        SplitBuild build;
        build.program = "preprocessSphericalOrtho";
        build.directory = a->output;
        build.name = options.ortho.name;
        build.format = kOrthoPartFormat;
        build.prepare = [&] { preflight = std::make_unique<OutputPreflight>(a->output, true, a->report); };
        build.encode = [&](const PartContext* part) {
            SphericalOrthoOptions run = options;
            OrthoShare share;
            if (part) {
                share = OrthoShare{part->index, part->count, part->out};
                run.ortho.share = &share;
            }
            report = encodeSphericalOrtho(a->input.resolve(), a->output, run);
        };
        build.merge = [&](const std::vector<std::string>& parts) {
            const OrthoMergeReport merged =
                mergeOrthoParts(parts, build.directory, mergeProgress("preprocessSphericalOrtho", talk));
            for (size_t k = 0; k < report.faces.size() && k < merged.pyramids.size(); ++k) {
                takeMerged(report.faces[k].ortho, merged.pyramids[k]);
            }
        };
        const BuildRole role = runSplitBuild(a->part, a->quiet, build);
        if (progress) {
            progress->finish();
        }
        if (role == BuildRole::OtherRank) {
            return kExitOk;
        }
        if (talk && role != BuildRole::Part) {
            std::fprintf(stderr, "%s: %s\n", a->output.c_str(), report.body.c_str());
            for (const SphericalOrthoFaceReport& f : report.faces) {
                printOrthoSummary(f.ortho);
                std::fprintf(stderr, "  finest level: %.0f to %.0f m between pixels\n", f.gsd.back().min,
                             f.gsd.back().max);
            }
        }
        if (!a->report.empty()) {
            writeJson(toJson(report), a->report);
        }
        preflight->keep();
        return kExitOk;
    };
}

} // namespace pyramid::cli
