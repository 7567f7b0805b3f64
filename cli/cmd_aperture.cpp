// `pyramid aperture` / `preprocessAperture DEM.dat -o APERTURE.dat`: the ambient aperture of a
// residual pyramid (libpyramid/encode/aperture/aperture.hpp), as an ortho pyramid; and
// `pyramid sphere-aperture` / `preprocessSphericalAperture DIR -o OUT`: of a planet's six faces.
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "libpyramid/encode/aperture/aperture.hpp"

namespace pyramid::cli {

namespace {

// The horizon search's options, shared by both commands.
void addSearchOptions(CLI::App& app, ApertureSearch& search) {
    app.add_option("--directions", search.directions, "Azimuths of the horizon search, 4 to 256")->capture_default_str();
    app.add_option("--radius", search.radius, "Steps along each azimuth per level, an even number from 2 to 1024")
        ->capture_default_str();
    app.add_option("--levels", search.levels,
                   "Levels searched: the finest, then each coarser one twice as far (the reach doubles a level), 1 to 16")
        ->capture_default_str();
}

// The output's options, shared by both commands.
void addOutputOptions(CLI::App& app, int& deflateLevel, int& threads, std::string& report, bool& quiet) {
    app.add_option("--deflate-level", deflateLevel, "Deflate level of the TIFF tiles, 1 to 12")
        ->capture_default_str()
        ->check(CLI::Range(1, 12));
    addThreadsOption(app, threads);
    addReportOption(app, report, "the report");
    app.add_flag("-q,--quiet", quiet, "No progress or summary on stderr");
    addProgressOption(app);
}

} // namespace

CommandRunner setupApertureCommand(CLI::App& app) {
    struct Args {
        std::string input, output, report;
        ApertureEncodeOptions options;
        bool quiet = false;
    };
    auto a = std::make_shared<Args>();
    ApertureEncodeOptions& o = a->options;
    app.add_option("INPUT", a->input, "A residual (DEM) pyramid file or region set (its main file, index or directory)")
        ->required();
    app.add_option("-o,--output", a->output, "The aperture pyramid to write (an ortho file, e.g. APERTURE.dat)")
        ->required();
    app.add_option("--size", o.size,
                   "The root quad's side on the ground in height units (default: from INPUT's georeference sidecar, in "
                   "metres)");
    addSearchOptions(app, o.search);
    addOutputOptions(app, o.deflateLevel, o.threads, a->report, a->quiet);
    return [a]() {
        const bool talk = speaks(a->quiet);
        OutputPreflight preflight(a->output, false, a->report);
        ApertureEncodeOptions options = a->options;
        options.progress = progressCallback("preprocessAperture", !talk);
        const ApertureReport r = encodeApertureFile(a->input, a->output, options);
        if (talk) {
            std::fprintf(stderr,
                         "%s: aperture of %s, %lld tiles of %d pixels, levels 0..%d, %.6g height units a pixel at the "
                         "finest, %d azimuths x %d steps x %d levels, %llu bytes, %.1f s\n",
                         r.output.c_str(), r.input.c_str(), static_cast<long long>(r.tiles), r.tileSize, r.maxLevel,
                         r.spacing, r.search.directions, r.search.radius, r.search.levels,
                         static_cast<unsigned long long>(r.bytes), r.seconds);
        }
        if (!a->report.empty()) {
            writeJson(toJson(r), a->report);
        }
        preflight.keep();
        return kExitOk;
    };
}

CommandRunner setupSphereApertureCommand(CLI::App& app) {
    struct Args {
        std::string input, output, report;
        SphericalApertureOptions options;
        bool quiet = false;
    };
    auto a = std::make_shared<Args>();
    SphericalApertureOptions& o = a->options;
    app.add_option("INPUT", a->input, "The directory of the six faces (NAME1.dat .. NAME6.dat, files or region sets)")
        ->required();
    app.add_option("-o,--output", a->output, "The directory to write OUTPUT1.dat .. OUTPUT6.dat into")->required();
    app.add_option("--name", o.name, "Base name of the faces read")->capture_default_str();
    app.add_option("--output-name", o.output, "Base name of the faces written")->capture_default_str();
    app.add_option("--body", o.body, "The body the faces were built on, as preprocessSphericalDem takes it")
        ->capture_default_str();
    app.add_option("--radius-metres", o.radius,
                   "The sphere the heights stand on (default: the body's equatorial radius)");
    addSearchOptions(app, o.search);
    addOutputOptions(app, o.deflateLevel, o.threads, a->report, a->quiet);
    return [a]() {
        const bool talk = speaks(a->quiet);
        OutputPreflight preflight(a->output, true, a->report);
        SphericalApertureOptions options = a->options;
        options.progress = progressCallback("preprocessSphericalAperture", !talk);
        const SphericalApertureReport r = encodeSphericalApertureFiles(a->input, a->output, options);
        if (talk) {
            std::fprintf(stderr,
                         "%s: aperture of the faces of %s, %lld tiles of %d pixels, levels 0..%d, %.6g m a pixel at the "
                         "finest (on a sphere of %.10g m), %d azimuths x %d steps x %d levels, %llu bytes, %.1f s\n",
                         r.directory.c_str(), r.input.c_str(), static_cast<long long>(r.tiles), r.tileSize, r.maxLevel,
                         r.spacing, r.radius, r.search.directions, r.search.radius, r.search.levels,
                         static_cast<unsigned long long>(r.bytes), r.seconds);
        }
        if (!a->report.empty()) {
            writeJson(toJson(r), a->report);
        }
        preflight.keep();
        return kExitOk;
    };
}

} // namespace pyramid::cli
