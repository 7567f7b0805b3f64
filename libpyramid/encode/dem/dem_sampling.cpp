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

DemSampler::DemSampler(const RasterSource& source, const DemGeometry& geometry, int band, std::optional<double> nodata)
    : source_(source), geometry_(geometry), band_(band), nodata_(nodata) {
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

// Bilinear interpolation of a window without nodata, separably: each input row the taps touch
// is interpolated horizontally once, at every grid column (`top` and `bottom` of the per-sample
// formula below, with the same operations), and each grid row then combines its two input rows.
// Columns beyond the input stay nodata. Taps of weight 0 read their first sample twice, whose
// difference is then 0: v + 0 * f = v, the sample itself.
PYRAMID_VECTOR_CLONES
void sampleCleanWindow(const std::vector<AxisTap>& xs, const std::vector<AxisTap>& ys, const float* window,
                       int64_t cx0, int64_t ry0, int64_t ww, SourceGrid& grid) {
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

} // namespace

void DemSampler::sample(SourceGrid& grid) const {
    if (grid.stride > 1 && grid.ny > 1) {
        // Sparse rows: read two input rows per grid row rather than the whole window.
        const size_t count = static_cast<size_t>(grid.nx) * static_cast<size_t>(grid.ny);
        std::vector<float> height(count);
        std::vector<uint8_t> valid(count);
        for (int64_t j = 0; j < grid.ny; ++j) {
            SourceGrid row;
            row.x0 = grid.x0;
            row.y0 = grid.y0 + j * grid.stride;
            row.stride = grid.stride;
            row.nx = grid.nx;
            row.ny = 1;
            sample(row);
            std::copy(row.height.begin(), row.height.end(), height.begin() + j * grid.nx);
            std::copy(row.valid.begin(), row.valid.end(), valid.begin() + j * grid.nx);
        }
        grid.height = std::move(height);
        grid.valid = std::move(valid);
        return;
    }
    const DemGeometry& g = geometry_;
    const std::vector<AxisTap> xs = axisTaps(grid.x0, grid.stride, grid.nx, false, g.N, g.lx, g.width);
    const std::vector<AxisTap> ys = axisTaps(grid.y0, grid.stride, grid.ny, true, g.N, g.ly, g.height);
    const size_t count = static_cast<size_t>(grid.nx) * static_cast<size_t>(grid.ny);
    grid.height.assign(count, 0.0f);
    grid.valid.assign(count, 0);
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
    const HeightSamples samples(nodata_);
    // Most windows hold only heights: one scan finds out, and the interpolation below then reads
    // the input without a test per tap (the same values, the same arithmetic).
    const bool clean = std::all_of(window.begin(), window.end(), [&](float s) { return samples.isHeight(s); });
    if (clean) {
        sampleCleanWindow(xs, ys, window.data(), cx0, ry0, ww, grid);
        return;
    }
    // Reads input (column c, row r) from `line`, the window's row r: false for nodata; NaN or
    // infinity that is not nodata is an error (height_samples.hpp).
    auto at = [&](const float* line, int64_t c, int64_t r, double& v) {
        const float s = line[c - cx0];
        if (!samples.usable(s, source_, c, r, band_)) {
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

} // namespace pyramid
