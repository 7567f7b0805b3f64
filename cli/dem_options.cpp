#include "cli/dem_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/encode/tile_size_rule.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid::cli {

namespace {

// The original Proland runtime's tile buffers hold 255 samples a side.
void warnUnreadableTiles(int tileSize, bool quiet) {
    if (tileSize + 5 >= 256) {
        warn(quiet, "tiles of " + std::to_string(tileSize + 5) +
                        " samples: the original Proland runtime reads tiles of at most 255 samples (tile size 250)");
    }
}

} // namespace

void addDemOptions(CLI::App& app, const std::shared_ptr<DemArgs>& args, const char* inputHelp, const char* outputHelp,
                   const char* maxLevelHelp, bool tileSizeAuto) {
    DemEncodeOptions& o = args->options;
    addInputOptions(app, args->input, inputHelp);
    app.add_option("-o,--output", args->output, outputHelp)->required();
    addTileSizeOption(app, args->tileSize,
                      tileSizeAuto ? "Tile size in intervals, without borders (tiles are size+5 samples), or 'auto': "
                                     "the tile size, root tile size and levels whose finest level is the input's own "
                                     "grid (vertex-registered, no resampling), or the least resampling where none is"
                                   : "Tile size in intervals, without borders (tiles are size+5 samples)",
                      "intervals", tileSizeAuto, "preprocessDem");
    args->rootTileSizeOption = app.add_option("--root-tile-size", o.rootTileSize,
                   "Intervals of the level-0 tile; minLevel = log2(tile-size / root-tile-size)")
        ->capture_default_str();
    app.add_option("--max-level", o.maxLevel, maxLevelHelp);
    app.add_option("--dst-max-level", o.dstMaxLevel,
                   "The finest level as the original tools' preprocessDem counts it (dstMaxLevel): from the first "
                   "level of full-size tiles, so the file's maxLevel is minLevel + this (with the defaults 192 and "
                   "24, minLevel is 3: dstMaxLevel 2 is --max-level 5)")
        ->excludes("--max-level");
    app.add_option("--scale", args->scale,
                   "Quantization step in height units, or 'auto' for the smallest 1-2-5 step without int16 overflow")
        ->capture_default_str();
    app.add_option("--max-error", args->maxError, "Largest allowed error E > 0: sets --scale to 2E")
        ->excludes("--scale")
        ->each([args](const std::string&) { args->maxErrorGiven = true; });
    app.add_option("--band", args->band, "Band (channel) holding the heights, from 1")->capture_default_str();
    app.add_option("--nodata", args->nodata,
                   "Value marking missing heights: a number, 'nan', 'inf', '-inf', or 'none' (default: what the file declares)");
    addResidualCodingOptions(app, args->coding);
    addThreadsOption(app, o.threads);
    addCacheOption(app, o.cacheMegabytes);
    addMaxFileBytesOption(app, args->maxFileBytes, "a region set");
    app.add_option("--layout", args->layout,
                   "sparse: where the input reaches only part of the pyramid, files only there (a main file of the "
                   "top levels and region files nested where the data is, each no deeper than its data; "
                   "doc/format.md 1.5); dense: every tile of every level in one file (or a --max-file-bytes set)")
        ->capture_default_str()
        ->check(CLI::IsMember({"sparse", "dense"}));
    CLI::Option* part = addPartOption(app, args->part);
    addProgressOption(app);
    addRegionOptions(app, args->region, part, "one region file (name it as a set does, e.g. DEM-L6-12-40.dat)",
                     "the main file (or set)");
    addReportOption(app, args->report, "the report");
    app.add_flag("-q,--quiet", args->quiet, "No progress or summary on stderr");
}

