// `pyramid sphere-dem` / `preprocessSphericalDem`: a global elevation map in, six cube-face
// residual pyramids out.
#include <cstdio>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "cli/dem_options.hpp"
#include "cli/sphere_options.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid::cli {

CommandRunner setupSphereDemCommand(CLI::App& app) {
    auto args = std::make_shared<DemArgs>();
    auto sphere = std::make_shared<SphereArgs>();
    auto heightScale = std::make_shared<std::string>("1");
    auto name = std::make_shared<std::string>("DEM");
    auto fill = std::make_shared<std::string>("smooth");
    addDemOptions(app, args,
                  "Elevation map: a GeoTIFF (or SRTM .hgt, DTED, ERDAS Imagine, XYZ text, USGS DEM, ESRI grid, ENVI raster) where its "
                  "georeferencing places it, else equirectangular with column 0 at longitude -180 (or the extent's west), row 0 at "
                  "the north; pixel centres",
                  "Directory to write NAME1.dat .. NAME6.dat into",
                  "maxLevel of every face, counted from the root tile (default: the smallest whose faces are as fine as the "
                  "map at the equator); the original tools' dstMaxLevel counts otherwise: see --dst-max-level");
    addSphereOptions(app, sphere);
    app.add_option("--height-scale", *heightScale,
                   "Multiply every sample by this number or ratio (e.g. 10000/255 for heights stored as 8-bit red)")
        ->capture_default_str();
    app.add_option("--fill", *fill,
                   "Height of the nodata the root holds (beyond the map, or its holes): smooth (from the map's heights "
                   "by Laplace's equation across the cube's edges) or a height after --height-scale, e.g. 0 for sea "
                   "level; deeper levels blend it with the map's heights")
        ->capture_default_str();
    app.add_option("--name", *name, "Base name of the files")->capture_default_str();
    return [args, sphere, heightScale, fill, name]() {
        SphericalDemOptions options;
        options.dem = resolveDemOptions(*args);
        const SphereChoice choice = resolveSphereOptions(*sphere);
        options.extent = choice.extent;
        options.body = choice.body;
        options.faces = choice.faces;
        options.heightScale = parseRatio(*heightScale, "--height-scale");
        if (*fill != "smooth") {
            options.fillHeight = parseNumber(*fill, "--fill", "a height or 'smooth'");
        }
        options.name = *name;
        const bool quiet = args->quiet;
        options.warning = [quiet](const std::string& what) { warn(quiet, what); };
        checkOutputsApart(args->input, {}, args->report); // the faces go into a directory
        const bool talk = speaks(args->quiet);
        std::unique_ptr<OutputPreflight> preflight;
        std::unique_ptr<Progress> progress;
        int64_t shown = 0;
        options.dem.progress = [&](int64_t done, int64_t total) {
            if (!progress) {
                progress = std::make_unique<Progress>("preprocessSphericalDem", total, !talk);
            }
            progress->advance(done - shown);
            shown = done;
        };
        SphericalDemReport report;
        SplitBuild build;
        build.program = "preprocessSphericalDem";
        build.directory = args->output;
        build.name = options.name;
        build.prepare = [&] { preflight = std::make_unique<OutputPreflight>(args->output, true, args->report); };
        build.format = kResidualPartFormat;
        build.encode = [&](const PartContext* part) {
            SphericalDemOptions run = options;
            ResidualShare share;
            if (part) {
                share = ResidualShare{part->index, part->count, part->out, part->agree};
                run.dem.share = &share;
            }
            report = encodeSphericalDem(args->input.resolve(), args->output, run);
        };
        build.merge = [&](const std::vector<std::string>& parts) {
            const ResidualMergeReport merged =
                mergeResidualParts(parts, build.directory, mergeProgress("preprocessSphericalDem", talk));
            for (size_t k = 0; k < report.faces.size() && k < merged.pyramids.size(); ++k) {
                takeMerged(report.faces[k].dem, merged.pyramids[k]);
            }
        };
        const BuildRole role = runSplitBuild(args->part, args->quiet, build);
        if (progress) {
            progress->finish();
        }
        if (role == BuildRole::OtherRank) {
            return kExitOk;
        }
        if (talk && role != BuildRole::Part) {
            std::fprintf(stderr, "%s: %s\n", args->output.c_str(), report.body.c_str());
            printValueScaling(report.input, report.inputInfo, report.band);
            for (const SphericalDemFaceReport& f : report.faces) {
                printDemSummary(f.dem);
                std::fprintf(stderr, "  finest level: %.0f to %.0f m between samples\n", f.gsd.back().min,
                             f.gsd.back().max);
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
