#include "libpyramid/preview/preview_levels.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>

#include "formats/error.hpp"
#include "libpyramid/runtime/level_heights.hpp"
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

ElevationGrid::ElevationGrid(const PyramidSet& set, int level, bool residuals, size_t cacheTiles)
    : set_(set), level_(level), residuals_(residuals) {
    const ResidualHeader h = ResidualFileReader::readHeader(set.main);
    scale_ = h.scale;
    n_ = h.tileSamples(level) - 5;
    across_ = static_cast<int>(h.tilesPerSide(level));
    if (!residuals_) {
        producer_ = makeSetLevelProducer(set_, level_, cacheTiles);
    }
}

void ElevationGrid::load(int tx, int ty) {
    const int64_t key = int64_t{ty} * across_ + tx;
    if (key == key_) {
        return;
    }
    key_ = key;
    if (residuals_) {
        stored_ = storedResidualTile(set_, level_, tx, ty);
        // Reused as the tile's values, times the scale.
        tile_.reset();
        auto values = std::make_shared<ElevationTile>();
        values->zf.resize(stored_.residuals.size());
        for (size_t k = 0; k < values->zf.size(); ++k) {
            values->zf[k] = static_cast<float>(stored_.residuals[k]) * scale_;
        }
        tile_ = std::move(values);
    } else {
        tile_ = producer_.fileTile(level_, tx, ty);
    }
    heights_ = tile_->zf.data();
}

float ElevationGrid::at(int tx, int ty, int i, int j) {
    load(tx, ty);
    const int side = n_ + 5;
    return heights_[static_cast<size_t>(j + 2) * static_cast<size_t>(side) + static_cast<size_t>(i + 2)];
}

double ElevationGrid::bilinear(double x, double y) {
    const LevelCell cell = levelCell(n_, across_, x, y);
    load(cell.tx, cell.ty);
    return cellHeight(heights_, n_, cell);
}

std::pair<double, double> ElevationGrid::range() {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int ty = 0; ty < across_; ++ty) {
        for (int tx = 0; tx < across_; ++tx) {
            for (int j = 0; j <= n_; ++j) {
                for (int i = 0; i <= n_; ++i) {
                    const double v = at(tx, ty, i, j);
                    if (std::isfinite(v)) {
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                    }
                }
            }
        }
    }
    return lo <= hi ? std::pair{lo, hi} : std::pair{0.0, 0.0};
}

// ---------------------------------------------------------------------------------------------

ColourGrid::ColourGrid(const PyramidSet& set, std::shared_ptr<OrthoProducer> producer, int level, size_t cacheTiles)
    : producer_(std::move(producer)), level_(level), capacity_(std::max<size_t>(cacheTiles, 1)) {
    const OrthoHeader& h = producer_->header();
    tileSize_ = h.tileSize;
    border_ = h.border();
    across_ = 1 << level;
    channels_ = h.dxt() ? (h.channels == 4 ? 4 : 3) : h.channels;
    // A colour residual file (the name preprocessOrtho gives it) is drawn as its colours.
    if (!h.dxt() && border_ == 2 && std::filesystem::path(set.main).parent_path().filename() == "residuals") {
        colours_ = std::make_unique<ColourProducer>(producer_, std::max<size_t>(cacheTiles, 8));
    }
}

const uint8_t* ColourGrid::tile(int tx, int ty) {
    const int64_t key = int64_t{ty} * across_ + tx;
    const auto found = index_.find(key);
    if (found != index_.end()) {
        tiles_.splice(tiles_.begin(), tiles_, found->second);
        return tiles_.front().second->data();
    }
    std::shared_ptr<const std::vector<uint8_t>> pixels =
        colours_ ? colours_->tile(level_, tx, ty)
                 : std::make_shared<const std::vector<uint8_t>>(producer_->tile(level_, tx, ty));
    tiles_.emplace_front(key, std::move(pixels));
    index_[key] = tiles_.begin();
    if (tiles_.size() > capacity_) {
        index_.erase(tiles_.back().first);
        tiles_.pop_back();
    }
    return tiles_.front().second->data();
}

