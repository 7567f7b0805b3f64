// `pyramid verify RGB.dat --source INPUT` for ortho files: the true levels rebuilt from the
// source (libpyramid/encode/ortho/ortho_levels.hpp, the preprocessor's own code) and compared with the
// file's tiles: decoded TIFF or DXT tiles, or, with colourResiduals, the tiles the
// colour-residual producer rebuilds.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/filters/colour_average.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"

namespace pyramid {

struct OrthoVerifyOptions {
    ColourSpace colourSpace = ColourSpace::Srgb;
    bool stretch = false;
    bool colourResiduals = false; // the file holds colour residuals (residuals/RGB.dat)
    int threads = 0;
    PlanarTarget target; // as the pyramid was built (--crs, --extent)
    // (tiles compared, tiles in all), the latter the same on every call; one thread at a time.
    std::function<void(int64_t, int64_t)> progress;
};

struct OrthoVerifyLevel {
    int level = 0;
    int64_t tiles = 0;
    int maxError = 0;
    double rmsError = 0.0;
    double psnr = 99.0;
    int64_t lossyTiles = 0; // JPEG or DXT tiles, whose error is expected
};

struct OrthoVerifyReport {
    std::string file, source, mode; // mode: "tiles", "dxt" or "colour-residuals"
    std::vector<OrthoVerifyLevel> levels;
    bool ok = true; // lossless tiles equal the source; colour residuals within 1
};

OrthoVerifyReport verifyOrtho(const std::string& file, const std::string& source, const OrthoVerifyOptions& options);

// The cube faces preprocessSphericalOrtho wrote into a directory (NAME1.dat .. NAME6.dat, each a
// file or a region set), against the map they were built from: one file or a mosaic, opened as
// preprocessSphericalOrtho opens it, each face's true tiles rebuilt by its own code on `body`.
struct SphericalOrthoVerifyOptions {
    std::string body = "wgs84";              // as encoded (PlanetBody::parse)
    std::string name = "RGB";                // files NAME1.dat .. NAME6.dat
    std::vector<int> faces{1, 2, 3, 4, 5, 6};
    std::optional<GeoExtent> extent;         // places a map without georeferencing
    ColourSpace colourSpace = ColourSpace::Srgb;
    bool colourResiduals = false;            // the faces hold colour residuals (residuals/)
    int threads = 0;
    // (tiles compared, tiles of all the faces); one thread at a time.
    std::function<void(int64_t, int64_t)> progress;
};
// One report per face, in the order of options.faces.
std::vector<OrthoVerifyReport> verifySphericalOrtho(const std::string& directory, const std::vector<std::string>& inputs,
                                                    const SphericalOrthoVerifyOptions& options);

nlohmann::json toJson(const OrthoVerifyReport& report);

} // namespace pyramid
