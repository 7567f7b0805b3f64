#include "libpyramid/encode/ortho/planar_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "libpyramid/support/row_pair_cache.hpp"
#include "formats/vector_clones.hpp"

namespace pyramid {

namespace {

// The two halves of the separable bilinear interpolation of PlanarPixels::sample, in
// functions of their own so that they are compiled for wider vectors too (vector_clones.hpp:
// the same operations, so the same bytes). A channel count known at compile time lets the
// compiler vectorise across the pixels of a row.
//
// Input row `in` interpolated at `columns` output columns: column i lies between the input
// pixels at element offsets first[i] and second[i], at `weight[i]` from the first.
template <int Channels, typename Sample>
[[gnu::always_inline]] inline void interpolateRowOf(const Sample* __restrict in, const size_t* __restrict first,
                                                    const size_t* __restrict second, const double* __restrict weight,
                                                    int columns, double* __restrict out) {
    for (int i = 0; i < columns; ++i) {
        const double fx = weight[i];
        for (int ch = 0; ch < Channels; ++ch) {
            const double v = in[first[i] + ch];
            out[i * Channels + ch] = v + (static_cast<double>(in[second[i] + ch]) - v) * fx;
        }
    }
}

// By channel count; inlined into each clone below, for 16-bit samples and for 8-bit samples as
// stored (each converts to the same double as when widened).
template <typename Sample>
[[gnu::always_inline]] inline void interpolateRowAny(const Sample* in, const size_t* first, const size_t* second,
                                                     const double* weight, int columns, int channels, double* out) {
    switch (channels) {
    case 1: return interpolateRowOf<1>(in, first, second, weight, columns, out);
    case 2: return interpolateRowOf<2>(in, first, second, weight, columns, out);
    case 3: return interpolateRowOf<3>(in, first, second, weight, columns, out);
    default: return interpolateRowOf<4>(in, first, second, weight, columns, out);
    }
}

PYRAMID_VECTOR_CLONES
void interpolateRow(const uint16_t* in, const size_t* first, const size_t* second, const double* weight,
                    int columns, int channels, double* out) {
    interpolateRowAny(in, first, second, weight, columns, channels, out);
}

PYRAMID_VECTOR_CLONES
void interpolateRow(const uint8_t* in, const size_t* first, const size_t* second, const double* weight,
                    int columns, int channels, double* out) {
    interpolateRowAny(in, first, second, weight, columns, channels, out);
}

// The documented conversion, v8 = lround(v * 255 / full), of values v in [0, full]: there the
// conversion to an integer truncates (floor) and x - floor(x) is exact, so it is std::lround's
// result without a branch or a library call.
PYRAMID_VECTOR_CLONES
void combineRowsExact(const double* __restrict top, const double* __restrict bottom, double fy, double full,
                      size_t count, uint8_t* __restrict row) {
    for (size_t k = 0; k < count; ++k) {
        const double x = (top[k] + (bottom[k] - top[k]) * fy) * 255.0 / full;
        const auto i = static_cast<int32_t>(x);
        row[k] = static_cast<uint8_t>(i + static_cast<int32_t>(x - static_cast<double>(i) >= 0.5));
    }
}

// 8-bit input (full = 255) without the multiplication and division: x = v * 255 / 255 lies
// within two units in the last place of v (two roundings of half a unit each), so x and v
// round to different integers only if a half lies between them, and no value within eight
// units in the last place of any half from 0.5 to 254.5 rounds differently (checked value by
// value in tests/ortho_levels_test.cpp): the same bytes as the formula.
PYRAMID_VECTOR_CLONES
void combineRows8(const double* __restrict top, const double* __restrict bottom, double fy, size_t count,
                  uint8_t* __restrict row) {
    for (size_t k = 0; k < count; ++k) {
        const double v = top[k] + (bottom[k] - top[k]) * fy;
        const auto i = static_cast<int32_t>(v);
        row[k] = static_cast<uint8_t>(i + static_cast<int32_t>(v - static_cast<double>(i) >= 0.5));
    }
}

} // namespace

void combineRows(const double* top, const double* bottom, double fy, double full, size_t count, uint8_t* row) {
    if (full == 255.0) {
        combineRows8(top, bottom, fy, count, row);
    } else {
        combineRowsExact(top, bottom, fy, full, count, row);
    }
}

PlanarPixels::PlanarPixels(const RasterSource& source, int channels, int64_t width, bool stretch)
    : source_(source), channels_(channels), stretch_(stretch) {
    const RasterInfo& info = source.info();
    sixteen_ = info.type == SampleType::UInt16;
    const int64_t W = width;
    ax_.output = ay_.output = W;
    ax_.input = info.width;
    ay_.input = info.height;
    ay_.flip = true;
    if (info.width == W && info.height == W) {
        ax_.exact = ay_.exact = true;
        inPlace_ = true;
        sampling_ = "input pixels are the finest level's pixels (no resampling)";
    } else if (stretch) {
        ax_.scale = static_cast<double>(info.width) / static_cast<double>(W);
        ay_.scale = static_cast<double>(info.height) / static_cast<double>(W);
        sampling_ = "bilinear resampling, width and height stretched independently onto " + std::to_string(W) + "x" +
                    std::to_string(W) + " pixels";
    } else {
        const int64_t longest = std::max(info.width, info.height);
        ax_.scale = ay_.scale = static_cast<double>(longest) / static_cast<double>(W);
        inPlace_ = info.width == W; // and so longest == W: scale 1, the height below W
        const std::string placed =
            info.width != info.height ? ", input at the north-west corner, the rest black and transparent" : "";
        sampling_ = longest == W ? "input pixels are the finest level's pixels (no resampling)" + placed
                                 : "bilinear resampling onto " + std::to_string(W) + "x" + std::to_string(W) +
                                       " pixels, aspect ratio kept" + placed;
    }
}

void PlanarPixels::passedNorthOf(int64_t y) const {
    // Row y reads input rows floor(position) and the one after (sample(): the rows' bounds);
    // the rows south of it read rows further south still.
    const double position = ay_.position(y);
    if (position >= 1.0) {
        source_.releaseRowsAbove(static_cast<int>(std::min<double>(std::floor(position), ay_.input)));
    }
}

Image8 PlanarPixels::sample(int64_t x0, int64_t y0, int w, int h) const {
    if (inPlace_ && !sixteen_) {
        return sampleInPlace(x0, y0, w, h);
    }
    // Pixels beyond the input are 0: the rows and columns below that no sample reaches are
    // cleared as they are met, not the whole image first.
    Image8 out(w, h, channels_, Image8::Unset);
    std::vector<double> px(static_cast<size_t>(w)), py(static_cast<size_t>(h));
    double minX = 1e300, maxX = -1e300, minY = 1e300, maxY = -1e300;
    for (int i = 0; i < w; ++i) {
        px[static_cast<size_t>(i)] = ax_.position(x0 + i);
        if (ax_.inside(px[static_cast<size_t>(i)])) {
            minX = std::min(minX, px[static_cast<size_t>(i)]);
            maxX = std::max(maxX, px[static_cast<size_t>(i)]);
        }
    }
    for (int j = 0; j < h; ++j) {
        py[static_cast<size_t>(j)] = ay_.position(y0 + j);
        if (ay_.inside(py[static_cast<size_t>(j)])) {
            minY = std::min(minY, py[static_cast<size_t>(j)]);
            maxY = std::max(maxY, py[static_cast<size_t>(j)]);
        }
    }
    if (minX > maxX || minY > maxY) {
        std::fill(out.pixels.begin(), out.pixels.end(), uint8_t{0}); // beyond the input: zeros
        return out;
    }
    const int cx0 = std::clamp(static_cast<int>(std::floor(minX)), 0, ax_.input - 1);
    const int cx1 = std::clamp(static_cast<int>(std::floor(maxX)) + 1, 0, ax_.input - 1);
    const int ry0 = std::clamp(static_cast<int>(std::floor(minY)), 0, ay_.input - 1);
    const int ry1 = std::clamp(static_cast<int>(std::floor(maxY)) + 1, 0, ay_.input - 1);
    const int ww = cx1 - cx0 + 1;
    // Every sample of the window is read next: not cleared first. One window per thread, kept
    // from subtree to subtree (it only grows): a fresh one would fault its pages in again for
    // every subtree. 8-bit samples are kept as they are (half the bytes, and no widening).
    thread_local std::vector<uint16_t, DefaultInitAllocator<uint16_t>> window16;
    thread_local std::vector<uint8_t, DefaultInitAllocator<uint8_t>> window8;
    const size_t windowSamples = static_cast<size_t>(ww) * static_cast<size_t>(ry1 - ry0 + 1) * channels_;
    if (sixteen_) {
        window16.resize(windowSamples);
        source_.readUInt16(cx0, ry0, cx1 + 1, ry1 + 1, 0, channels_, window16.data());
    } else {
        window8.resize(windowSamples);
        source_.readUInt8(cx0, ry0, cx1 + 1, ry1 + 1, 0, channels_, window8.data(),
                          static_cast<std::ptrdiff_t>(ww) * channels_);
    }
    // The columns' neighbours and weights are the same on every row: computed once (the
    // same values as per pixel, so the same bytes). Columns inside the input are a prefix
    // [0, insideEnd), as positions grow with the column.
    std::vector<size_t> off0(static_cast<size_t>(w)), off1(static_cast<size_t>(w));
    std::vector<double> colFx(static_cast<size_t>(w));
    int insideEnd = 0;
    for (int i = 0; i < w; ++i) {
        const double X = px[static_cast<size_t>(i)];
        insideEnd = ax_.inside(X) ? i + 1 : insideEnd;
        const double fx0 = std::floor(X);
        colFx[static_cast<size_t>(i)] = X - fx0;
        off0[static_cast<size_t>(i)] =
            static_cast<size_t>(std::clamp(static_cast<int>(fx0), 0, ax_.input - 1) - cx0) * channels_;
        off1[static_cast<size_t>(i)] =
            static_cast<size_t>(std::clamp(static_cast<int>(fx0) + 1, 0, ax_.input - 1) - cx0) * channels_;
    }
    // Separable evaluation of the formula: `top` and `bottom` are each the horizontal
    // interpolation of one input row, computed once per input row and shared by the output
    // rows that use it (RowPairCache); then `v = top + (bottom - top) * fy`
    // for a whole output row at once. Where fx or fy is 0 the formula gives the sample
    // itself, exactly, so no case needs a path of its own.
    const size_t rowSamples = static_cast<size_t>(insideEnd) * channels_;
    RowPairCache rows(rowSamples);
    const auto horizontal = [&](int64_t r, double* interpolated) {
        const size_t at = static_cast<size_t>(r - ry0) * ww * channels_;
        if (sixteen_) {
            interpolateRow(&window16[at], off0.data(), off1.data(), colFx.data(), insideEnd, channels_, interpolated);
        } else {
            interpolateRow(&window8[at], off0.data(), off1.data(), colFx.data(), insideEnd, channels_, interpolated);
        }
    };
    const size_t rowBytes = static_cast<size_t>(w) * channels_;
    for (int j = 0; j < h; ++j) {
        const double Y = py[static_cast<size_t>(j)];
        if (!ay_.inside(Y) || insideEnd == 0) {
            std::fill_n(out.at(0, j), rowBytes, uint8_t{0});
            continue;
        }
        const double fy0 = std::floor(Y);
        const double fy = Y - fy0;
        const int r0 = std::clamp(static_cast<int>(fy0), 0, ay_.input - 1);
        const int r1 = std::clamp(static_cast<int>(fy0) + 1, 0, ay_.input - 1);
        uint8_t* row = out.at(0, j);
        if (ax_.exact && !sixteen_) {
            // 8-bit input pixels are the finest pixels (every column inside the input): the
            // interpolation and conversion below would give each sample unchanged.
            const size_t first = (static_cast<size_t>(r0 - ry0) * ww + static_cast<size_t>(x0 - cx0)) * channels_;
            std::copy_n(&window8[first], static_cast<size_t>(w) * channels_, row);
            continue;
        }
        const double* top = rows.row(r0, r1, horizontal);
        const double* bottom = rows.row(r1, r0, horizontal);
        combineRows(top, bottom, fy, sixteen_ ? 65535.0 : 255.0, rowSamples, row);
        std::fill(row + rowSamples, row + rowBytes, uint8_t{0});
    }
    return out;
}

// An 8-bit input as wide as the finest level and as high or less, at scale 1: every position is
// an input pixel's centre (X = x, Y = W - 1 - y), where the formula gives the pixel unchanged,
// and the rows beyond the input's height are 0. The input rows are read straight into place,
// bottom up (output row j is input row W - 1 - (y0 + j)); the general path gives the same bytes
// through a 16-bit window and a copy.
Image8 PlanarPixels::sampleInPlace(int64_t x0, int64_t y0, int w, int h) const {
    const int64_t firstInside = std::max<int64_t>(0, ay_.output - ay_.input - y0); // output row
    // Every row is read into place when all are inside; the others stay 0.
    Image8 out = firstInside == 0 ? Image8(w, h, channels_, Image8::Unset) : Image8(w, h, channels_);
    if (firstInside < h) {
        const auto rowBytes = static_cast<std::ptrdiff_t>(w) * channels_;
        const auto top = static_cast<int>(ay_.output - y0 - h); // the input row of output row h - 1
        const auto end = static_cast<int>(ay_.output - y0 - firstInside);
        source_.readUInt8(static_cast<int>(x0), top, static_cast<int>(x0) + w, end, 0, channels_, out.at(0, h - 1),
                          -rowBytes);
    }
    return out;
}

// Positions grow with x, and shrink with y (flipped): the nearest pixel to the input is the
// first column, and the last row.
bool PlanarPixels::knownBlank(int64_t x0, int64_t y0, int64_t w, int64_t h) const {
    return !ax_.inside(ax_.position(x0)) || !ay_.inside(ay_.position(y0 + h - 1)) || w <= 0 || h <= 0;
}

// The map's edge pixels repeat.
int64_t PlanarPixels::borderPixel(int64_t p, int64_t width) const { return std::clamp<int64_t>(p, 0, width - 1); }

} // namespace pyramid

