#include "cli/ortho_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "formats/error.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid::cli {

namespace {

// `text` as one of `choices` (the names an option accepts, in the order its error lists them).
TilePolicy parsePolicy(const std::string& option, const std::string& text,
                       const std::vector<std::pair<std::string, TilePolicy>>& choices) {
    std::string names;
    for (size_t k = 0; k < choices.size(); ++k) {
        if (choices[k].first == text) {
            return choices[k].second;
        }
        names += (k == 0 ? "" : k + 1 == choices.size() ? " or " : ", ") + choices[k].first;
    }
    fail(option, "'" + text + "' is not " + names);
}

void parseOutputs(const std::string& text, OrthoEncodeOptions& o) {
    o.writeTiff = o.writeDxt = o.writeResiduals = false;
    std::stringstream list(text);
    std::string item;
    while (std::getline(list, item, ',')) {
        if (item == "tiff") {
            o.writeTiff = true;
        } else if (item == "dxt") {
            o.writeDxt = true;
        } else if (item == "residuals") {
            o.writeResiduals = true;
        } else {
            fail("--outputs", "'" + item + "' is not tiff, dxt or residuals");
        }
    }
}

} // namespace

void addOrthoOptions(CLI::App& app, const std::shared_ptr<OrthoArgs>& a, const char* inputHelp, const char* outputHelp,
                     const char* maxLevelHelp, bool tileSizeAuto) {
    OrthoEncodeOptions& o = a->options;
    addInputOptions(app, a->input, inputHelp);
    app.add_option("-o,--output", a->output, outputHelp)->required();
    app.add_option("--outputs", a->outputs, "Which files: a comma list of tiff, dxt, residuals")->capture_default_str();
    app.add_option("--name", o.name, "Base name of the files")->capture_default_str();
    if (tileSizeAuto) {
        a->tileSize = "auto";
    }
    a->tileSizeOption = addTileSizeOption(
        app, a->tileSize,
        tileSizeAuto ? "Tile size in pixels, without borders, or 'auto': the tile size (a multiple of 4, at most 256) "
                       "and levels whose finest level fits the input's longer side with the least resampling (192, the "
                       "original tools' size, where --max-level is given without --tile-size)"
                     : "Tile size in pixels, without borders",
        "pixels", tileSizeAuto, "preprocessOrtho");
    app.add_option("--max-level", o.levels.maxLevel, maxLevelHelp);
    app.add_option("--channels", o.levels.channels, "Use the first N channels (default: all, 1 to 4)");
    app.add_option("--border", o.border, "Tile border in pixels, 2 (as the original) or 0")->capture_default_str();
    app.add_option("--compression", a->compression,
                   "TIFF tiles: deflate (lossless), lzw, none, jpeg, jpeg-ycbcr (smaller; not for the original runtime), or original (JPEG inside, Deflate on the edge)")
        ->capture_default_str();
    app.add_option("--jpeg-quality", o.jpegQuality, "JPEG quality, 1 to 100")->capture_default_str();
    app.add_option("--deflate-level", o.deflateLevel,
                   "Deflate TIFF tiles: 1 (fastest) to 12 (smallest); the decoded pixels are the same")
        ->capture_default_str();
    app.add_flag("--jpeg-error", o.measureJpegError,
                 "Decode each JPEG TIFF tile again and report the largest error per level (tiff_max_error)");
    app.add_option("--dxt-quality", o.dxtQuality, "DXT encoder: 0 colour fit refined once (fastest), 1 refined twice, 2 libsquish cluster fit, 3 iterative (slowest)")
        ->capture_default_str();
    app.add_option("--residual-compression", a->residualCompression, "Colour residual tiles: deflate or jpeg")
        ->capture_default_str();
    app.add_option("--residual-deflate-level", a->residualDeflateLevel,
                   "Deflate colour residual tiles: auto (per tile 1 or 2, the faster for its residuals), or 1 "
                   "(fastest) to 12 (smallest); the residuals are the same")
        ->capture_default_str();
    app.add_option("--colour-space", a->colourSpace,
                   "Averaging for coarser levels: srgb (decode sRGB, average light, encode) or linear (as stored)")
        ->capture_default_str();
}

void addOrthoRunOptions(CLI::App& app, const std::shared_ptr<OrthoArgs>& a, bool faces) {
    OrthoEncodeOptions& o = a->options;
    addThreadsOption(app, o.levels.threads);
    addCacheOption(app, o.levels.cacheMegabytes);
    addMaxFileBytesOption(app, a->maxFileBytes, "each output as a region set");
    if (faces) {
        app.add_option("--layout", a->layout,
                       "sparse: a face the map does not fill is written as the files that hold its data (a main "
                       "file of the top levels and region files nested where the map is; doc/format.md 1.5), "
                       "no tile elsewhere; dense: every tile of every level in one file (or a --max-file-bytes set), "
                       "refused for maps of several resolutions")
            ->capture_default_str()
            ->check(CLI::IsMember({"sparse", "dense"}));
    }
    CLI::Option* part = addPartOption(app, a->part);
    addProgressOption(app);
    addRegionOptions(app, a->region, part,
                     "one region file of each output (named as a set names its files: NAME-L6-12-40.dat)",
                     "the colour-residual file (or set), residuals/NAME.dat");
    addReportOption(app, a->report, "the report");
    app.add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
}

