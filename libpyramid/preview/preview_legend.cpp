// The legend under an elevation preview (preview_levels.hpp, legendRows): a colour bar of the
// style's colours over the range, its values written in a 5 x 7 pixel font.
#include "libpyramid/preview/preview_levels.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
#include <vector>

namespace pyramid::preview {

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
