#include "libpyramid/preview/preview_levels.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "formats/error.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid::preview {

int64_t elevationLevelSide(const ResidualHeader& h, int level) {
    return h.tilesPerSide(level) * (h.tileSamples(level) - 5) + 1;
}

int64_t orthoLevelSide(const OrthoHeader& h, int level) { return int64_t{h.tileSize} << level; }

int chooseLevel(const PreviewOptions& o, int deepest, int64_t limit, const std::function<int64_t(int)>& side,
                const std::string& name) {
    if (o.level) {
        if (*o.level > deepest) {
            failOption("level", std::to_string(*o.level) + " is not a level of " + name + " (0 to " +
                                    std::to_string(deepest) + ")");
        }
        return *o.level;
    }
    int level = 0;
    while (level < deepest && side(level + 1) <= limit) {
        ++level;
    }
    return level;
}

PreviewStyle elevationStyle(const PreviewOptions& o, const std::string& name) {
    const PreviewStyle style = o.style == PreviewStyle::Auto ? PreviewStyle::Hillshade : o.style;
    if (style == PreviewStyle::Colours) {
        failOption("style", "colours are for ortho pyramids; " + name + " holds elevations");
    }
    if (o.legend && style == PreviewStyle::Shade) {
        failOption("legend", "the shade style has no colour scale to show");
    }
    return style;
}

void checkColourStyle(const PreviewOptions& o, const std::string& name) {
    if (o.style != PreviewStyle::Auto && o.style != PreviewStyle::Colours) {
        failOption("style", previewStyleName(o.style) + " is for elevation pyramids; " + name + " holds orthos");
    }
    if (o.legend) {
        failOption("legend", "a legend shows the scale of an elevation style; " + name + " holds orthos");
    }
    if (o.seaLevel) {
        failOption("sea-level", "is for elevation styles; " + name + " holds orthos");
    }
}

std::vector<PngText> previewText(const std::string& source, const PreviewReport& report) {
    std::vector<PngText> text = {{"Software", "libpyramid pyramid preview"},
                                 {"Source", source},
                                 {"Level", std::to_string(report.level)},
                                 {"Style", report.style}};
    if (report.projection != "face") {
        text.push_back({"Projection", report.projection});
        text.push_back({"Body", report.body});
    }
    if (report.kind == "elevation") {
        const std::string what = report.style == "residuals" ? "residual" : "height";
        text.push_back({"Minimum " + what, exactNumberText(report.minimum)});
        text.push_back({"Maximum " + what, exactNumberText(report.maximum)});
    }
    if (report.legendHeight > 0) {
        text.push_back({"Legend rows", std::to_string(report.legendHeight)});
    }
    return text;
}

void writeImage(PngWriter& png, const LevelImage& image) {
    std::vector<uint8_t> rows;
    const size_t rowBytes = static_cast<size_t>(image.side) * static_cast<size_t>(image.channels);
    for (int s = 0; s < image.strips; ++s) {
        const int count = image.strip(s, rows);
        for (int r = 0; r < count; ++r) {
            png.writeRow(rows.data() + static_cast<size_t>(r) * rowBytes);
        }
    }
}

// ---------------------------------------------------------------------------------------------

ElevationPaint::ElevationPaint(PreviewStyle s, double low, double high, const PreviewOptions& o)
    : style(s), lo(low), hi(high), seaLevel(o.seaLevel), zFactor(o.zFactor), azimuth(o.azimuth),
      altitude(o.altitude) {}

Rgb8 ElevationPaint::base(double v) const {
    if (!std::isfinite(v)) {
        return {0, 0, 0};
    }
    if (style == PreviewStyle::Residuals) {
        // A signed square root: the many small residuals show beside the few large ones.
        const double extreme = std::max(std::abs(lo), std::abs(hi)) > 0 ? std::max(std::abs(lo), std::abs(hi)) : 1.0;
        const double t = v / extreme;
        return divergingColour(t < 0 ? -std::sqrt(-t) : std::sqrt(t));
    }
    if (seaLevel && v <= *seaLevel) {
        return {52, 98, 158};
    }
    // Above the sea (when there is one), the ramp starts at its level.
    const double floor = seaLevel && *seaLevel > lo ? *seaLevel : lo;
    const double span = hi > floor ? hi - floor : 1.0;
    return hypsometricColour((v - floor) / span);
}