OrthoEncodeOptions resolveOrthoOptions(const OrthoArgs& a) {
    OrthoEncodeOptions options = a.options;
    const bool tileSizeGiven = a.tileSizeOption != nullptr && a.tileSizeOption->count() > 0;
    if (a.tileSize == "auto" && options.levels.maxLevel && !tileSizeGiven) {
        options.levels.tileSize = OrthoLevelsOptions{}.tileSize; // levels given: the original tools' 192
    } else if (a.tileSize == "auto") {
        if (options.levels.maxLevel) {
            fail("--max-level", "is chosen by --tile-size auto: give one or the other");
        }
        options.levels.fitTiles = true;
    } else {
        options.levels.tileSize = *readWholeNumber<int>(a.tileSize); // a whole number: checked while parsing
    }
    options.layout = a.layout == "dense" ? PyramidLayout::Dense : PyramidLayout::Sparse;
    parseOutputs(a.outputs, options);
    options.compression = parsePolicy("--compression", a.compression,
                                      {{"deflate", TilePolicy::Deflate},
                                       {"lzw", TilePolicy::Lzw},
                                       {"jpeg", TilePolicy::Jpeg},
                                       {"jpeg-ycbcr", TilePolicy::JpegYCbCr},
                                       {"none", TilePolicy::None},
                                       {"original", TilePolicy::Original}});
    // Colour residual tiles are Deflate or JPEG (OrthoEncodeOptions::validate()).
    options.residualCompression = parsePolicy("--residual-compression", a.residualCompression,
                                              {{"deflate", TilePolicy::Deflate}, {"jpeg", TilePolicy::Jpeg}});
    if (a.residualDeflateLevel == "auto") {
        options.residualDeflateLevel = 0;
    } else {
        const double level = parseNumber(a.residualDeflateLevel, "--residual-deflate-level", "auto or 1..12");
        if (!(level >= 1 && level <= 12) || level != std::floor(level)) {
            fail("--residual-deflate-level", "'" + a.residualDeflateLevel + "' is not auto or 1..12");
        }
        options.residualDeflateLevel = static_cast<int>(level);
    }
    if (a.colourSpace == "srgb") {
        options.levels.colourSpace = ColourSpace::Srgb;
    } else if (a.colourSpace == "linear" || a.colourSpace == "none") {
        options.levels.colourSpace = ColourSpace::Linear;
    } else {
        fail("--colour-space", "'" + a.colourSpace + "' is not srgb or linear");
    }
    options.maxFileBytes = a.maxFileBytes.resolve();
    options.region = a.region.resolve();
    if (options.compression == TilePolicy::JpegYCbCr && options.writeTiff) {
        warn(a.quiet, "--compression jpeg-ycbcr: the original Proland runtime cannot read these tiles (libpyramid's "
                      "readers can)");
    }
    return options;
}

void takeMerged(OrthoReport& report, const OrthoReport& merged) {
    report.outputs = merged.outputs;
    report.bytes = merged.bytes;
    report.files = merged.files;
    report.sharedTiles = merged.sharedTiles;
    report.levels = merged.levels;
    report.tiles = merged.tiles;
}

void printOrthoSummary(const OrthoReport& report) {
    for (size_t k = 0; k < report.outputs.size(); ++k) {
        std::fprintf(stderr, "%s: %lld tiles (%lld shared), %llu bytes\n", report.outputs[k].c_str(),
                     static_cast<long long>(report.tiles), static_cast<long long>(report.sharedTiles[k]),
                     static_cast<unsigned long long>(report.bytes[k]));
        if (k < report.files.size() && !report.files[k].empty()) {
            uint64_t largest = 0;
            for (const auto& f : report.files[k]) {
                largest = std::max(largest, f.second);
            }
            std::fprintf(stderr, "  a region set of %zu files (the largest %llu bytes), listed in %s.regions.json\n",
                         report.files[k].size(), static_cast<unsigned long long>(largest), report.outputs[k].c_str());
        }
    }
    if (report.region) {
        std::fprintf(stderr, "  the region rooted at tile %s: its levels 0..%d", tileText(*report.region).c_str(),
                     report.maxLevel);
    } else {
        std::fprintf(stderr, "  levels 0..%d", report.maxLevel);
    }
    std::fprintf(stderr, " of %d-pixel tiles, %.1f s; %s\n", report.tileSize, report.seconds, report.sampling.c_str());
}

} // namespace pyramid::cli
