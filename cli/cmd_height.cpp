// `pyramid height SET|DIR (--grid X,Y | --pixel X,Y --source INPUT | --xy X,Y | --lonlat LON,LAT)`: the
// reconstructed height at one point, through the runtime's own producer: a pipeline's check
// that a build landed where it should.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/error.hpp"
#include "formats/georeference_sidecar.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/dem/dem_sampling.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/runtime/height_query.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/face_locate.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid::cli {

namespace {

struct HeightArgs {
    std::string target; // a residual file or region set, or a directory of NAME1..6.dat
    std::string grid, pixel, lonlat, xy;
    std::string source;
    bool stretch = false;
    std::string body = "wgs84";
    std::string name = "DEM";
    std::string report; // --report FILE|- (or --json)
};

std::pair<double, double> parsePair(const std::string& text, const std::string& option) {
    const size_t comma = text.find(',');
    if (comma == std::string::npos) {
        fail(option, "'" + text + "' is not two numbers A,B");
    }
    return {parseNumber(text.substr(0, comma), option), parseNumber(text.substr(comma + 1), option)};
}

int64_t finestIntervals(const ResidualHeader& h) {
    return static_cast<int64_t>(h.tileSize >> h.minLevel) << h.maxLevel;
}

// A directory names a planar region set (its one index) unless it holds a spherical set's faces.
bool isPlanarSetDirectory(const HeightArgs& a) {
    if (!std::filesystem::is_directory(a.target)) {
        return false;
    }
    if (a.lonlat.empty()) {
        return true;
    }
    if (std::filesystem::exists(faceFilePath(a.target, a.name, 1))) {
        return false;
    }
    try {
        return !findRegionIndex(a.target).empty();
    } catch (const Error&) {
        return false;
    }
}

// A file built from a georeferenced input has its sidecar: the source's own georeferencing must
// put the pixel (a DEM sample at its pixel's centre) where the geometry put it, (u, v), within a
// hundredth of a finest interval. Otherwise the source is not the raster the file was built from
// alone (another raster, one tile of a mosaic, a build with --crs or --extent) or the build's
// --stretch was not the one given: refused, as a height from the wrong place would be wrong.
void checkPixelPlacement(const std::string& main, const HeightArgs& a, const RasterInfo& info, double px, double py,
                         double u, double v, double intervals) {
    if (!info.georeference || !info.georeference->axisAligned() ||
        !std::filesystem::exists(georeferenceSidecarPath(main))) {
        return;
    }
    const auto& t = info.georeference->pixelToCrs;
    const double cx = px + 0.5, cy = py + 0.5;
    const double x = t[0] + t[1] * cx + t[2] * cy, y = t[3] + t[4] * cx + t[5] * cy;
    const std::array<double, 2> placed = crsToRootQuad(main, x, y, false);
    const double tolerance = std::max(0.01 / intervals, 1e-12);
    if (!(std::abs(placed[0] - u) <= tolerance && std::abs(placed[1] - v) <= tolerance)) {
        fail("--source", a.source + "'s georeferencing puts pixel " + a.pixel + " at (" + numberText(placed[0]) +
                             ", " + numberText(placed[1]) + ") of " + main + "'s root quad, the build's geometry" +
                             (a.stretch ? " with" : " without") + " --stretch at (" + numberText(u) + ", " +
                             numberText(v) + "): not the raster the file was built from alone (give the point with "
                             "--xy or --lonlat)");
    }
}

int runHeight(const HeightArgs& a) {
    std::string file = a.target;
    double u = 0.0, v = 0.0;
    int face = 0;
    const bool planarSet = isPlanarSetDirectory(a) || (std::filesystem::is_regular_file(a.target) &&
                                                       !findRegionIndex(a.target).empty());
    const bool planar = std::filesystem::is_regular_file(a.target) || planarSet;
    // The main file of a set: the one its sidecar and header belong to.
    const std::string main = planarSet ? openPyramidSet(a.target).main : a.target;
    if (!a.xy.empty() || (!a.lonlat.empty() && planar)) {
        // A planar file of a georeferenced input: placed by its sidecar.
        const bool lonlat = a.xy.empty();
        const auto [x, y] = parsePair(lonlat ? a.lonlat : a.xy, lonlat ? "--lonlat" : "--xy");
        const std::array<double, 2> uv = crsToRootQuad(main, x, y, lonlat);
        u = uv[0];
        v = uv[1];
    } else if (!a.lonlat.empty()) {
        const auto [lon, lat] = parsePair(a.lonlat, "--lonlat");
        if (!(lat >= -90.0 && lat <= 90.0)) {
            fail("--lonlat", "latitude " + std::to_string(lat) + " is outside -90..90");
        }
        const PlanetBody body = PlanetBody::parse(a.body);
        const FacePoint p = facePointOf(directionOf(body, GeodeticPoint{lat, lon}));
        face = p.face;
        file = faceFilePath(a.target, a.name, face);
        u = (p.u + 1.0) / 2.0;
        v = (p.v + 1.0) / 2.0;
    } else {
        ResidualHeader h = ResidualFileReader::open(main)->header();
        if (planarSet) {
            h.maxLevel = setMaxLevel(openPyramidSet(a.target)); // the set's finest level
        }
        const auto N = static_cast<double>(finestIntervals(h));
        if (!a.grid.empty()) {
            const auto [x, y] = parsePair(a.grid, "--grid");
            u = x / N;
            v = y / N;
        } else {
            if (a.source.empty()) {
                fail("--pixel", "needs the source raster the file was built from (--source INPUT)");
            }
            const auto [px, py] = parsePair(a.pixel, "--pixel");
            // Opened as the encoder opens one input: north-up, whichever way its rows run.
            const RasterInfo info = openPlanarMosaic({a.source}, 16, false, PlanarTarget{})->info();
            if (!(px >= 0.0 && px <= info.width - 1 && py >= 0.0 && py <= info.height - 1)) {
                fail("--pixel", a.pixel + " is outside " + a.source + "'s " + std::to_string(info.width) + " x " +
                                    std::to_string(info.height) + " samples (columns 0.." +
                                    std::to_string(info.width - 1) + ", rows 0.." + std::to_string(info.height - 1) +
                                    ")");
            }
            // The encoder's own geometry (doc/dem-encoding.md, "Sampling"): X = x Lx / N,
            // Y = (N - y) Ly / N.
            const DemGeometry g = makeDemGeometry(info.width, info.height, finestIntervals(h), a.stretch, a.source);
            u = px / static_cast<double>(g.lx);
            v = 1.0 - py / static_cast<double>(g.ly);
            checkPixelPlacement(main, a, info, px, py, u, v, static_cast<double>(finestIntervals(h)));
        }
    }
    const PointHeight p = setHeightAt(file, u, v); // a file alone, or the set it or its index names
    if (!a.report.empty()) {
        nlohmann::json j = {{"file", file}, {"height", p.height}, {"level", p.level}, {"tile", {p.tx, p.ty}},
                            {"u", u}, {"v", v}};
        if (face) {
            j["face"] = face;
        }
        writeJson(j, a.report);
    }
    if (a.report != "-") {
        std::printf("%.9g\n", p.height);
        std::fprintf(stderr, "%s: level %d, tile (%d, %d), at %.6g, %.6g of the root quad\n", file.c_str(), p.level,
                     p.tx, p.ty, u, v);
    }
    return kExitOk;
}

} // namespace