namespace pyramid {

bool PlanarPixels::severalLevels() const {
    const std::vector<RasterPart>& parts = source_.info().parts;
    return std::any_of(parts.begin(), parts.end(), [&](const RasterPart& p) {
        return std::fabs(p.pixelsPerSample - parts.front().pixelsPerSample) > 1e-9 * parts.front().pixelsPerSample;
    });
}

bool PlanarPixels::mayNeedLevel(int64_t levelWidth, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    const std::vector<RasterPart>& parts = source_.info().parts;
    if (parts.empty()) {
        return true;
    }
    const Axis ax = coarser(ax_, levelWidth), ay = coarser(ay_, levelWidth);
    // The input pixels the samples interpolate: from the first's to the one after the last's.
    const auto span = [](const Axis& a, int64_t p0, int64_t p1) {
        const double u = a.position(p0), v = a.position(p1);
        return std::pair<int64_t, int64_t>{static_cast<int64_t>(std::floor(std::min(u, v))),
                                           static_cast<int64_t>(std::floor(std::max(u, v))) + 1};
    };
    const auto [cx0, cx1] = span(ax, x0, x1);
    const auto [ry0, ry1] = span(ay, y0, y1);
    const double longest = std::max(ax_.input, ay_.input);
    for (const RasterPart& p : parts) {
        if (!(longest / p.pixelsPerSample > static_cast<double>(levelWidth) / 2.0)) {
            continue; // a part too coarse for this level
        }
        if (cx0 < p.x1 && p.x0 <= cx1 && ry0 < p.y1 && p.y0 <= ry1) {
            return true;
        }
    }
    return false;
}

PlanarPixels::Axis PlanarPixels::coarser(const Axis& finest, int64_t levelWidth) const {
    Axis a = finest;
    if (levelWidth == finest.output) {
        return a;
    }
    a.output = levelWidth;
    a.exact = false;
    const int64_t longest = std::max(ax_.input, ay_.input);
    a.scale = static_cast<double>(stretch_ ? a.input : longest) / static_cast<double>(levelWidth);
    return a;
}

Image8 PlanarPixels::sampleAt(int64_t levelWidth, int64_t x0, int64_t y0, int w, int h) const {
    if (levelWidth == ax_.output) {
        return sample(x0, y0, w, h);
    }
    const Axis ax = coarser(ax_, levelWidth), ay = coarser(ay_, levelWidth);
    Image8 out(w, h, channels_); // pixels beyond the input stay 0
    // Each sample's two input columns and rows, and its weights: the formula of sample().
    struct Tap {
        int first = 0, second = 0;
        double weight = 0.0;
        bool inside = false;
    };
    const auto taps = [](const Axis& a, int64_t p0, int n, std::vector<int>& used) {
        std::vector<Tap> t(static_cast<size_t>(n));
        for (int i = 0; i < n; ++i) {
            const double X = a.position(p0 + i);
            Tap& k = t[static_cast<size_t>(i)];
            k.inside = a.inside(X);
            const double f = std::floor(X);
            k.weight = X - f;
            k.first = std::clamp(static_cast<int>(f), 0, a.input - 1);
            k.second = std::clamp(static_cast<int>(f) + 1, 0, a.input - 1);
            if (k.inside) {
                used.push_back(k.first);
                used.push_back(k.second);
            }
        }
        std::sort(used.begin(), used.end());
        used.erase(std::unique(used.begin(), used.end()), used.end());
        return t;
    };
    std::vector<int> columns, rows;
    const std::vector<Tap> tx = taps(ax, x0, w, columns), ty = taps(ay, y0, h, rows);
    if (columns.empty() || rows.empty()) {
        return out;
    }
    const auto indexOf = [](const std::vector<int>& v, int x) {
        return static_cast<size_t>(std::lower_bound(v.begin(), v.end(), x) - v.begin());
    };
    std::vector<uint16_t> values(columns.size() * rows.size() * static_cast<size_t>(channels_));
    source_.readUInt16At(columns, rows, 0, channels_, values.data()); // as sample() reads its window
    const size_t across = columns.size();
    std::vector<double> top(static_cast<size_t>(w) * channels_), bottom(top.size());
    const auto horizontal = [&](int row, std::vector<double>& into) {
        const size_t r = indexOf(rows, row);
        for (int i = 0; i < w; ++i) {
            const Tap& k = tx[static_cast<size_t>(i)];
            if (!k.inside) {
                continue;
            }
            const size_t a = (r * across + indexOf(columns, k.first)) * channels_;
            const size_t b = (r * across + indexOf(columns, k.second)) * channels_;
            for (int ch = 0; ch < channels_; ++ch) {
                const double v = values[a + static_cast<size_t>(ch)];
                into[static_cast<size_t>(i) * channels_ + ch] = v + (static_cast<double>(values[b + static_cast<size_t>(ch)]) - v) * k.weight;
            }
        }
    };
    int insideEnd = 0;
    for (int i = 0; i < w; ++i) {
        insideEnd = tx[static_cast<size_t>(i)].inside ? i + 1 : insideEnd;
    }
    for (int j = 0; j < h; ++j) {
        const Tap& k = ty[static_cast<size_t>(j)];
        if (!k.inside) {
            continue;
        }
        horizontal(k.first, top);
        horizontal(k.second, bottom);
        combineRows(top.data(), bottom.data(), k.weight, sixteen_ ? 65535.0 : 255.0,
                    static_cast<size_t>(insideEnd) * channels_, out.at(0, j));
    }
    return out;
}

} // namespace pyramid
