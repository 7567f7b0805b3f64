#include "libpyramid/encode/dem/dem_sampling.hpp"

#include <algorithm>
#include <cmath>

#include "formats/error.hpp"
#include "libpyramid/input/height_samples.hpp"
#include "libpyramid/input/nodata_text.hpp"
#include "libpyramid/support/row_pair_cache.hpp"
#include "formats/vector_clones.hpp"

namespace pyramid {

NodataChoice parseNodataChoice(const std::string& text, const std::string& option) {
    NodataChoice choice;
    if (text.empty()) {
        return choice;
    }
    if (text == "none") {
        choice.ignoreDeclared = true;
    } else if (const std::optional<double> v = tryParseNodataText(text)) {
        choice.value = *v;
    } else {
        fail(option, "'" + text + "' is not a number, nan, inf, -inf or none");
    }
    return choice;
}

DemGeometry makeDemGeometry(int width, int height, int64_t N, bool stretch, const std::string& where) {
    if (width < 2 || height < 2) {
        fail(where, "input of " + std::to_string(width) + "x" + std::to_string(height) +
                        " samples is too small (2x2 at least)");
    }
    DemGeometry g;
    g.N = N;
    g.width = width;
    g.height = height;
    if (stretch) {
        g.lx = width - 1;
        g.ly = height - 1;
    } else {
        g.lx = g.ly = std::max(width, height) - 1;
    }
    return g;
}

std::string DemGeometry::describe() const {
    if (exact()) {
        return "input samples are the finest grid samples (no resampling)";
    }
    if (lx == N && ly == N && width != height) {
        // The longer side spans the root quad sample for sample: x = X, y = N - Y exactly.
        return "input samples are finest grid samples (no resampling); aspect ratio kept, input at the north-west "
               "corner of the " + std::to_string(N + 1) + "x" + std::to_string(N + 1) +
               " finest grid, the rest filled as nodata";
    }
    std::string s = "bilinear resampling of " + std::to_string(width) + "x" + std::to_string(height) +
                    " input samples onto " + std::to_string(N + 1) + "x" + std::to_string(N + 1) + " finest samples";
    if (lx == ly && (width != height)) {
        s += "; aspect ratio kept, input at the north-west corner, the rest filled as nodata";
    } else if (lx != ly || width != height) {
        s += "; width and height stretched independently";
    }
    return s;
}

DemSampler::DemSampler(const RasterSource& source, const DemGeometry& geometry, int band, std::optional<double> nodata,
                       int64_t rootIntervals)
    : rootIntervals_(rootIntervals), source_(source), geometry_(geometry), band_(band), nodata_(nodata) {
    if (band < 0 || band >= source.info().channels) {
        fail(source.path(), "no band " + std::to_string(band + 1) + " (the input has " +
                                std::to_string(source.info().channels) + ")");
    }
}

namespace {

// One axis of the mapping: input index and weight of the next sample for each grid position.
struct AxisTap {
    int64_t index = 0;   // first input sample
    double frac = 0.0;   // weight of index + 1
    bool inside = true;  // false beyond the input
};

std::vector<AxisTap> axisTaps(int64_t first, int64_t stride, int64_t count, bool flip, int64_t N, int64_t L,
                              int extent) {
    std::vector<AxisTap> taps(static_cast<size_t>(count));
    for (int64_t k = 0; k < count; ++k) {
        int64_t p = first + k * stride;
        if (flip) {
            p = N - p;
        }
        // Exact rational position p * L / N: integer part and remainder.
        const int64_t num = p * L;
        AxisTap& t = taps[static_cast<size_t>(k)];
        t.index = num / N;
        t.frac = static_cast<double>(num % N) / static_cast<double>(N);
        t.inside = t.index < extent - 1 || (t.index == extent - 1 && t.frac == 0.0);
        if (t.index >= extent - 1) {
            t.index = std::min<int64_t>(t.index, extent - 1);
        }
    }
    return taps;
}

// Bilinear interpolation of window rows without nodata, separably: each input row the taps touch
// is interpolated horizontally once, at every grid column (`top` and `bottom` of the per-sample
// formula below, with the same operations), and each grid row then combines its two input rows.
// Columns beyond the input stay nodata. Taps of weight 0 read their first sample twice, whose
// difference is then 0: v + 0 * f = v, the sample itself. `heightRows`: null when every row of
// the window holds only heights; else one flag per window row, and only the grid rows whose
// input rows are all flagged are computed here (the others are left to the per-tap loop).
PYRAMID_VECTOR_CLONES
void sampleCleanRows(const std::vector<AxisTap>& xs, const std::vector<AxisTap>& ys, const float* window,
                     int64_t cx0, int64_t ry0, int64_t ww, const uint8_t* heightRows, SourceGrid& grid) {
    const size_t nx = static_cast<size_t>(grid.nx);
    std::vector<size_t> first(nx), second(nx);
    std::vector<double> weight(nx);
    std::vector<uint8_t> inside(nx);
    for (size_t i = 0; i < nx; ++i) {
        const AxisTap& t = xs[i];
        inside[i] = t.inside ? 1 : 0;
        first[i] = t.inside ? static_cast<size_t>(t.index - cx0) : 0;
        second[i] = t.inside && t.frac > 0.0 ? first[i] + 1 : first[i];
        weight[i] = t.inside ? t.frac : 0.0;
    }
    // Input row r interpolated along x at every grid column.
    const auto horizontal = [&](int64_t r, double* __restrict out) {
        const float* __restrict line = window + (r - ry0) * ww;
        for (size_t i = 0; i < nx; ++i) {
            const double v0 = line[first[i]], v1 = line[second[i]];
            out[i] = v0 + (v1 - v0) * weight[i];
        }
    };
    RowPairCache rows(nx);
    for (int64_t j = 0; j < grid.ny; ++j) {
        const AxisTap& ty = ys[static_cast<size_t>(j)];
        if (!ty.inside) {
            continue;
        }
        const bool fy = ty.frac > 0.0;
        if (heightRows != nullptr &&
            (heightRows[ty.index - ry0] == 0 || (fy && heightRows[ty.index + 1 - ry0] == 0))) {
            continue;
        }
        const double* top = rows.row(ty.index, fy ? ty.index + 1 : -1, horizontal);
        float* __restrict height = grid.height.data() + j * grid.nx;
        uint8_t* __restrict valid = grid.valid.data() + j * grid.nx;
        if (fy) {
            const double* bottom = rows.row(ty.index + 1, ty.index, horizontal);
            const double f = ty.frac;
            for (size_t i = 0; i < nx; ++i) {
                const double h = top[i] + (bottom[i] - top[i]) * f;
                height[i] = inside[i] != 0 ? static_cast<float>(h) : 0.0f;
            }
        } else {
            for (size_t i = 0; i < nx; ++i) {
                height[i] = inside[i] != 0 ? static_cast<float>(top[i]) : 0.0f;
            }
        }
        std::copy(inside.begin(), inside.end(), valid);
    }
}

// The heights at taps xs, ys (their indices into `window`: ww samples a row, its sample (0, 0)
// input sample (cx0, ry0)), into grid. `columns` and `rows`, when given, are the input's columns
// and rows of the window's (a window of samples picked at their crossings), for messages.
void interpolate(const std::vector<AxisTap>& xs, const std::vector<AxisTap>& ys, const std::vector<float>& window,
                 int64_t cx0, int64_t ry0, int64_t ww, SourceGrid& grid, const std::optional<double>& nodata,
                 const RasterSource& source, int band, const std::vector<int>* columns, const std::vector<int>* rows) {
    const HeightSamples samples(nodata);
    // Most windows hold only heights, and most rows of many others (a void, a band of nodata
    // along the north or south): one scan finds the rows that do, whose grid rows are then
    // interpolated without a test per tap (the same values, the same arithmetic); the per-tap
    // loop below takes the rest. Rows of heights hold no sample the loop could fail on, so an
    // error is still the first one in the loop's order.
    const auto wh = static_cast<int64_t>(window.size()) / ww;
    std::vector<uint8_t> heightRows(static_cast<size_t>(wh));
    bool clean = true;
    for (int64_t r = 0; r < wh; ++r) {
        const float* line = window.data() + r * ww;
        const bool heights = std::all_of(line, line + ww, [&](float s) { return samples.isHeight(s); });
        heightRows[static_cast<size_t>(r)] = heights ? 1 : 0;
        clean = clean && heights;
    }
    sampleCleanRows(xs, ys, window.data(), cx0, ry0, ww, clean ? nullptr : heightRows.data(), grid);
    if (clean) {
        return;
    }
    // Reads input (column c, row r) from `line`, the window's row r: false for nodata; NaN or
    // infinity that is not nodata is an error (height_samples.hpp).
    auto at = [&](const float* line, int64_t c, int64_t r, double& v) {
        const float s = line[c - cx0];
        const int64_t ic = columns ? (*columns)[static_cast<size_t>(c)] : c;
        const int64_t ir = rows ? (*rows)[static_cast<size_t>(r)] : r;
        if (!samples.usable(s, source, ic, ir, band)) {
            return false;
        }
        v = s;
        return true;
    };
    float* outHeight = grid.height.data();
    uint8_t* outValid = grid.valid.data();
    for (int64_t j = 0; j < grid.ny; ++j) {
        const AxisTap& ty = ys[static_cast<size_t>(j)];
        if (!ty.inside) {
            continue;
        }
        // The window's rows ty.index and ty.index + 1 (the latter only read when fy).
        const float* line0 = window.data() + (ty.index - ry0) * ww;
        const float* line1 = line0 + ww;
        const bool fy = ty.frac > 0.0;
        if (heightRows[static_cast<size_t>(ty.index - ry0)] != 0 &&
            (!fy || heightRows[static_cast<size_t>(ty.index + 1 - ry0)] != 0)) {
            continue; // sampleCleanRows's
        }
        float* height = outHeight + j * grid.nx;
        uint8_t* valid = outValid + j * grid.nx;
        for (int64_t i = 0; i < grid.nx; ++i) {
            const AxisTap& tx = xs[static_cast<size_t>(i)];
            if (!tx.inside) {
                continue;
            }
            const bool fx = tx.frac > 0.0;
            double v00 = 0, v10 = 0, v01 = 0, v11 = 0;
            bool ok = at(line0, tx.index, ty.index, v00);
            if (ok && fx) {
                ok = at(line0, tx.index + 1, ty.index, v10);
            }
            if (ok && fy) {
                ok = at(line1, tx.index, ty.index + 1, v01);
                if (ok && fx) {
                    ok = at(line1, tx.index + 1, ty.index + 1, v11);
                }
            }
            if (!ok) {
                continue;
            }
            double h = v00;
            if (fx || fy) {
                const double top = v00 + (v10 - v00) * tx.frac;
                const double bottom = v01 + (v11 - v01) * tx.frac;
                h = top + (bottom - top) * ty.frac;
            }
            height[i] = static_cast<float>(h);
            valid[i] = 1;
        }
    }
}


} // namespace

void DemSampler::sample(SourceGrid& grid) const {
    const DemGeometry& g = geometry_;
    std::vector<AxisTap> xs = axisTaps(grid.x0, grid.stride, grid.nx, false, g.N, g.lx, g.width);
    std::vector<AxisTap> ys = axisTaps(grid.y0, grid.stride, grid.ny, true, g.N, g.ly, g.height);
    const size_t count = static_cast<size_t>(grid.nx) * static_cast<size_t>(grid.ny);
    grid.height.assign(count, 0.0f);
    grid.valid.assign(count, 0);
    if (grid.stride > 1) {
        // Strided positions (a coarse level's): only the input samples their taps read, at the
        // crossings of those columns and rows, rather than the whole window (a planar mosaic
        // computes each of its samples).
        const auto needed = [](std::vector<AxisTap>& taps, int extent) {
            std::vector<int> at;
            for (const AxisTap& t : taps) {
                if (t.inside) {
                    at.push_back(static_cast<int>(t.index));
                    if (t.frac > 0.0 && t.index + 1 < extent) {
                        at.push_back(static_cast<int>(t.index + 1));
                    }
                }
            }
            std::sort(at.begin(), at.end());
            at.erase(std::unique(at.begin(), at.end()), at.end());
            for (AxisTap& t : taps) { // indices into the picked samples: index + 1 follows index
                if (t.inside) {
                    t.index = std::lower_bound(at.begin(), at.end(), static_cast<int>(t.index)) - at.begin();
                }
            }
            return at;
        };
        const std::vector<int> columns = needed(xs, g.width), rows = needed(ys, g.height);
        if (columns.empty() || rows.empty()) {
            return; // entirely outside the input: all nodata
        }
        const auto ww = static_cast<int64_t>(columns.size());
        std::vector<float> window(columns.size() * rows.size());
        source_.readFloatAt(columns, rows, band_, window.data());
        interpolate(xs, ys, window, 0, 0, ww, grid, nodata_, source_, band_, &columns, &rows);
        return;
    }
    // The input window these taps touch.
    int64_t cx0 = g.width, cx1 = -1, ry0 = g.height, ry1 = -1;
    for (const AxisTap& t : xs) {
        if (t.inside) {
            cx0 = std::min(cx0, t.index);
            cx1 = std::max(cx1, std::min<int64_t>(t.index + (t.frac > 0.0 ? 1 : 0), g.width - 1));
        }
    }
    for (const AxisTap& t : ys) {
        if (t.inside) {
            ry0 = std::min(ry0, t.index);
            ry1 = std::max(ry1, std::min<int64_t>(t.index + (t.frac > 0.0 ? 1 : 0), g.height - 1));
        }
    }
    if (cx1 < cx0 || ry1 < ry0) {
        return; // entirely outside the input: all nodata
    }
    const int64_t ww = cx1 - cx0 + 1;
    const int64_t wh = ry1 - ry0 + 1;
    std::vector<float> window(static_cast<size_t>(ww * wh));
    source_.readFloat(static_cast<int>(cx0), static_cast<int>(ry0), static_cast<int>(cx1 + 1),
                      static_cast<int>(ry1 + 1), band_, window.data());
    interpolate(xs, ys, window, cx0, ry0, ww, grid, nodata_, source_, band_, nullptr, nullptr);
}

bool DemSampler::mayHaveHeights(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    return partMeets(-1, x0, y0, x1, y1);
}

bool DemSampler::mayHaveHeightsAt(int level, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    return partMeets(rootIntervals_ > 0 ? level : -1, x0, y0, x1, y1);
}

bool DemSampler::severalLevels() const {
    const std::vector<RasterPart>& parts = source_.info().parts;
    return rootIntervals_ > 0 && std::any_of(parts.begin(), parts.end(), [&](const RasterPart& p) {
               return std::fabs(p.pixelsPerSample - parts.front().pixelsPerSample) > 1e-9 * parts.front().pixelsPerSample;
           });
}

bool DemSampler::partMeets(int level, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    const std::vector<RasterPart>& parts = source_.info().parts;
    if (parts.empty()) {
        return true;
    }
    const DemGeometry& g = geometry_;
    // The input pixels the positions' interpolation reads: X = x lx / N, Y = (N - y) ly / N,
    // and the pixel after each.
    const auto floorDiv = [](int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
    const int64_t cx0 = floorDiv(x0 * g.lx, g.N), cx1 = floorDiv(x1 * g.lx, g.N) + 1;
    const int64_t ry0 = floorDiv((g.N - y1) * g.ly, g.N), ry1 = floorDiv((g.N - y0) * g.ly, g.N) + 1;
    // Level l has rootIntervals << l intervals across the root quad, which spans lx input pixels.
    const double coarsest = level > 0 ? std::ldexp(static_cast<double>(rootIntervals_), level - 1) : 0.0;
    for (const RasterPart& p : parts) {
        if (level > 0 && !(static_cast<double>(g.lx) / p.pixelsPerSample > coarsest)) {
            continue; // a part too coarse for this level
        }
        if (cx0 < p.x1 && p.x0 <= cx1 && ry0 < p.y1 && p.y0 <= ry1) {
            return true;
        }
    }
    return false;
}

} // namespace pyramid
