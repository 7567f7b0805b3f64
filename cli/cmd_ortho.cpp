// `pyramid ortho` / `preprocessOrtho`: imagery in, ortho pyramids out.
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"
#include "libpyramid/ortho_encoder.hpp"

namespace pyramid::cli {

namespace {

TilePolicy parsePolicy(const std::string& option, const std::string& text) {
    static const std::map<std::string, TilePolicy> names = {{"deflate", TilePolicy::Deflate},
                                                            {"lzw", TilePolicy::Lzw},
                                                            {"jpeg", TilePolicy::Jpeg},
                                                            {"none", TilePolicy::None},
                                                            {"original", TilePolicy::Original}};
    const auto it = names.find(text);
    if (it == names.end()) {
        fail(option, "'" + text + "' is not deflate, lzw, jpeg, none or original");
    }
    return it->second;
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

CommandRunner setupOrthoCommand(CLI::App& app) {
    struct Args {
        std::string input, output, outputs = "tiff,dxt,residuals", compression = "deflate",
                                   residualCompression = "deflate", colourSpace = "srgb", report;
        bool quiet = false;
        OrthoEncodeOptions options;
    };
    auto a = std::make_shared<Args>();
    OrthoEncodeOptions& o = a->options;
    app.add_option("INPUT", a->input, "Imagery: 1-4 channels of 8 or 16 bits (any format OpenImageIO reads)")->required();
    app.add_option("-o,--output", a->output, "Output directory: NAME.dat, dxt/NAME.dat, residuals/NAME.dat")->required();
    app.add_option("--outputs", a->outputs, "Which files: a comma list of tiff, dxt, residuals")->capture_default_str();
    app.add_option("--name", o.name, "Base name of the files")->capture_default_str();
    app.add_option("--tile-size", o.levels.tileSize, "Tile size in pixels, without borders")->capture_default_str();
    app.add_option("--max-level", o.levels.maxLevel,
                   "The files' maxLevel (default: the smallest whose tile-size << maxLevel holds the longer side)");
    app.add_option("--channels", o.levels.channels, "Use the first N channels (default: all, 1 to 4)");
    app.add_option("--border", o.border, "Tile border in pixels, 2 (as the original) or 0")->capture_default_str();
    app.add_option("--compression", a->compression,
                   "TIFF tiles: deflate (lossless), lzw, none, jpeg, or original (JPEG inside, Deflate on the edge)")
        ->capture_default_str();
    app.add_option("--jpeg-quality", o.jpegQuality, "JPEG quality, 1 to 100")->capture_default_str();
    app.add_option("--dxt-quality", o.dxtQuality, "DXT encoder effort: 0 fast, 1 cluster fit, 2 iterative (best)")
        ->capture_default_str();
    app.add_option("--residual-compression", a->residualCompression, "Colour residual tiles: deflate or jpeg")
        ->capture_default_str();
    app.add_option("--colour-space", a->colourSpace,
                   "Averaging for coarser levels: srgb (decode sRGB, average light, encode) or linear (as stored)")
        ->capture_default_str();
    app.add_flag("--stretch", o.levels.stretch, "Stretch width and height independently onto the square root quad");
    app.add_option("--threads", o.levels.threads, "Worker threads (default: all cores; the output does not depend on it)");
    app.add_option("--cache-mb", o.levels.cacheMegabytes, "Input cache budget in MB")->capture_default_str();
    app.add_option("--report", a->report, "Write a JSON report to this file ('-' for stdout)");
    app.add_flag("-q,--quiet", a->quiet, "No progress or summary on stderr");
    return [a]() {
        OrthoEncodeOptions options = a->options;
        parseOutputs(a->outputs, options);
        options.compression = parsePolicy("--compression", a->compression);
        options.residualCompression = parsePolicy("--residual-compression", a->residualCompression);
        if (a->colourSpace == "srgb") {
            options.levels.colourSpace = ColourSpace::Srgb;
        } else if (a->colourSpace == "linear" || a->colourSpace == "none") {
            options.levels.colourSpace = ColourSpace::Linear;
        } else {
            fail("--colour-space", "'" + a->colourSpace + "' is not srgb or linear");
        }
        if (options.levels.threads < 0) {
            fail("--threads", "must be 0 (all cores) or more");
        }
        std::unique_ptr<Progress> progress;
        options.progress = [&](int64_t done, int64_t total) {
            if (!progress) {
                progress = std::make_unique<Progress>("preprocessOrtho", total, a->quiet);
            }
            progress->advance(1);
            (void)done;
        };
        const OrthoReport report = encodeOrtho(a->input, a->output, options);
        if (progress) {
            progress->finish();
        }
        if (!a->quiet) {
            for (size_t k = 0; k < report.outputs.size(); ++k) {
                std::fprintf(stderr, "%s: %lld tiles (%lld shared), %llu bytes\n", report.outputs[k].c_str(),
                             static_cast<long long>(report.tiles), static_cast<long long>(report.sharedTiles[k]),
                             static_cast<unsigned long long>(report.bytes[k]));
            }
            std::fprintf(stderr, "  levels 0..%d of %d-pixel tiles, %.1f s; %s\n", report.maxLevel, report.tileSize,
                         report.seconds, report.sampling.c_str());
        }
        if (!a->report.empty()) {
            writeJson(toJson(report), a->report);
        }
        return kExitOk;
    };
}

} // namespace pyramid::cli
