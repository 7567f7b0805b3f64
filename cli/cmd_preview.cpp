// `pyramid preview FILE|SET -o OUT.png [--level L] [--size PX] [--style ...]`: one level of a
// pyramid drawn as a PNG (libpyramid/preview/preview.hpp, doc/cli/pyramid-preview.md).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"
#include "libpyramid/preview/preview.hpp"

namespace pyramid::cli {

namespace {

struct PreviewArgs {
    std::string target, output, style = "auto";
    PreviewOptions options;
    std::string report; // --report FILE|- (or --json)
    bool quiet = false;
};

} // namespace

CommandRunner setupPreviewCommand(CLI::App& app) {
    auto a = std::make_shared<PreviewArgs>();
    PreviewOptions& o = a->options;
    app.add_option("TARGET", a->target, "A pyramid file or region set (its main file, index or directory)")->required();
    app.add_option("-o,--output", a->output, "The PNG to write")->required();
    app.add_option("--level", o.level, "The level to draw (default: the deepest at most --size samples a side)");
    app.add_option("--size", o.size, "Pixels a side the default level may have")->capture_default_str();
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
    return [a]() {
        std::string ext = std::filesystem::path(a->output).extension().string();
        for (char& c : ext) {
            c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        }
        if (ext != ".png") {
            fail(a->output, "a preview is a PNG: name it OUT.png");
        }
        PreviewOptions options = a->options;
        options.style = parsePreviewStyle(a->style);
        const PreviewReport r = writePreview(a->target, a->output, options);
        if (!a->quiet) {
            std::fprintf(stderr, "%s: level %d of %s, %d x %d pixels, %s (%s %g to %g)\n", a->output.c_str(), r.level,
                         r.input.c_str(), r.width, r.height, r.style.c_str(),
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
