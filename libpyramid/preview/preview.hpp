// `pyramid preview`: one level of a pyramid file or region set drawn as a PNG, tile row by
// tile row from the north, so that memory holds one row of tiles' pixels whatever the image's
// size (doc/cli/pyramid-preview.md):
//  * elevation residual pyramids: a hillshade over hypsometric colours of the reconstructed
//    heights (the runtime's elevation producer), or the heights alone, or the stored residuals
//    (times the scale) on a diverging ramp, to show where the error budget goes;
//  * ortho pyramids: the level's tiles as a mosaic (their borders cut), colour residual files
//    (a file in a residuals/ directory) through the colour producer.
// The level's samples are the image's pixels: a DEM level of n-interval tiles gives
// tiles x n + 1 vertices a side, an ortho level tiles x tileSize pixels.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace pyramid {

// Hillshade: shaded hypsometric colours; Shade: the hillshade alone, grey; Heights: the colours alone.
enum class PreviewStyle { Auto, Hillshade, Shade, Heights, Residuals, Colours };

struct PreviewOptions {
    int level = -1;  // -1: the deepest level at most `size` samples a side (level 0 at least)
    int size = 1024;
    PreviewStyle style = PreviewStyle::Auto; // Auto: Hillshade for elevations, Colours for orthos
    // Ground distance between the level's samples, in height units (hillshade): 0 takes it from
    // the pyramid's georeference sidecar (FILE.georef.json: metres, geographic degrees converted
    // at the extent's middle latitude), else 1.
    double spacing = 0.0;
    double zFactor = 1.0;    // heights are multiplied by it for the hillshade
    double azimuth = 315.0;  // the sun, degrees clockwise from north
    double altitude = 45.0;  // degrees above the horizon
};

struct PreviewReport {
    std::string input, output, kind, style;
    int level = 0, width = 0, height = 0;
    double minimum = 0.0, maximum = 0.0; // heights, residuals (x scale) or (colours) 0..255
    double spacing = 0.0;                // hillshade only
};

// Throws Error naming the file (or OptionError naming the option) and writes nothing on error.
PreviewReport writePreview(const std::string& input, const std::string& png, const PreviewOptions& options);

PreviewStyle parsePreviewStyle(const std::string& text); // throws OptionError("style", ...)
std::string previewStyleName(PreviewStyle style);
nlohmann::json toJson(const PreviewReport& report);

} // namespace pyramid
