#include "libpyramid/preview/preview.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/input/pyramid_georeference.hpp"
#include "libpyramid/preview/planet_preview.hpp"
#include "libpyramid/preview/png_writer.hpp"
#include "libpyramid/preview/preview_levels.hpp"
#include "libpyramid/preview/shading.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

PreviewStyle parsePreviewStyle(const std::string& text) {
    if (text == "auto") {
        return PreviewStyle::Auto;
    }
    if (text == "hillshade") {
        return PreviewStyle::Hillshade;
    }
    if (text == "shade") {
        return PreviewStyle::Shade;
    }
    if (text == "heights") {
        return PreviewStyle::Heights;
    }
    if (text == "residuals") {
        return PreviewStyle::Residuals;
    }
    if (text == "colours" || text == "colors") {
        return PreviewStyle::Colours;
    }
    failOption("style", "'" + text + "' is not auto, hillshade, shade, heights, residuals or colours");
}

std::string previewStyleName(PreviewStyle style) {
    switch (style) {
    case PreviewStyle::Auto:
        return "auto";
    case PreviewStyle::Hillshade:
        return "hillshade";
    case PreviewStyle::Shade:
        return "shade";
    case PreviewStyle::Heights:
        return "heights";
    case PreviewStyle::Residuals:
        return "residuals";
    case PreviewStyle::Colours:
        return "colours";
    }
    return "auto";
}

PreviewProjection parsePreviewProjection(const std::string& text) {
    if (text == "auto") {
        return PreviewProjection::Auto;
    }
    if (text == "face") {
        return PreviewProjection::Face;
    }
    if (text == "equirectangular" || text == "world") {
        return PreviewProjection::Equirectangular;
    }
    if (text == "cube") {
        return PreviewProjection::Cube;
    }
    failOption("projection", "'" + text + "' is not auto, face, equirectangular (world) or cube");
}

std::string previewProjectionName(PreviewProjection projection) {
    switch (projection) {
    case PreviewProjection::Auto:
        return "auto";
    case PreviewProjection::Face:
        return "face";
    case PreviewProjection::Equirectangular:
        return "equirectangular";
    case PreviewProjection::Cube:
        return "cube";
    }
    return "auto";
}

nlohmann::json toJson(const PreviewReport& r) {
    nlohmann::json j = {{"input", r.input},     {"output", r.output},   {"kind", r.kind},
                        {"style", r.style},     {"level", r.level},     {"width", r.width},
                        {"height", r.height},   {"minimum", r.minimum}, {"maximum", r.maximum},
                        {"spacing", r.spacing}, {"projection", r.projection}, {"legend_height", r.legendHeight}};
    if (!r.faces.empty()) {
        j["faces"] = r.faces;
        j["body"] = r.body;
    }
    return j;
}

namespace {

using namespace preview;

PreviewReport elevationPreview(const PyramidSet& set, const std::string& output, const PreviewOptions& o) {
    const ResidualHeader h = ResidualFileReader::readHeader(set.main);
    const int level = chooseLevel(o, setMaxLevel(set), o.size, [&](int l) { return elevationLevelSide(h, l); },
                                  set.name());
    const PreviewStyle style = elevationStyle(o, set.name());
    ElevationGrid grid(set, level, style == PreviewStyle::Residuals, 8);
    PreviewReport report;
    report.kind = "elevation";
    report.style = previewStyleName(style);
    report.level = level;
    report.width = report.height = static_cast<int>(grid.side());
    std::tie(report.minimum, report.maximum) = grid.range();
    const ElevationPaint paint(style, report.minimum, report.maximum, o);
    std::array<double, 2> spacing{o.spacing, o.spacing};
    if (paint.shading() && o.spacing <= 0.0) {
        spacing = groundSpacing(set.main, level);
        if (spacing[0] <= 0.0 || spacing[1] <= 0.0) {
            spacing = {1.0, 1.0};
        }
    }
    report.spacing = paint.shading() ? spacing[0] : 0.0;
    const LevelImage image = elevationImage(grid, paint, [spacing](int, int, int, int) { return spacing; });
    const auto legend = o.legend ? legendRows(image.side, paint) : std::vector<std::vector<uint8_t>>{};
    report.legendHeight = static_cast<int>(legend.size());
    report.height += report.legendHeight;
    PngWriter png(output, report.width, report.height, 3, 8, previewText(set.main, report));
    writeImage(png, image);
    for (const auto& row : legend) {
        png.writeRow(row.data());
    }
    png.commit();
    return report;
}

PreviewReport orthoPreview(const PyramidSet& set, const std::string& output, const PreviewOptions& o) {
    checkColourStyle(o, set.name());
    auto producer = openOrthoSet(set);
    const OrthoHeader h = producer->header();
    const int level =
        chooseLevel(o, producer->maxLevel(), o.size, [&](int l) { return orthoLevelSide(h, l); }, set.name());
    ColourGrid grid(set, std::move(producer), level, size_t{1} << level);
    PreviewReport report;
    report.kind = grid.residuals() ? "colour residuals" : "ortho";
    report.style = "colours";
    report.level = level;
    report.width = report.height = static_cast<int>(grid.side());
    report.maximum = 255.0;
    const LevelImage image = colourImage(grid);
    PngWriter png(output, report.width, report.height, image.channels, 8, previewText(set.main, report));
    writeImage(png, image);
    png.commit();
    return report;
}

// The options every preview checks.
void checkOptions(const PreviewOptions& o) {
    if (o.size < 1) {
        failOption("size", std::to_string(o.size) + " is not a positive number of pixels");
    }
    if (o.level && *o.level < 0) {
        failOption("level", std::to_string(*o.level) + " is not a level");
    }
    if (!(o.spacing >= 0.0) || !std::isfinite(o.spacing)) {
        failOption("spacing", "must be a positive distance");
    }
    if (!std::isfinite(o.zFactor) || !std::isfinite(o.azimuth) || !(o.altitude > 0.0 && o.altitude <= 90.0)) {
        failOption("altitude", "the sun must be 0 to 90 degrees above the horizon, the z factor and azimuth finite");
    }
    if (o.seaLevel && !std::isfinite(*o.seaLevel)) {
        failOption("sea-level", "must be a finite height");
    }
}

} // namespace

