// `pyramid verify SET --source INPUT`: rebuild every level of a file or a region set (its main
// file, index or directory) and compare it with the source.
// `pyramid verify DIR --source MAP`: every face of a planet (DEM or imagery) against its map.
// `pyramid verify FILE --gl`: produce every tile on the CPU and on the GPU and compare them.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <optional>
#include <vector>
#include <filesystem>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "cli/sphere_options.hpp"
#include "formats/error.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/pyramid_set.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/input/input_list.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#ifdef PYRAMID_WITH_GL
#include "libpyramid/gl/gl_verify.hpp"
#endif

namespace pyramid::cli {

namespace {

struct VerifyArgs {
    std::string file;
    std::string source;
    std::string report; // --report FILE|- (or --json)
    int band = 1;
    std::string nodata;
    bool stretch = false;
    int threads = 0;
    bool colourResiduals = false;
    std::string colourSpace = "srgb";
    bool gl = false;
    bool quiet = false;
    PlanarTargetArgs target;
    // A planet's directory (NAME1..6.dat, as preprocessSphericalDem wrote them):
    std::string body = "wgs84";
    std::string name;  // empty: DEM, else RGB (the faces the directory holds)
    std::string faces; // empty: every face the directory holds
    std::string heightScale = "1";
};

// A residual pyramid's verification, a line per level, under a line naming it and its source.
void printDemLevels(const DemVerifyReport& report) {
    std::printf("%s against %s: scale %g, bound %g\n", report.file.c_str(), report.source.c_str(), report.scale,
                report.bound);
    for (const DemVerifyLevel& l : report.levels) {
        char line[200];
        std::snprintf(line, sizeof line, "  level %2d: %6lld tiles %10lld samples  max error %-10.6g rms %-10.6g%s",
                      l.level, static_cast<long long>(l.tiles), static_cast<long long>(l.samples), l.maxError,
                      l.rmsError, l.beyondBound ? "  BEYOND BOUND" : "");
        std::string text = line;
        if (l.nonFinite) {
            text += "  " + std::to_string(l.nonFinite) + " NON-FINITE";
        }
        text.erase(text.find_last_not_of(' ') + 1); // the columns' padding, not at the end of a line
        std::printf("%s\n", text.c_str());
    }
}

// preprocessOrtho writes its colour residuals into DIR/residuals/ (the spherical one its faces),
// in the same file format as plain tiles: compared as tiles, they differ everywhere. A hint for
// a failed comparison of files in `folder`.
std::string residualsHint(const std::filesystem::path& folder, bool colourResiduals) {
    std::filesystem::path name = folder.filename();
    if (name.empty()) {
        name = folder.parent_path().filename(); // "DIR/residuals/"
    }
    return name == "residuals" && !colourResiduals
               ? " (its folder is residuals/: verify colour residuals with --colour-residuals)"
               : "";
}

ColourSpace parseColourSpace(const std::string& text) {
    if (text == "linear" || text == "none") {
        return ColourSpace::Linear;
    }
    if (text != "srgb") {
        fail("--colour-space", "'" + text + "' is not srgb or linear");
    }
    return ColourSpace::Srgb;
}

// An ortho pyramid's verification, a line per level, under a line naming it and its source.
void printOrthoLevels(const OrthoVerifyReport& report) {
    std::printf("%s against %s (%s)\n", report.file.c_str(), report.source.c_str(), report.mode.c_str());
    for (const OrthoVerifyLevel& l : report.levels) {
        std::printf("  level %2d: %6lld tiles  max error %3d  rms %-8.4g psnr %6.2f dB  %lld lossy tiles\n", l.level,
                    static_cast<long long>(l.tiles), l.maxError, l.rmsError, l.psnr,
                    static_cast<long long>(l.lossyTiles));
    }
}

// Whether NAMEi.dat of a planet's directory is there, as a file or as a region set's index.
bool faceThere(const std::string& directory, const std::string& name, int face) {
    const std::string file = faceFilePath(directory, name, face);
    std::error_code ec;
    return std::filesystem::exists(file, ec) || std::filesystem::exists(regionIndexPath(file), ec);
}

// The base name of the faces a planet's directory holds: --name, else DEM or RGB, the first the
// directory holds a face of; nothing for a path that is not such a directory.
std::optional<std::string> planetFaceName(const VerifyArgs& a) {
    std::error_code ec;
    if (!std::filesystem::is_directory(a.file, ec)) {
        return std::nullopt;
    }
    const std::vector<std::string> names = a.name.empty() ? std::vector<std::string>{"DEM", "RGB"}
                                                          : std::vector<std::string>{a.name};
    for (const std::string& name : names) {
        for (int face = 1; face <= 6; ++face) {
            if (faceThere(a.file, name, face)) {
                return name;
            }
        }
    }
    return std::nullopt;
}

// Which options were given on the command line: those that apply to one kind of face only.
struct GivenOptions {
    bool band = false, nodata = false, heightScale = false, colourSpace = false;
};

// `pyramid verify DIR --source MAP`: every face of a planet (DEM faces, or imagery faces: plain,
// DXT or colour residuals) rebuilt and compared with the map, opened and sampled as the
// spherical preprocessors do.
int verifySpherical(const VerifyArgs& a, const std::string& name, const GivenOptions& given) {
    if (a.source.empty()) {
        fail("--source", "verifying a planet's faces needs the map they were built from (--source MAP)");
    }
    if (!a.target.crs.empty()) {
        fail("--crs", "a planet's faces are not in a CRS: give the map as the spherical preprocessors took it");
    }
    if (a.stretch) {
        fail("--stretch", "does not apply to a planet's faces");
    }
    std::string faces = a.faces;
    if (faces.empty()) {
        for (int face = 1; face <= 6; ++face) {
            if (faceThere(a.file, name, face)) {
                faces += (faces.empty() ? "" : ",") + std::to_string(face);
            }
        }
    }
    const SphereChoice choice = resolveSphereOptions(SphereArgs{a.target.extent, a.body, faces});
    const std::string first = faceFilePath(a.file, name, choice.faces.front());
    const PyramidKind kind =
        findRegionIndex(first).empty() ? detectPyramidKind(first) : resolvePyramidSet(first).kind;
    const std::vector<std::string> inputs = expandInputs({a.source}).paths;
    const auto progress = progressCallback(a.file, a.quiet, Progress::OffTerminal::Silent);
    std::vector<bool> passed;
    nlohmann::json faceReports = nlohmann::json::array();
    std::vector<std::function<void()>> prints;
    if (kind == PyramidKind::Residual) {
        if (a.colourResiduals || given.colourSpace) {
            fail(a.colourResiduals ? "--colour-residuals" : "--colour-space", "does not apply to a planet's DEM faces");
        }
        SphericalDemVerifyOptions o;
        o.body = choice.body;
        o.name = name;
        o.faces = choice.faces;
        o.extent = choice.extent;
        o.heightScale = parseRatio(a.heightScale, "--height-scale");
        o.threads = a.threads;
        o.band = a.band - 1;
        const NodataChoice nodata = parseNodataChoice(a.nodata, "--nodata");
        o.nodata = nodata.value;
        o.ignoreDeclaredNodata = nodata.ignoreDeclared;
        o.progress = progress;
        for (const DemVerifyReport& r : verifySphericalDem(a.file, inputs, o)) {
            passed.push_back(r.ok());
            faceReports.push_back(toJson(r));
            prints.push_back([r] { printDemLevels(r); });
        }
    } else {
        if (given.band || given.nodata || given.heightScale) {
            fail(given.band ? "--band" : given.nodata ? "--nodata" : "--height-scale",
                 "does not apply to a planet's imagery faces");
        }
        SphericalOrthoVerifyOptions o;
        o.body = choice.body;
        o.name = name;
        o.faces = choice.faces;
        o.extent = choice.extent;
        o.colourSpace = parseColourSpace(a.colourSpace);
        o.colourResiduals = a.colourResiduals;
        o.threads = a.threads;
        o.progress = progress;
        for (const OrthoVerifyReport& r : verifySphericalOrtho(a.file, inputs, o)) {
            passed.push_back(r.ok);
            faceReports.push_back(toJson(r));
            prints.push_back([r] { printOrthoLevels(r); });
        }
    }
    const bool dem = kind == PyramidKind::Residual;
    const bool ok = std::all_of(passed.begin(), passed.end(), [](bool p) { return p; });
    for (size_t k = 0; k < faceReports.size(); ++k) {
        faceReports[k]["face"] = choice.faces[k];
    }
    if (!a.report.empty()) {
        writeJson({{"directory", a.file}, {"source", a.source}, {"faces", faceReports}, {"ok", ok}}, a.report);
    }
    if (a.report != "-") {
        for (const auto& print : prints) {
            print();
        }
        std::printf("%s\n", ok ? (dem ? "ok: every sample of every face within scale/2" : "ok: every face")
                               : (dem ? "FAILED: samples beyond scale/2 or not finite"
                                      : "FAILED: lossless tiles differ from the source"));
    }
    if (!ok) {
        std::string failed;
        size_t count = 0;
        for (size_t k = 0; k < passed.size(); ++k) {
            if (!passed[k]) {
                failed += (failed.empty() ? "" : ", ") + std::to_string(choice.faces[k]);
                ++count;
            }
        }
        sayFailure(a.file + ": face" + (count == 1 ? " " : "s ") + failed + " (" + name + "N.dat): " +
                   (dem ? "samples beyond scale/2 or not finite" : "lossless tiles differ") + " against " + a.source +
                   (dem ? "" : residualsHint(a.file, a.colourResiduals)));
    }
    return ok ? kExitOk : kExitFailure;
}

int verifyResidual(const VerifyArgs& a) {
    if (a.source.empty()) {
        fail("--source", "verifying a residual file needs the source raster (--source INPUT)");
    }
    DemVerifyOptions o;
    o.band = a.band - 1;
    o.stretch = a.stretch;
    o.threads = a.threads;
    o.target = a.target.resolve();
    o.progress = progressCallback(a.file, a.quiet, Progress::OffTerminal::Silent);
    const NodataChoice nodata = parseNodataChoice(a.nodata, "--nodata");
    o.nodata = nodata.value;
    o.ignoreDeclaredNodata = nodata.ignoreDeclared;
    const DemVerifyReport report = verifyDem(a.file, a.source, o);
    if (!a.report.empty()) {
        writeJson(toJson(report), a.report);
    }
    if (a.report != "-") {
        printDemLevels(report);
        std::printf("%s\n", report.ok() ? "ok: every sample within scale/2" : "FAILED: samples beyond scale/2 or not finite");
    }
    if (!report.ok()) {
        sayFailure(a.file + ": samples beyond scale/2 or not finite against " + a.source);
    }
    return report.ok() ? kExitOk : kExitFailure;
}

int verifyGl(const VerifyArgs& a) {
#ifdef PYRAMID_WITH_GL
    const GlVerifyReport report = verifyOnGl(a.file);
    if (!a.report.empty()) {
        writeJson(toJson(report), a.report);
    }
    if (a.report != "-") {
        std::printf("%s: CPU against GPU (%s)\n", a.file.c_str(), report.renderer.c_str());
        for (const GlVerifyPart& p : report.parts) {
            std::printf("  %-26s %7lld tiles %7lld differing  largest difference %g %s%s\n", p.what.c_str(),
                        static_cast<long long>(p.tiles), static_cast<long long>(p.differingTiles), p.maxDifference,
                        p.unit.c_str(), p.ok() ? "" : "  BEYOND TOLERANCE");
        }
        std::printf("%s\n", report.ok() ? "ok: CPU and GPU agree" : "FAILED: CPU and GPU differ");
    }
    if (!report.ok()) {
        sayFailure(a.file + ": the CPU and GPU producers differ");
    }
    return report.ok() ? kExitOk : kExitFailure;
#else
    fail(a.file, "--gl needs a build with the OpenGL producers (PYRAMID_WITH_GL)");
#endif
}

int verifyOrthoFile(const VerifyArgs& a) {
    if (a.source.empty()) {
        fail("--source", "verifying an ortho file needs the source image (--source INPUT)");
    }
    OrthoVerifyOptions o;
    o.stretch = a.stretch;
    o.threads = a.threads;
    o.colourResiduals = a.colourResiduals;
    o.target = a.target.resolve();
    o.progress = progressCallback(a.file, a.quiet, Progress::OffTerminal::Silent);
    o.colourSpace = parseColourSpace(a.colourSpace);
    const OrthoVerifyReport report = verifyOrtho(a.file, a.source, o);
    if (!a.report.empty()) {
        writeJson(toJson(report), a.report);
    }
    if (a.report != "-") {
        printOrthoLevels(report);
        std::printf("%s\n", report.ok ? "ok" : "FAILED: lossless tiles differ from the source");
    }
    if (!report.ok) {
        sayFailure(a.file + ": lossless tiles differ from " + a.source +
                   residualsHint(std::filesystem::path(a.file).parent_path(), a.colourResiduals));
    }
    return report.ok ? kExitOk : kExitFailure;
}

} // namespace

CommandRunner setupVerifyCommand(CLI::App& app) {
    auto args = std::make_shared<VerifyArgs>();
    app.add_option("FILE", args->file,
                   "Pyramid file or region set (its main file, index or directory) to verify, or a planet's directory "
                   "of DEM faces")
        ->required();
    auto* source = app.add_option("--source", args->source, "The raster the file was built from");
    app.add_flag("--gl", args->gl, "Produce every tile on the CPU and on the GPU (headless EGL) and compare them")
        ->excludes(source);
    addReportOption(app, args->report, "the report");
    auto* band = app.add_option("--band", args->band, "Band of the source holding the heights, from 1 (as preprocessDem)")
        ->capture_default_str();
    auto* nodata = app.add_option("--nodata", args->nodata, "Missing-height value of the source, as preprocessDem");
    app.add_flag("--stretch", args->stretch, "The source was stretched (preprocessDem --stretch)");
    addThreadsOption(app, args->threads);
    app.add_flag("-q,--quiet", args->quiet, "No progress on stderr");
    addProgressOption(app);
    addPlanarTargetOptions(app, args->target);
    app.add_flag("--colour-residuals", args->colourResiduals,
                 "Ortho files: FILE holds colour residuals (residuals/RGB.dat); compare the rebuilt colours");
    auto* colourSpace = app.add_option("--colour-space", args->colourSpace, "Ortho files: the averaging of preprocessOrtho (srgb or linear)")
        ->capture_default_str();
    app.add_option("--body", args->body, "A planet's directory: the body its faces were built on, as preprocessSphericalDem")
        ->capture_default_str();
    app.add_option("--name", args->name,
                   "A planet's directory: the base name of its faces, NAME1.dat .. NAME6.dat (default: DEM, else RGB)");
    app.add_option("--faces", args->faces, "A planet's directory: the faces to verify, e.g. 1,3 (default: every face it holds)");
    auto* heightScale = app.add_option("--height-scale", args->heightScale,
                   "A planet's directory: the --height-scale of preprocessSphericalDem (a number or a ratio A/B)")
        ->capture_default_str();
    return [args, band, nodata, heightScale, colourSpace]() {
        if (const std::optional<std::string> name = planetFaceName(*args)) {
            if (args->gl) {
                fail(args->file, "--gl compares a single pyramid file, not a planet's faces");
            }
            const GivenOptions given{band->count() > 0, nodata->count() > 0, heightScale->count() > 0,
                                     colourSpace->count() > 0};
            return verifySpherical(*args, *name, given);
        }
        // A file alone, or a region set (its main file, index or directory), verified whole.
        const bool set = !findRegionIndex(args->file).empty();
        if (args->gl) {
            if (set) {
                fail(args->file, "--gl compares a single pyramid file, not a region set");
            }
            return verifyGl(*args);
        }
        switch (set ? resolvePyramidSet(args->file).kind : detectPyramidKind(args->file)) {
        case PyramidKind::Residual:
            return verifyResidual(*args);
        case PyramidKind::Ortho:
            return verifyOrthoFile(*args);
        }
        return kExitFailure;
    };
}

} // namespace pyramid::cli
