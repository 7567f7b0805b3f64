// `pyramid preview`: one level of a pyramid file or region set drawn as a PNG, tile row by
// tile row from the north, so that memory holds one row of tiles' pixels whatever the image's
// size (doc/cli/pyramid-preview.md); or the six cube faces of a planet (a directory of
// NAME1.dat .. NAME6.dat, as the spherical preprocessors write them) as an equirectangular
// world map or an unfolded cube cross:
//  * elevation residual pyramids: a hillshade over hypsometric colours of the reconstructed
//    heights (the runtime's elevation producer), or the heights alone, or the stored residuals
//    (times the scale) on a diverging ramp, to show where the error budget goes;
//  * ortho pyramids: the level's tiles as a mosaic (their borders cut), colour residual files
//    (a file in a residuals/ directory) through the colour producer.
// The level's samples are the image's pixels: a DEM level of n-interval tiles gives
// tiles x n + 1 vertices a side, an ortho level tiles x tileSize pixels.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pyramid {

// Hillshade: shaded hypsometric colours; Shade: the hillshade alone, grey; Heights: the colours alone.
enum class PreviewStyle { Auto, Hillshade, Shade, Heights, Residuals, Colours };

// Face: one pyramid (a plane, or one cube face) as its level's samples. Equirectangular: a
// planet's faces resampled onto longitude and latitude (4 face sides wide, 2 high). Cube: the six
// faces unfolded into a cross, 4 x 3 face sides, each face as its samples:
//        [1]
//        [2][3][4][5]
//        [6]
// (the poles above and below face 2 at 90 W, every face upright as its own preview draws it, so
// that each edge of the cross joins two faces that meet on the planet). Auto: Equirectangular
// for a directory of six faces, Face otherwise.
enum class PreviewProjection { Auto, Face, Equirectangular, Cube };

struct PreviewOptions {
    std::optional<int> level; // none: the deepest level at most `size` samples a side (level 0 at least)
    int size = 1024;
    PreviewStyle style = PreviewStyle::Auto; // Auto: Hillshade for elevations, Colours for orthos
    // Ground distance between the level's samples, in height units (hillshade): 0 takes it from
    // the pyramid's georeference sidecar (FILE.georef.json: metres, geographic degrees converted
    // at the extent's middle latitude), else 1.
    double spacing = 0.0;
    double zFactor = 1.0;    // heights are multiplied by it for the hillshade
    double azimuth = 315.0;  // the sun, degrees clockwise from north
    double altitude = 45.0;  // degrees above the horizon
    PreviewProjection projection = PreviewProjection::Auto;
    std::string body = "wgs84";      // planets: as encoded (PlanetBody::parse)
    bool legend = false;             // elevation styles: a colour bar with its range below the image
    std::optional<double> seaLevel;  // elevation styles: heights at or below it drawn as water
};

struct PreviewReport {
    std::string input, output, kind, style;
    int level = 0, width = 0, height = 0;
    double minimum = 0.0, maximum = 0.0; // heights, residuals (x scale) or (colours) 0..255
    double spacing = 0.0;                // hillshade only (planets: 0, the body gives it)
    std::string projection = "face";     // face, equirectangular or cube
    std::vector<std::string> faces;      // planets: the six face files (or sets), 1 to 6
    std::string body;                    // planets: PlanetBody::describe()
    int legendHeight = 0;                // rows of legend below the image (0: none)
};

// Throws Error naming the file (or OptionError naming the option) and writes nothing on error.
PreviewReport writePreview(const std::string& input, const std::string& png, const PreviewOptions& options);

// One DEM tile's heights (`side` x `side` floats, row 0 the south, as ElevationTile::zf with its
// borders) drawn as an RGB PNG, north up, in an elevation style (options.style: auto is the
// hillshade; the sun, spacing, z factor, sea level and legend apply). Slopes are central
// differences, one-sided at the tile's edges. A spacing of 0 is taken from the sidecar of `file`
// (FILE.georef.json) at `level`, else 1. Throws as writePreview.
PreviewReport writeTilePreview(const std::vector<float>& heights, int side, const std::string& file, int level,
                               const std::string& png, const PreviewOptions& options);

PreviewStyle parsePreviewStyle(const std::string& text); // throws OptionError("style", ...)
std::string previewStyleName(PreviewStyle style);
// "auto", "face", "equirectangular" (or "world"), "cube"; throws OptionError("projection", ...).
PreviewProjection parsePreviewProjection(const std::string& text);
std::string previewProjectionName(PreviewProjection projection);
nlohmann::json toJson(const PreviewReport& report);

} // namespace pyramid
