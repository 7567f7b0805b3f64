// Ambient aperture (doc/shading.md, "Ambient aperture"; Oat and Sander, "Ambient Aperture
// Lighting", I3D 2007): at every pixel of a terrain, the solid angle of sky above the local
// horizontal plane that the terrain around does not hide, and the principal (mean) direction of
// that visible sky, found by a horizon search over the reconstructed heights of several levels
// of a residual pyramid (the runtime's elevation producer). preprocessAperture writes them as an
// ortho pyramid (3 channels) that the ortho producers read.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"

namespace pyramid {

struct ApertureSearch {
    int directions = 16; // azimuths, evenly spaced from east, counter-clockwise
    int radius = 16;     // steps per level along each azimuth
    // Levels searched: the finest (steps 1..radius samples away), then each coarser one on its own
    // samples, twice as far apart (steps radius/2 + 1 .. radius of it): the reach doubles a level.
    int levels = 3;
    // Throws OptionError("directions" | "radius" | "levels") for values out of 4..256, 2..1024
    // (even), 1..16.
    void validate() const;
};

// The visible sky at one point: `visible` its solid angle over the hemisphere's (2 pi), 0..1;
// `direction` its mean direction (unit; x east, y north, z up).
struct Aperture {
    double visible = 1.0;
    std::array<double, 3> direction{0.0, 0.0, 1.0};
};

// The aperture from the horizon angles (radians above the horizontal, >= 0) of `count` equal
// sectors of azimuth, sector k centred on azimuth 2 pi k / count from east: each sector sees the
// sky above its horizon, a solid angle of (2 pi / count)(1 - sin h); its mean direction is the
// integral of the direction over it, (cos^2 over elevation: (pi/2 - h)/2 - sin(2h)/4 for the
// horizontal part, cos^2(h)/2 for the vertical), summed over the sectors and normalised.
Aperture apertureOfHorizons(const double* horizons, int count);

// The three channels of an aperture pixel: visible x 255, and the direction's x and y as
// 128 + 127 v (1..255, 0 exactly 128: v = (byte - 128) / 127), each rounded to the nearest.
std::array<uint8_t, 3> encodeAperture(const Aperture& a);

struct ApertureEncodeOptions {
    ApertureSearch search;
    // The root quad's side on the ground, in height units (positive and finite); none: from the
    // DEM's georeference sidecar (metres), else an error.
    std::optional<double> size;
    int threads = 0;
    int deflateLevel = 6;
    std::function<void(int64_t, int64_t)> progress; // (tiles done, total)
};

// What both aperture reports give.
struct ApertureRun {
    std::string input;
    int tileSize = 0, maxLevel = 0;
    double spacing = 0.0; // the finest level's sample spacing (a planet's: its mean, on the ground)
    ApertureSearch search;
    int64_t tiles = 0;
    uint64_t bytes = 0;
    double seconds = 0.0;
};

struct ApertureReport : ApertureRun {
    std::string output;
    double size = 0.0; // the root quad's side
};

// preprocessAperture: the aperture pyramid of the residual pyramid (file or region set) `dem`,
// into `output` (NAME.dat): ortho tiles of the DEM's tile size, one level per DEM level from
// its minLevel on (ortho level L covers DEM tile level minLevel + L), 3 channels, Deflate TIFF.
// The finest level's pixels are searched; coarser levels are their linear averages. Throws Error
// or OptionError and leaves nothing behind.
ApertureReport encodeApertureFile(const std::string& dem, const std::string& output, const ApertureEncodeOptions& options);

// The fields both reports give, the search as "directions", "radius_steps"
// (ApertureSearch::radius) and "levels".
nlohmann::json toJson(const ApertureRun& run);
nlohmann::json toJson(const ApertureReport& report);

struct SphericalApertureOptions {
    ApertureSearch search;
    std::string name = "DEM";       // the faces read: DIR/NAME1.dat .. NAME6.dat (files or region sets)
    std::string output = "APERTURE"; // the faces written: OUT/OUTPUT1.dat .. OUTPUT6.dat
    std::string body = "wgs84";     // as the faces were built (PlanetBody::parse)
    // The sphere the heights stand on, as the renderer deforms the faces (doc/shading.md,
    // "Geometry"); 0: the body's equatorial radius.
    double radius = 0.0;
    int threads = 0;
    int deflateLevel = 6;
    std::function<void(int64_t, int64_t)> progress; // (tiles done, total), all faces together
};

struct SphericalApertureReport : ApertureRun {
    std::string directory;
    std::vector<std::string> outputs;
    double radius = 0.0; // the sphere's the search runs on
};

// preprocessSphericalAperture: the aperture of the six cube faces of a planet (DIR/NAME1..6.dat,
// as preprocessSphericalDem writes them) as six ortho pyramids OUT/OUTPUT1..6.dat of the faces'
// tile size and levels (from their minLevel on). Each face pixel's point is searched on the
// sphere: along great circles from it, crossing faces as the ground does, so that the faces
// join without seams (their tile borders are their neighbours' pixels). The mean direction is
// stored in the point's own east and north. Throws Error or OptionError and leaves nothing
// behind.
SphericalApertureReport encodeSphericalApertureFiles(const std::string& directory, const std::string& output,
                                                     const SphericalApertureOptions& options);

nlohmann::json toJson(const SphericalApertureReport& report);

} // namespace pyramid
