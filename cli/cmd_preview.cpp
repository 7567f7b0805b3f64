// `pyramid preview FILE|SET -o OUT.png [--level L] [--size PX] [--style ...]`: one level of a
// pyramid drawn as a PNG (libpyramid/preview/preview.hpp, doc/cli/pyramid-preview.md).
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"
#include "libpyramid/preview/preview.hpp"

namespace pyramid::cli {

namespace {

struct PreviewArgs {
    std::string target, output, style = "auto", projection = "auto";
    double seaLevel = 0.0;
    PreviewOptions options;
    std::string report; // --report FILE|- (or --json)
    bool quiet = false;
};

} // namespace

CommandRunner setupPreviewCommand(CLI::App& app) {
    auto a = std::make_shared<PreviewArgs>();
    PreviewOptions& o = a->options;
    app.add_option("TARGET", a->target,
                   "A pyramid file or region set (its main file, index or directory), or a planet: a directory of "
                   "six cube faces NAME1.dat .. NAME6.dat, or one of them with --projection")
        ->required();
    app.add_option("-o,--output", a->output, "The PNG to write")->required();
    app.add_option("--level", o.level,
                   "The level to draw (default: the deepest at most --size samples a side; planets: a face at most "
                   "--size / 4)");
    app.add_option("--size", o.size, "Pixels a side the default level may have (planets: the image's width)")
        ->capture_default_str();
    app.add_option("--projection", a->projection,
                   "auto (a directory of six faces: equirectangular, else face), face (one pyramid as its samples), "
                   "equirectangular or world (a planet's world map, 4 face sides by 2), cube (a planet's six faces "
                   "unfolded into a cross, 4 by 3)")
        ->capture_default_str();
    app.add_option("--body", o.body, "Planets: the body the faces were built on, as the spherical preprocessors take it")
        ->capture_default_str();
    app.add_flag("--legend", o.legend, "Elevations: a colour bar with the range it spans below the image");
    auto* sea = app.add_option("--sea-level", a->seaLevel, "Elevations: heights at or below this drawn as water");
    app.add_option("--style", a->style,
                   "auto, hillshade (elevations: shaded hypsometric colours), shade (the hillshade alone, grey), heights (colours alone), residuals "
                   "(the stored residuals times the scale, blue to red), colours (orthos)")
        ->capture_default_str();
    app.add_option("--spacing", o.spacing,
                   "Hillshade: ground distance between the level's samples in height units (default: from "
                   "FILE.georef.json in metres, else 1)");
    app.add_option("--z-factor", o.zFactor, "Hillshade: heights are multiplied by this")->capture_default_str();
    app.add_option("--azimuth", o.azimuth, "Hillshade: the sun, degrees clockwise from north")->capture_default_str();
    app.add_option("--altitude", o.altitude, "Hillshade: the sun, degrees above the horizon")->capture_default_str();
    addReportOption(app, a->report, "the report");
    app.add_flag("-q,--quiet", a->quiet, "No summary on stderr");
    return [a, sea]() {
        if (lowerExtension(a->output) != ".png") {
            fail(a->output, "a preview is a PNG: name it OUT.png");
        }
        PreviewOptions options = a->options;
        options.style = parsePreviewStyle(a->style);
        options.projection = parsePreviewProjection(a->projection);
        if (*sea) {
            options.seaLevel = a->seaLevel;
        }
        const PreviewReport r = writePreview(a->target, a->output, options);
        if (!a->quiet) {
            std::fprintf(stderr, "%s: level %d of %s%s, %d x %d pixels, %s (%s %g to %g)\n", a->output.c_str(), r.level,
                         r.input.c_str(), r.projection == "face" ? "" : (" (" + r.projection + ")").c_str(), r.width,
                         r.height, r.style.c_str(),
                         r.style == "residuals" ? "residuals" : r.kind == "elevation" ? "heights" : "values",
                         r.minimum, r.maximum);
        }
        if (!a->report.empty()) {
            writeJson(toJson(r), a->report);
        }
        return kExitOk;
    };
}

} // namespace pyramid::cli