PreviewReport writeTilePreview(const std::vector<float>& heights, int side, const std::string& file, int level,
                               const std::string& output, const PreviewOptions& o) {
    checkOptions(o);
    const PreviewStyle style = elevationStyle(o, file);
    if (style == PreviewStyle::Residuals) {
        failOption("style", "a tile's residuals are drawn by pyramid tile --residual");
    }
    PreviewReport report;
    report.kind = "elevation";
    report.style = previewStyleName(style);
    report.level = level;
    report.width = side;
    report.minimum = std::numeric_limits<double>::infinity();
    report.maximum = -report.minimum;
    for (const float v : heights) {
        if (std::isfinite(v)) {
            report.minimum = std::min(report.minimum, static_cast<double>(v));
            report.maximum = std::max(report.maximum, static_cast<double>(v));
        }
    }
    if (!(report.minimum <= report.maximum)) {
        report.minimum = report.maximum = 0.0;
    }
    const ElevationPaint paint(style, report.minimum, report.maximum, o);
    std::array<double, 2> spacing{o.spacing, o.spacing};
    if (paint.shading() && o.spacing <= 0.0) {
        spacing = groundSpacing(file, level);
        if (spacing[0] <= 0.0 || spacing[1] <= 0.0) {
            spacing = {1.0, 1.0};
        }
    }
    report.spacing = paint.shading() ? spacing[0] : 0.0;
    const auto legend = o.legend ? legendRows(side, paint) : std::vector<std::vector<uint8_t>>{};
    report.legendHeight = static_cast<int>(legend.size());
    report.height = side + report.legendHeight;
    PngWriter png(output, report.width, report.height, 3, 8, previewText(file, report));
    const auto at = [&](int i, int j) {
        return static_cast<double>(heights[static_cast<size_t>(std::clamp(j, 0, side - 1)) * static_cast<size_t>(side) +
                                           static_cast<size_t>(std::clamp(i, 0, side - 1))]);
    };
    std::vector<uint8_t> row(static_cast<size_t>(side) * 3);
    for (int j = side - 1; j >= 0; --j) {
        for (int i = 0; i < side; ++i) {
            // Central differences inside, one-sided at the edges (over one sample, not two).
            const double wide = (i > 0) + (i + 1 < side), tall = (j > 0) + (j + 1 < side);
            const double dzdx = wide > 0 ? (at(i + 1, j) - at(i - 1, j)) / (wide * spacing[0]) : 0.0;
            const double dzdy = tall > 0 ? (at(i, j + 1) - at(i, j - 1)) / (tall * spacing[1]) : 0.0;
            const Rgb8 c = paint.colour(at(i, j), dzdx, dzdy);
            std::copy(c.begin(), c.end(), row.begin() + static_cast<std::ptrdiff_t>(i) * 3);
        }
        png.writeRow(row.data());
    }
    for (const auto& r : legend) {
        png.writeRow(r.data());
    }
    png.commit();
    report.input = file;
    report.output = output;
    return report;
}

PreviewReport writePreview(const std::string& input, const std::string& output, const PreviewOptions& o) {
    checkOptions(o);
    PreviewProjection projection = o.projection;
    std::optional<PlanetFaces> planet;
    std::error_code ec;
    if (projection == PreviewProjection::Auto && std::filesystem::is_directory(input, ec)) {
        planet = planetFacesIn(input);
        projection = planet ? PreviewProjection::Equirectangular : PreviewProjection::Face;
    } else if (projection == PreviewProjection::Equirectangular || projection == PreviewProjection::Cube) {
        planet = planetFacesOf(input);
    }
    PreviewReport report;
    if (planet) {
        report = planetPreview(*planet, output, o, projection);
    } else {
        const PyramidSet set = openPyramidSet(input);
        report = set.kind == PyramidKind::Residual ? elevationPreview(set, output, o) : orthoPreview(set, output, o);
    }
    report.input = input;
    report.output = output;
    return report;
}

} // namespace pyramid
