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
#include "libpyramid/preview/png_writer.hpp"
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

nlohmann::json toJson(const PreviewReport& r) {
    return {{"input", r.input},   {"output", r.output}, {"kind", r.kind},       {"style", r.style},
            {"level", r.level},   {"width", r.width},   {"height", r.height},   {"minimum", r.minimum},
            {"maximum", r.maximum}, {"spacing", r.spacing}};
}

namespace {

// The level drawn: the one asked for, or the deepest whose side (samples(l)) fits in `size`.
int chooseLevel(const PreviewOptions& o, int deepest, const std::function<int64_t(int)>& samples, const std::string& name) {
    if (o.level >= 0) {
        if (o.level > deepest) {
            failOption("level", std::to_string(o.level) + " is not a level of " + name + " (0 to " +
                                    std::to_string(deepest) + ")");
        }
        return o.level;
    }
    int level = 0;
    while (level < deepest && samples(level + 1) <= o.size) {
        ++level;
    }
    return level;
}

// Ground distance between the samples of `level` along x and y, from the georeference sidecar
// beside `main`, converted to metres; {0, 0} without one.
std::array<double, 2> sidecarSpacing(const std::string& main, int level) {
    std::ifstream in(main + ".georef.json");
    if (!in) {
        return {0.0, 0.0};
    }
    try {
        const nlohmann::json g = nlohmann::json::parse(in);
        for (const auto& entry : g.at("units_per_sample")) {
            if (entry.at("level").get<int>() != level) {
                continue;
            }
            double x = entry.at("x").get<double>(), y = entry.at("y").get<double>();
            const auto& crs = g.at("crs");
            if (crs.at("kind") == "geographic") {
                const double a = crs.at("semi_major_axis_metres").get<double>();
                const double degree = a * std::numbers::pi / 180.0 * crs.value("unit_degrees", 1.0);
                const auto& root = g.at("root_extent");
                const double middle = (root.at("min_y").get<double>() + root.at("max_y").get<double>()) / 2.0;
                x *= degree * std::cos(middle * std::numbers::pi / 180.0);
                y *= degree;
            } else {
                x *= crs.value("unit_metres", 1.0);
                y *= crs.value("unit_metres", 1.0);
            }
            return {std::abs(x), std::abs(y)};
        }
    } catch (const nlohmann::json::exception&) {
        fail(main + ".georef.json", "not a georeference sidecar; give --spacing");
    }
    return {0.0, 0.0};
}

// A grid level drawn tile row by tile row, north first: `across` tiles of n intervals a side,
// whose vertices are tiles x n + 1 pixels. `load(tx, ty)` makes a tile current and `value(i, j)`
// reads it at vertex (i, j), i, j in -2 .. n + 2 (row 0 = south); `colour(i, j)` draws it.
struct GridLevel {
    int across = 1;
    int n = 0;
    std::function<void(int, int)> load;
    std::function<float(int, int)> value;
};

void scanRange(const GridLevel& g, double& lo, double& hi) {
    lo = std::numeric_limits<double>::infinity();
    hi = -lo;
    for (int ty = 0; ty < g.across; ++ty) {
        for (int tx = 0; tx < g.across; ++tx) {
            g.load(tx, ty);
            for (int j = 0; j <= g.n; ++j) {
                for (int i = 0; i <= g.n; ++i) {
                    const double v = g.value(i, j);
                    if (std::isfinite(v)) {
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                    }
                }
            }
        }
    }
    if (!(lo <= hi)) {
        lo = hi = 0.0;
    }
}

void drawGrid(const GridLevel& g, PngWriter& png, const std::function<Rgb8(int, int)>& colour) {
    const int64_t width = int64_t{g.across} * g.n + 1;
    std::vector<uint8_t> strip;
    for (int ty = g.across - 1; ty >= 0; --ty) {
        const int top = ty == g.across - 1 ? g.n : g.n - 1; // a tile's top row is its northern neighbour's bottom row
        strip.assign(static_cast<size_t>(width) * static_cast<size_t>(top + 1) * 3, 0);
        for (int tx = 0; tx < g.across; ++tx) {
            g.load(tx, ty);
            const int last = tx == g.across - 1 ? g.n : g.n - 1;
            for (int j = top; j >= 0; --j) {
                uint8_t* row = strip.data() + static_cast<size_t>(top - j) * static_cast<size_t>(width) * 3;
                for (int i = 0; i <= last; ++i) {
                    const Rgb8 c = colour(i, j);
                    std::copy(c.begin(), c.end(), row + (static_cast<size_t>(tx) * g.n + static_cast<size_t>(i)) * 3);
                }
            }
        }
        for (int r = 0; r <= top; ++r) {
            png.writeRow(strip.data() + static_cast<size_t>(r) * static_cast<size_t>(width) * 3);
        }
    }
}

std::string number(double v) { return exactNumberText(v); }

PreviewReport elevationPreview(const PyramidSet& set, const std::string& output, const PreviewOptions& o) {
    const ResidualHeader h = ResidualFileReader::readHeader(set.main);
    const int deepest = setMaxLevel(set);
    const auto intervals = [&](int l) { return h.tileSamples(l) - 5; };
    const int level =
        chooseLevel(o, deepest, [&](int l) { return h.tilesPerSide(l) * intervals(l) + 1; }, set.name());
    PreviewStyle style = o.style == PreviewStyle::Auto ? PreviewStyle::Hillshade : o.style;
    if (style == PreviewStyle::Colours) {
        failOption("style", "colours are for ortho pyramids; " + set.name() + " holds elevations");
    }
    GridLevel g;
    g.n = intervals(level);
    g.across = static_cast<int>(h.tilesPerSide(level));
    const int side = g.n + 5;
    PreviewReport report;
    report.kind = "elevation";
    report.style = previewStyleName(style);
    report.level = level;
    report.width = report.height = g.across * g.n + 1;

    std::shared_ptr<const ElevationTile> tile;
    StoredResidualTile stored;
    FileLevelProducer producer;
    if (style == PreviewStyle::Residuals) {
        g.load = [&](int tx, int ty) { stored = storedResidualTile(set, level, tx, ty); };
        g.value = [&](int i, int j) {
            return static_cast<float>(stored.residuals[static_cast<size_t>(j + 2) * static_cast<size_t>(side) +
                                                       static_cast<size_t>(i + 2)]) * h.scale;
        };
    } else {
        producer = makeSetLevelProducer(set, level, 8);
        g.load = [&](int tx, int ty) { tile = producer.fileTile(level, tx, ty); };
        g.value = [&](int i, int j) {
            return tile->zf[static_cast<size_t>(j + 2) * static_cast<size_t>(side) + static_cast<size_t>(i + 2)];
        };
    }
    scanRange(g, report.minimum, report.maximum);
    std::array<double, 2> spacing{o.spacing, o.spacing};
    const bool shading = style == PreviewStyle::Hillshade || style == PreviewStyle::Shade;
    if (shading && o.spacing <= 0.0) {
        spacing = sidecarSpacing(set.main, level);
        if (spacing[0] <= 0.0 || spacing[1] <= 0.0) {
            spacing = {1.0, 1.0};
        }
    }
    report.spacing = shading ? spacing[0] : 0.0;
    const double lo = report.minimum, hi = report.maximum;
    const double span = hi > lo ? hi - lo : 1.0;
    const double extreme = std::max(std::abs(lo), std::abs(hi)) > 0 ? std::max(std::abs(lo), std::abs(hi)) : 1.0;
    const std::function<Rgb8(int, int)> colour = [&](int i, int j) -> Rgb8 {
        const double v = g.value(i, j);
        if (style == PreviewStyle::Residuals) {
            // A signed square root: the many small residuals show beside the few large ones.
            const double t = v / extreme;
            return divergingColour(t < 0 ? -std::sqrt(-t) : std::sqrt(t));
        }
        const Rgb8 base = hypsometricColour((v - lo) / span);
        if (style == PreviewStyle::Heights) {
            return base;
        }
        const double dzdx = (g.value(i + 1, j) - g.value(i - 1, j)) * o.zFactor / (2.0 * spacing[0]);
        const double dzdy = (g.value(i, j + 1) - g.value(i, j - 1)) * o.zFactor / (2.0 * spacing[1]);
        const double light = hillshade(dzdx, dzdy, o.azimuth, o.altitude);
        if (style == PreviewStyle::Shade) {
            const auto grey = static_cast<uint8_t>(std::lround(255.0 * light));
            return {grey, grey, grey};
        }
        return shaded(base, light);
    };
    const std::string what = style == PreviewStyle::Residuals ? "residual" : "height";
    PngWriter png(output, report.width, report.height, 3, 8,
                  {{"Software", "libpyramid pyramid preview"},
                   {"Source", set.main},
                   {"Level", std::to_string(level)},
                   {"Style", report.style},
                   {"Minimum " + what, number(report.minimum)},
                   {"Maximum " + what, number(report.maximum)}});
    drawGrid(g, png, colour);
    png.commit();
    return report;
}

PreviewReport orthoPreview(const PyramidSet& set, const std::string& output, const PreviewOptions& o) {
    const auto producer = openOrthoSet(set);
    const OrthoHeader& h = producer->header();
    if (o.style != PreviewStyle::Auto && o.style != PreviewStyle::Colours) {
        failOption("style", previewStyleName(o.style) + " is for elevation pyramids; " + set.name() + " holds orthos");
    }
    const int T = h.tileSize, b = h.border();
    const int level = chooseLevel(o, producer->maxLevel(), [&](int l) { return int64_t{T} << l; }, set.name());
    // A colour residual file (the name preprocessOrtho gives it) is drawn as its colours.
    const bool residuals = !h.dxt() && b == 2 &&
                           std::filesystem::path(set.main).parent_path().filename() == "residuals";
    std::unique_ptr<ColourProducer> colours;
    if (residuals) {
        colours = std::make_unique<ColourProducer>(producer, 8);
    }
    const int channels = h.dxt() ? (h.channels == 4 ? 4 : 3) : h.channels;
    const int across = 1 << level;
    const int64_t width = int64_t{T} * across;
    PreviewReport report;
    report.kind = residuals ? "colour residuals" : "ortho";
    report.style = "colours";
    report.level = level;
    report.width = report.height = static_cast<int>(width);
    report.maximum = 255.0;
    PngWriter png(output, report.width, report.height, channels, 8,
                  {{"Software", "libpyramid pyramid preview"},
                   {"Source", set.main},
                   {"Level", std::to_string(level)},
                   {"Style", report.style}});
    const int tilePixels = T + 2 * b;
    const size_t rowBytes = static_cast<size_t>(width) * static_cast<size_t>(channels);
    std::vector<uint8_t> strip(rowBytes * static_cast<size_t>(T));
    for (int ty = across - 1; ty >= 0; --ty) {
        for (int tx = 0; tx < across; ++tx) {
            const std::vector<uint8_t> pixels = colours ? *colours->tile(level, tx, ty) : producer->tile(level, tx, ty);
            for (int j = 0; j < T; ++j) {
                const uint8_t* from = pixels.data() + (static_cast<size_t>(j + b) * static_cast<size_t>(tilePixels) +
                                                       static_cast<size_t>(b)) * static_cast<size_t>(channels);
                std::copy_n(from, static_cast<size_t>(T) * static_cast<size_t>(channels),
                            strip.data() + static_cast<size_t>(T - 1 - j) * rowBytes +
                                static_cast<size_t>(tx) * static_cast<size_t>(T) * static_cast<size_t>(channels));
            }
        }
        for (int r = 0; r < T; ++r) {
            png.writeRow(strip.data() + static_cast<size_t>(r) * rowBytes);
        }
    }
    png.commit();
    return report;
}

} // namespace

PreviewReport writePreview(const std::string& input, const std::string& output, const PreviewOptions& o) {
    if (o.size < 1) {
        failOption("size", std::to_string(o.size) + " is not a positive number of pixels");
    }
    if (o.level < -1) {
        failOption("level", std::to_string(o.level) + " is not a level");
    }
    if (!(o.spacing >= 0.0) || !std::isfinite(o.spacing)) {
        failOption("spacing", "must be a positive distance");
    }
    if (!std::isfinite(o.zFactor) || !std::isfinite(o.azimuth) || !(o.altitude > 0.0 && o.altitude <= 90.0)) {
        failOption("altitude", "the sun must be 0 to 90 degrees above the horizon, the z factor and azimuth finite");
    }
    const PyramidSet set = openPyramidSet(input);
    PreviewReport report =
        set.kind == PyramidKind::Residual ? elevationPreview(set, output, o) : orthoPreview(set, output, o);
    report.input = input;
    report.output = output;
    return report;
}

} // namespace pyramid
