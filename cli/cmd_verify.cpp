// `pyramid verify SET --source INPUT`: rebuild every level of a file or a region set (its main
// file, index or directory) and compare it with the source.
// `pyramid verify DIR --source MAP`: every face of a spherical DEM set against its map.
// `pyramid verify FILE --gl`: produce every tile on the CPU and on the GPU and compare them.
#include <cstdio>
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
    std::string name = "DEM";
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

// A directory holding a face of a spherical DEM set: NAMEi.dat, or its region set's index.
bool holdsSphericalFaces(const VerifyArgs& a) {
    std::error_code ec;
    if (!std::filesystem::is_directory(a.file, ec)) {
        return false;
    }
    for (int face = 1; face <= 6; ++face) {
        const std::filesystem::path file = std::filesystem::path(a.file) / (a.name + std::to_string(face) + ".dat");
        if (std::filesystem::exists(file, ec) || std::filesystem::exists(regionIndexPath(file.string()), ec)) {
            return true;
        }
    }
    return false;
}

// `pyramid verify DIR --source MAP`: every face of a spherical DEM set rebuilt and compared with
// the map sampled at the face's points, as preprocessSphericalDem sampled it.
int verifySpherical(const VerifyArgs& a) {
    if (a.source.empty()) {
        fail("--source", "verifying a planet's faces needs the map they were built from (--source MAP)");
    }
    if (!a.target.crs.empty()) {
        fail("--crs", "a planet's faces are not in a CRS: give the map as preprocessSphericalDem took it");
    }
    if (a.stretch || a.colourResiduals) {
        fail(a.stretch ? "--stretch" : "--colour-residuals", "does not apply to a planet's DEM faces");
    }
    std::string faces = a.faces;
    if (faces.empty()) {
        for (int face = 1; face <= 6; ++face) {
            const std::string file = (std::filesystem::path(a.file) / (a.name + std::to_string(face) + ".dat")).string();
            std::error_code ec;
            if (std::filesystem::exists(file, ec) || std::filesystem::exists(regionIndexPath(file), ec)) {
                faces += (faces.empty() ? "" : ",") + std::to_string(face);
            }
        }
    }
    const SphereChoice choice = resolveSphereOptions(SphereArgs{a.target.extent, a.body, faces});
    SphericalDemVerifyOptions o;
    o.body = choice.body;
    o.name = a.name;
    o.faces = choice.faces;
    o.extent = choice.extent;
    o.heightScale = parseRatio(a.heightScale, "--height-scale");
    o.threads = a.threads;
    o.band = a.band - 1;
    const NodataChoice nodata = parseNodataChoice(a.nodata, "--nodata");
    o.nodata = nodata.value;
    o.ignoreDeclaredNodata = nodata.ignoreDeclared;
    o.progress = progressCallback(a.file, a.quiet, Progress::OffTerminal::Silent);
    const std::vector<DemVerifyReport> reports = verifySphericalDem(a.file, expandInputs({a.source}).paths, o);
    bool ok = true;
    nlohmann::json faceReports = nlohmann::json::array();
    for (size_t k = 0; k < reports.size(); ++k) {
        ok = ok && reports[k].ok();
        nlohmann::json j = toJson(reports[k]);
        j["face"] = o.faces[k];
        faceReports.push_back(std::move(j));
    }
    if (!a.report.empty()) {
        writeJson({{"directory", a.file}, {"source", a.source}, {"faces", faceReports}, {"ok", ok}}, a.report);
    }
    if (a.report != "-") {
        for (const DemVerifyReport& r : reports) {
            printDemLevels(r);
        }
        std::printf("%s\n", ok ? "ok: every sample of every face within scale/2"
                               : "FAILED: samples beyond scale/2 or not finite");
    }
    if (!ok) {
        std::string failed;
        size_t count = 0;
        for (size_t k = 0; k < reports.size(); ++k) {
            if (!reports[k].ok()) {
                failed += (failed.empty() ? "" : ", ") + std::to_string(o.faces[k]);
                ++count;
            }
        }
        sayFailure(a.file + ": face" + (count == 1 ? " " : "s ") + failed + " (" + a.name +
                   "N.dat): samples beyond scale/2 or not finite against " + a.source);
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
    if (a.colourSpace == "linear" || a.colourSpace == "none") {
        o.colourSpace = ColourSpace::Linear;
    } else if (a.colourSpace != "srgb") {
        fail("--colour-space", "'" + a.colourSpace + "' is not srgb or linear");
    }
    const OrthoVerifyReport report = verifyOrtho(a.file, a.source, o);
    if (!a.report.empty()) {
        writeJson(toJson(report), a.report);
    }
    if (a.report != "-") {
        std::printf("%s against %s (%s)\n", a.file.c_str(), a.source.c_str(), report.mode.c_str());
        for (const OrthoVerifyLevel& l : report.levels) {
            std::printf("  level %2d: %6lld tiles  max error %3d  rms %-8.4g psnr %6.2f dB  %lld lossy tiles\n", l.level,
                        static_cast<long long>(l.tiles), l.maxError, l.rmsError, l.psnr,
                        static_cast<long long>(l.lossyTiles));
        }
        std::printf("%s\n", report.ok ? "ok" : "FAILED: lossless tiles differ from the source");
    }
    if (!report.ok) {
        // preprocessOrtho writes its colour residuals as DIR/residuals/RGB.dat, in the same file
        // format as plain tiles: compared as tiles, they differ everywhere.
        const bool inResiduals = std::filesystem::path(a.file).parent_path().filename() == "residuals";
        sayFailure(a.file + ": lossless tiles differ from " + a.source +
                   (inResiduals && !a.colourResiduals
                        ? " (its folder is residuals/: verify colour residuals with --colour-residuals)"
                        : ""));
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
    app.add_option("--band", args->band, "Band of the source holding the heights, from 1 (as preprocessDem)")
        ->capture_default_str();
    app.add_option("--nodata", args->nodata, "Missing-height value of the source, as preprocessDem");
    app.add_flag("--stretch", args->stretch, "The source was stretched (preprocessDem --stretch)");
    addThreadsOption(app, args->threads);
    app.add_flag("-q,--quiet", args->quiet, "No progress on stderr");
    addProgressOption(app);
    addPlanarTargetOptions(app, args->target);
    app.add_flag("--colour-residuals", args->colourResiduals,
                 "Ortho files: FILE holds colour residuals (residuals/RGB.dat); compare the rebuilt colours");
    app.add_option("--colour-space", args->colourSpace, "Ortho files: the averaging of preprocessOrtho (srgb or linear)")
        ->capture_default_str();
    app.add_option("--body", args->body, "A planet's directory: the body its faces were built on, as preprocessSphericalDem")
        ->capture_default_str();
    app.add_option("--name", args->name, "A planet's directory: the base name of its faces (NAME1.dat .. NAME6.dat)")
        ->capture_default_str();
    app.add_option("--faces", args->faces, "A planet's directory: the faces to verify, e.g. 1,3 (default: every face it holds)");
    app.add_option("--height-scale", args->heightScale,
                   "A planet's directory: the --height-scale of preprocessSphericalDem (a number or a ratio A/B)")
        ->capture_default_str();
    return [args]() {
        if (holdsSphericalFaces(*args)) {
            if (args->gl) {
                fail(args->file, "--gl compares a single pyramid file, not a planet's faces");
            }
            return verifySpherical(*args);
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