void ColourGrid::bilinear(double x, double y, uint8_t* out) {
    const int pixels = tileSize_ + 2 * border_;
    const auto cell = [&](double c, int& t, int& k, double& f) {
        const double lowest = -0.5, highest = static_cast<double>(side()) - 0.5;
        c = std::clamp(c, lowest, highest);
        const auto whole = static_cast<int64_t>(std::floor(c));
        t = static_cast<int>(std::clamp<int64_t>(whole < 0 ? 0 : whole / tileSize_, 0, across_ - 1));
        // The pixel in the tile's own coordinates, borders included; without borders the
        // edge pixel stands for what lies beyond.
        k = static_cast<int>(whole - int64_t{t} * tileSize_) + border_;
        f = c - static_cast<double>(whole);
        if (k < 0) {
            k = 0;
            f = 0.0;
        } else if (k + 1 > pixels - 1) {
            k = pixels - 2;
            f = 1.0;
        }
    };
    int tx = 0, ty = 0, i = 0, j = 0;
    double fx = 0.0, fy = 0.0;
    cell(x, tx, i, fx);
    cell(y, ty, j, fy);
    const uint8_t* p = tile(tx, ty);
    const auto at = [&](int a, int b, int c) {
        return static_cast<double>(p[(static_cast<size_t>(b) * static_cast<size_t>(pixels) + static_cast<size_t>(a)) *
                                         static_cast<size_t>(channels_) +
                                     static_cast<size_t>(c)]);
    };
    for (int c = 0; c < channels_; ++c) {
        const double v = (at(i, j, c) * (1.0 - fx) + at(i + 1, j, c) * fx) * (1.0 - fy) +
                         (at(i, j + 1, c) * (1.0 - fx) + at(i + 1, j + 1, c) * fx) * fy;
        out[c] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
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

// ---------------------------------------------------------------------------------------------

namespace {

// A 5 x 7 pixel font for the legend's numbers: each glyph 7 rows of 5 bits, the high bit on the left.
const std::array<uint8_t, 7>* glyph(char c) {
    static const std::array<uint8_t, 7> digits[10] = {
        {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}, {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E},
        {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}, {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E},
        {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}, {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E},
        {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}, {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08},
        {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}, {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}};
    static const std::array<uint8_t, 7> minus{0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00};
    static const std::array<uint8_t, 7> plus{0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00};
    static const std::array<uint8_t, 7> point{0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C};
    static const std::array<uint8_t, 7> e{0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E};
    if (c >= '0' && c <= '9') {
        return &digits[c - '0'];
    }
    switch (c) {
    case '-':
        return &minus;
    case '+':
        return &plus;
    case '.':
        return &point;
    case 'e':
        return &e;
    default:
        return nullptr; // a space
    }
}

// The legend's text of a value: four significant digits.
std::string legendText(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", v == 0.0 ? 0.0 : v);
    return text;
}

} // namespace

std::vector<std::vector<uint8_t>> legendRows(int64_t width, const ElevationPaint& paint) {
    const int scale = width >= 240 ? 2 : 1;
    const int margin = 4 * scale, bar = 8 * scale, gap = 3 * scale, textHeight = 7 * scale;
    const int height = margin + bar + gap + textHeight + margin;
    const auto w = static_cast<size_t>(width);
    std::vector<std::vector<uint8_t>> rows(static_cast<size_t>(height), std::vector<uint8_t>(w * 3, 255));
    const int64_t x0 = std::min<int64_t>(margin, width / 4), x1 = std::max<int64_t>(width - 1 - x0, x0);
    const double low = paint.legendLow(), high = paint.legendHigh();
    for (int64_t x = x0; x <= x1; ++x) {
        const double p = x1 > x0 ? static_cast<double>(x - x0) / static_cast<double>(x1 - x0) : 0.0;
        const Rgb8 c = paint.base(low + (high - low) * p);
        for (int r = margin; r < margin + bar; ++r) {
            std::copy(c.begin(), c.end(), rows[static_cast<size_t>(r)].data() + static_cast<size_t>(x) * 3);
        }
    }
    // The labels: left-aligned under the bar's left end, right-aligned under its right end, and
    // (residuals) 0 centred under its middle. Glyphs beyond the image are cut.
    const auto write = [&](const std::string& text, int64_t left) {
        for (size_t k = 0; k < text.size(); ++k) {
            const auto* g = glyph(text[k]);
            if (!g) {
                continue;
            }
            for (int gy = 0; gy < 7 * scale; ++gy) {
                for (int gx = 0; gx < 5 * scale; ++gx) {
                    const int64_t x = left + static_cast<int64_t>(k) * 6 * scale + gx;
                    if (x < 0 || x >= width || !((*g)[static_cast<size_t>(gy / scale)] & (0x10 >> (gx / scale)))) {
                        continue;
                    }
                    uint8_t* p = rows[static_cast<size_t>(margin + bar + gap + gy)].data() + static_cast<size_t>(x) * 3;
                    p[0] = p[1] = p[2] = 0;
                }
            }
        }
    };
    const auto textWidth = [&](const std::string& t) { return static_cast<int64_t>(t.size()) * 6 * scale - scale; };
    const std::string left = legendText(low), right = legendText(high);
    write(left, x0);
    write(right, x1 + 1 - textWidth(right));
    if (paint.style == PreviewStyle::Residuals) {
        write("0", (x0 + x1 + 1) / 2 - textWidth("0") / 2);
    }
    return rows;
}

} // namespace pyramid::preview