CommandRunner setupHeightCommand(CLI::App& app) {
    auto a = std::make_shared<HeightArgs>();
    app.add_option("TARGET", a->target,
                   "A residual (DEM) file or region set (its main file, index or directory), or with --lonlat the "
                   "directory of a spherical set")
        ->required();
    auto* grid = app.add_option("--grid", a->grid,
                                "X,Y in the finest level's sample intervals, from the south-west corner of the root quad");
    auto* pixel = app.add_option("--pixel", a->pixel,
                                 "X,Y in pixels of the source raster (column from the west, row from the north)");
    auto* lonlat = app.add_option("--lonlat", a->lonlat,
                                  "LON,LAT in degrees: on a spherical set (geodetic on --body), or on a planar file of "
                                  "an input in a geographic CRS");
    auto* xy = app.add_option("--xy", a->xy, "X,Y in the CRS units of the georeferenced input a planar file was built from");
    grid->excludes(pixel)->excludes(lonlat)->excludes(xy);
    pixel->excludes(lonlat)->excludes(xy);
    lonlat->excludes(xy);
    app.add_option("--source", a->source, "With --pixel: the raster the file was built from")->needs(pixel);
    app.add_flag("--stretch", a->stretch, "With --pixel: the file was built with --stretch")->needs(pixel);
    app.add_option("--body", a->body, "With --lonlat: the body the set was built on")->capture_default_str()->needs(lonlat);
    app.add_option("--name", a->name, "With --lonlat: the set's file name before the face number")
        ->capture_default_str()
        ->needs(lonlat);
    addReportOption(app, a->report, "the height, its tile and place");
    app.parse_complete_callback([grid, pixel, lonlat, xy] {
        if (!*grid && !*pixel && !*lonlat && !*xy) {
            throw CLI::RequiredError("the point (--grid X,Y, --pixel X,Y --source INPUT, --xy X,Y or --lonlat LON,LAT)");
        }
    });
    return [a]() { return runHeight(*a); };
}

} // namespace pyramid::cli