Rgb8 ElevationPaint::colour(double v, double dzdx, double dzdy) const {
    if (!std::isfinite(v)) {
        return {0, 0, 0};
    }
    if (!shading()) {
        return base(v);
    }
    double light = hillshade(dzdx * zFactor, dzdy * zFactor, azimuth, altitude);
    if (!std::isfinite(light)) {
        light = 0.0; // a slope next to a missing sample
    }
    if (style == PreviewStyle::Shade) {
        const auto grey = static_cast<uint8_t>(std::lround(255.0 * light));
        return {grey, grey, grey};
    }
    return shaded(base(v), light);
}

double ElevationPaint::legendLow() const {
    return style == PreviewStyle::Residuals ? -std::max(std::abs(lo), std::abs(hi)) : lo;
}

double ElevationPaint::legendHigh() const {
    return style == PreviewStyle::Residuals ? std::max(std::abs(lo), std::abs(hi)) : hi;
}

// ---------------------------------------------------------------------------------------------

LevelImage elevationImage(ElevationGrid& grid, const ElevationPaint& paint, const SampleSpacing& spacing) {
    LevelImage image;
    image.side = grid.side();
    image.channels = 3;
    image.strips = grid.across();
    image.strip = [&grid, &paint, spacing](int s, std::vector<uint8_t>& rows) {
        const int across = grid.across(), n = grid.n();
        const int ty = across - 1 - s;
        const size_t width = static_cast<size_t>(grid.side());
        const int top = ty == across - 1 ? n : n - 1; // a tile's top row is its northern neighbour's bottom row
        rows.assign(width * static_cast<size_t>(top + 1) * 3, 0);
        for (int tx = 0; tx < across; ++tx) {
            const int last = tx == across - 1 ? n : n - 1;
            for (int j = top; j >= 0; --j) {
                uint8_t* row = rows.data() + static_cast<size_t>(top - j) * width * 3;
                for (int i = 0; i <= last; ++i) {
                    const double v = grid.at(tx, ty, i, j);
                    double dzdx = 0.0, dzdy = 0.0;
                    if (paint.shading()) {
                        const std::array<double, 2> d = spacing(tx, ty, i, j);
                        dzdx = (grid.at(tx, ty, i + 1, j) - grid.at(tx, ty, i - 1, j)) / (2.0 * d[0]);
                        dzdy = (grid.at(tx, ty, i, j + 1) - grid.at(tx, ty, i, j - 1)) / (2.0 * d[1]);
                    }
                    const Rgb8 c = paint.colour(v, dzdx, dzdy);
                    std::copy(c.begin(), c.end(), row + (static_cast<size_t>(tx) * static_cast<size_t>(n) + static_cast<size_t>(i)) * 3);
                }
            }
        }
        return top + 1;
    };
    return image;
}

LevelImage colourImage(ColourGrid& grid) {
    LevelImage image;
    image.side = grid.side();
    image.channels = grid.channels();
    image.strips = grid.across();
    image.strip = [&grid](int s, std::vector<uint8_t>& rows) {
        const int T = grid.tileSize(), b = grid.border(), C = grid.channels();
        const int ty = grid.across() - 1 - s;
        const size_t rowBytes = static_cast<size_t>(grid.side()) * static_cast<size_t>(C);
        const size_t tilePixels = static_cast<size_t>(T + 2 * b);
        rows.resize(rowBytes * static_cast<size_t>(T));
        for (int tx = 0; tx < grid.across(); ++tx) {
            const uint8_t* pixels = grid.tile(tx, ty);
            for (int j = 0; j < T; ++j) {
                const uint8_t* from = pixels + (static_cast<size_t>(j + b) * tilePixels + static_cast<size_t>(b)) * static_cast<size_t>(C);
                std::copy_n(from, static_cast<size_t>(T) * static_cast<size_t>(C),
                            rows.data() + static_cast<size_t>(T - 1 - j) * rowBytes +
                                static_cast<size_t>(tx) * static_cast<size_t>(T) * static_cast<size_t>(C));
            }
        }
        return T;
    };
    return image;
}

} // namespace pyramid::preview