DemEncodeOptions resolveDemOptions(const DemArgs& args) {
    DemEncodeOptions options = args.options;
    if (args.maxErrorGiven) {
        if (!(args.maxError > 0.0)) {
            fail("--max-error", "must be a positive number, not " + numberText(args.maxError));
        }
        options.scale = 2.0 * args.maxError;
    } else if (args.scale == "auto") {
        options.autoScale = true;
    } else {
        options.scale = parseNumber(args.scale, "--scale", "a number or 'auto'"); // its range: validate()
    }
    options.tiles = args.coding.resolve(args.quiet);
    options.maxFileBytes = args.maxFileBytes.resolve();
    options.layout = args.layout == "dense" ? PyramidLayout::Dense : PyramidLayout::Sparse;
    options.region = args.region.resolve();
    options.band = args.band - 1;
    const NodataChoice nodata = parseNodataChoice(args.nodata, "--nodata");
    options.nodata = nodata.value;
    options.ignoreDeclaredNodata = nodata.ignoreDeclared;
    if (args.tileSize == "auto") {
        // The fit chooses the root tile and the levels with the tiles (dem_tile_fit.hpp).
        if (args.rootTileSizeOption && args.rootTileSizeOption->count() > 0) {
            fail("--root-tile-size", "is chosen by --tile-size auto: give one or the other");
        }
        if (options.maxLevel || options.dstMaxLevel) {
            fail(options.maxLevel ? "--max-level" : "--dst-max-level",
                 "is chosen by --tile-size auto: give one or the other");
        }
        options.fitTiles = true;
        return options; // the warning, if any, comes with the choice (printTileFit)
    }
    options.tileSize = std::stoi(args.tileSize); // a whole number: checked while parsing
    requireEncodableTileSize(options.tileSize);  // refused alone, before any warning about it
    warnUnreadableTiles(options.tileSize, args.quiet);
    return options;
}

void printTileFit(const DemTileFit& fit) {
    std::fprintf(stderr, "--tile-size auto: %s\n", fit.describe().c_str());
    warnUnreadableTiles(fit.tileSize, false); // printed only when the run speaks
}

void takeMerged(DemReport& report, const ResidualPyramidReport& merged) {
    report.header = merged.header;
    report.tiles = merged.tiles;
    report.sharedTiles = merged.sharedTiles;
    report.bytes = merged.bytes;
    report.files = merged.files;
    report.finestSamples = merged.finestSamples;
    report.nodataFilled = merged.nodataFilled;
    report.levels = merged.levels;
    report.scalesTried = merged.scalesTried;
}

void printValueScaling(const std::string& input, const RasterInfo& info, int band) {
    const auto b = static_cast<size_t>(band);
    if (b < info.scaling.size() && !info.scaling[b].identity()) {
        const double offset = info.scaling[b].offset;
        char added[40] = "";
        if (offset != 0.0) {
            std::snprintf(added, sizeof added, " %c %.10g", offset < 0.0 ? '-' : '+', std::fabs(offset));
        }
        std::fprintf(stderr, "%s: heights are band %d's samples x %.10g%s (its GDAL metadata)\n", input.c_str(),
                     band + 1, info.scaling[b].scale, added);
    }
}

void printDemSummary(const DemReport& r) {
    std::fprintf(stderr, "%s: %lld tiles (%lld shared), levels 0..%d of %d-tiles, scale %g, %.2f bits/sample, %.1f s\n",
                 r.output.c_str(), static_cast<long long>(r.tiles), static_cast<long long>(r.sharedTiles),
                 r.header.maxLevel, r.header.tileSize, static_cast<double>(r.header.scale),
                 r.finestSamples ? 8.0 * static_cast<double>(r.bytes) / static_cast<double>(r.finestSamples) : 0.0,
                 r.seconds);
    double worst = 0.0;
    for (const ResidualLevelReport& l : r.levels) {
        worst = std::max(worst, l.maxError);
    }
    std::fprintf(stderr, "  max error %g (bound scale/2 = %g), %lld nodata samples filled; %s\n", worst,
                 static_cast<double>(r.header.scale) / 2.0, static_cast<long long>(r.nodataFilled),
                 r.sampling.c_str());
    if (!r.files.empty()) {
        uint64_t largest = 0;
        for (const auto& f : r.files) {
            largest = std::max(largest, f.second);
        }
        if (r.files.size() == 1) { // a sparse set's main file alone, or a --max-file-bytes set that fits
            std::fprintf(stderr, "  a region set of its main file alone, listed in %s.regions.json\n", r.output.c_str());
        } else {
            std::fprintf(stderr, "  a region set of %zu files (the largest %llu bytes), listed in %s.regions.json\n",
                         r.files.size(), static_cast<unsigned long long>(largest), r.output.c_str());
        }
    }
}

} // namespace pyramid::cli
