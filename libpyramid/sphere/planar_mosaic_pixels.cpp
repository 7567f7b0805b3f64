#include "libpyramid/sphere/planar_mosaic_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <type_traits>
#include <utility>

#include "libpyramid/input/colour_coverage.hpp"
#include "libpyramid/sphere/map_mosaic.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/support/pixel_copy.hpp"

namespace pyramid {

namespace {

// How a group on the grid is read: one channel of numbers, a sample counting where it is not
// the group's nodata (height_samples.hpp's rule)...
struct FloatRead {
    int channel;
    size_t stored(const RasterSource&) const { return 1; }
    size_t first() const { return 0; }
    void read(const RasterSource& s, int a0, int b0, int a1, int b1, float* to) const {
        s.readFloat(a0, b0, a1, b1, channel, to);
    }
    void readAt(const RasterSource& s, const std::vector<int>& c, const std::vector<int>& r, float* to) const {
        s.readFloatAt(c, r, channel, to);
    }
    static auto holds(const RasterSource& s) {
        return [nodata = s.info().nodata](const float* v) { return !isNodata(*v, nodata); };
    }
};

// ... or colours, every channel read (and the file's mask) and a pixel counting by the whole pixel
// (colour_coverage.hpp), the channels from `first` on given.
struct ColourRead {
    int from;
    static int all(const RasterSource& s) { return ColourCoverage(s.info()).stored(); }
    size_t stored(const RasterSource& s) const { return static_cast<size_t>(all(s)); }
    size_t first() const { return static_cast<size_t>(from); }
    void read(const RasterSource& s, int a0, int b0, int a1, int b1, uint16_t* to) const {
        s.readUInt16(a0, b0, a1, b1, 0, all(s), to);
    }
    void readAt(const RasterSource& s, const std::vector<int>& c, const std::vector<int>& r, uint16_t* to) const {
        s.readUInt16At(c, r, 0, all(s), to);
    }
    static auto holds(const RasterSource& s) {
        return [coverage = ColourCoverage(s.info())](const uint16_t* pixel) { return coverage.has(pixel); };
    }
};

class ResampledPixels final : public RasterPixels {
public:
    // `own`: the groups on the grid (the finest group in the CRS and any other on its grid), in
    // priority order; `x0`, `y0`: the grid's pixel (0, 0) in the mosaic; `grid`: the CRS and
    // transform of the grid's pixel coordinates (the mosaic's, shifted by (x0, y0)).
    ResampledPixels(std::vector<std::vector<std::string>> groups, std::vector<OwnGroup> own, int x0, int y0,
                    RasterInfo info, PlanetBody body, int cacheMegabytes, const Georeference& grid, int64_t gridWidth,
                    int64_t gridHeight, const std::string& gridName)
        : groups_(std::move(groups)), own_(std::move(own)), x0_(x0), y0_(y0), info_(std::move(info)),
          body_(std::move(body)), cacheMegabytes_(cacheMegabytes), grid_(grid, gridWidth, gridHeight, gridName) {}

    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const override {
        const float gap = info_.nodata ? static_cast<float>(*info_.nodata) : 0.0f;
        read<float>(x0, y0, x1, y1, 1, gap, out, FloatRead{channel}, mosaic(SampleRead::Float), channel);
    }

    // Only the samples asked for: each group on the grid's own where it has them, the others at
    // those pixels' centres.
    void readFloatAt(const std::vector<int>& columns, const std::vector<int>& rows, int channel,
                     float* out) const override {
        const float gap = info_.nodata ? static_cast<float>(*info_.nodata) : 0.0f;
        readAt<float>(columns, rows, 1, gap, out, FloatRead{channel}, mosaic(SampleRead::Float), channel);
    }

    void readUInt16At(const std::vector<int>& columns, const std::vector<int>& rows, int c0, int c1,
                      uint16_t* out) const override {
        readAt<uint16_t>(columns, rows, c1 - c0, 0, out, ColourRead{c0}, mosaic(SampleRead::UInt16), c0);
    }

    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const override {
        read<uint16_t>(x0, y0, x1, y1, c1 - c0, 0, out, ColourRead{c0}, mosaic(SampleRead::UInt16), c0);
    }

private:
    // The groups as one map, channels [0, channels), read as `read`: made at its first use.
    const MapMosaic& mosaic(SampleRead read) const {
        const size_t k = read == SampleRead::Float ? 0 : 1;
        std::call_once(once_[k], [&] {
            mosaics_[k] = std::make_unique<MapMosaic>(
                groups_, body_, 0, info_.channels, read,
                [](const RasterInfo& info, const std::string&) { return info.nodata; }, cacheMegabytes_);
        });
        return *mosaics_[k];
    }

    // Values at the crossings of `columns` and `rows`, `values` per sample: the first group on the
    // grid with its own there (`how`: FloatRead, ColourRead), else the mosaic's at the pixel
    // centre, else `gap`.
    template <typename T, typename How>
    void readAt(const std::vector<int>& columns, const std::vector<int>& rows, int values, T gap, T* out,
                const How& how, const MapMosaic& map, int firstChannel) const {
        const size_t width = columns.size();
        const auto n = static_cast<size_t>(values);
        std::fill(out, out + width * rows.size() * n, gap);
        std::vector<uint8_t> done(width * rows.size(), 0);
        std::vector<T> part;
        for (const OwnGroup& g : own_) {
            const RasterSource& s = *g.source;
            std::vector<int> cols, rws;
            std::vector<size_t> ci, rj; // their places in `columns` and `rows`
            for (size_t i = 0; i < width; ++i) {
                const int64_t c = columns[i] - g.x;
                if (c >= 0 && c < s.info().width) {
                    cols.push_back(static_cast<int>(c));
                    ci.push_back(i);
                }
            }
            for (size_t j = 0; j < rows.size(); ++j) {
                const int64_t r = rows[j] - g.y;
                if (r >= 0 && r < s.info().height) {
                    rws.push_back(static_cast<int>(r));
                    rj.push_back(j);
                }
            }
            if (cols.empty() || rws.empty()) {
                continue;
            }
            const size_t all = how.stored(s);
            part.resize(cols.size() * rws.size() * all);
            how.readAt(s, cols, rws, part.data());
            const auto holds = How::holds(s);
            for (size_t b = 0; b < rws.size(); ++b) {
                for (size_t a = 0; a < cols.size(); ++a) {
                    const size_t k = rj[b] * width + ci[a];
                    const T* from = &part[(b * cols.size() + a) * all];
                    if (done[k] || !holds(from)) {
                        continue;
                    }
                    copyPixel(from + how.first(), out + k * n, n);
                    done[k] = 1;
                }
            }
        }
        sampleLeft(
            done,
            [&](size_t k) {
                return std::pair{static_cast<double>(columns[k % width] - x0_) + 0.5,
                                 static_cast<double>(rows[k / width] - y0_) + 0.5};
            },
            map, firstChannel, n, out);
    }

    // Values (x, y) of the window, `values` per pixel: the first group on the grid with its own
    // there (`how`), else the mosaic's at the pixel centre, else `gap`.
    template <typename T, typename How>
    void read(int x0, int y0, int x1, int y1, int values, T gap, T* out, const How& how, const MapMosaic& map,
              int firstChannel) const {
        const size_t width = static_cast<size_t>(x1 - x0);
        const auto n = static_cast<size_t>(values);
        std::fill(out, out + width * static_cast<size_t>(y1 - y0) * n, gap);
        std::vector<uint8_t> done(width * static_cast<size_t>(y1 - y0), 0);
        // Each group's pixels on the grid: the window within it, shifted by its place in the mosaic.
        std::vector<T> part;
        for (const OwnGroup& g : own_) {
            const RasterSource& s = *g.source;
            const int fx0 = static_cast<int>(std::max<int64_t>(x0 - g.x, 0));
            const int fx1 = static_cast<int>(std::min<int64_t>(x1 - g.x, s.info().width));
            const int fy0 = static_cast<int>(std::max<int64_t>(y0 - g.y, 0));
            const int fy1 = static_cast<int>(std::min<int64_t>(y1 - g.y, s.info().height));
            if (fx0 >= fx1 || fy0 >= fy1) {
                continue;
            }
            const auto partWidth = static_cast<size_t>(fx1 - fx0);
            const size_t all = how.stored(s);
            part.resize(partWidth * static_cast<size_t>(fy1 - fy0) * all);
            how.read(s, fx0, fy0, fx1, fy1, part.data());
            const auto holds = How::holds(s);
            for (int y = fy0; y < fy1; ++y) {
                for (int x = fx0; x < fx1; ++x) {
                    const size_t k = static_cast<size_t>(y + g.y - y0) * width + static_cast<size_t>(x + g.x - x0);
                    const size_t at = static_cast<size_t>(y - fy0) * partWidth + static_cast<size_t>(x - fx0);
                    const T* from = &part[at * all];
                    if (done[k] || !holds(from)) {
                        continue;
                    }
                    copyPixel(from + how.first(), out + k * n, n);
                    done[k] = 1;
                }
            }
        }
        // The others at the centres of the pixels left.
        sampleLeft(
            done,
            [&](size_t k) {
                return std::pair{static_cast<double>(x0 - x0_) + static_cast<double>(k % width) + 0.5,
                                 static_cast<double>(y0 - y0_) + static_cast<double>(k / width) + 0.5};
            },
            map, firstChannel, n, out);
    }

    // The values of `map` at the centres of the pixels not `done` (pixel k's centre at
    // centre(k) in the grid's pixel coordinates): `values` channels from `firstChannel` into
    // out[k * values ...], where the map has a value.
    template <typename T, typename Centre>
    void sampleLeft(const std::vector<uint8_t>& done, const Centre& centre, const MapMosaic& map, int firstChannel,
                    size_t values, T* out) const {
        std::vector<size_t> left;
        std::vector<GeodeticPoint> points;
        for (size_t k = 0; k < done.size(); ++k) {
            if (!done[k]) {
                left.push_back(k);
                const auto [col, row] = centre(k);
                points.push_back(grid_.geodeticOf(col, row));
            }
        }
        if (left.empty()) {
            return;
        }
        const auto channels = static_cast<size_t>(map.channels());
        std::vector<float> sampled(points.size() * channels);
        std::vector<uint8_t> valid(points.size());
        map.sample(points.data(), points.size(), sampled.data(), valid.data());
        for (size_t i = 0; i < left.size(); ++i) {
            if (!valid[i]) {
                continue;
            }
            for (size_t c = 0; c < values; ++c) {
                const float v = sampled[i * channels + static_cast<size_t>(firstChannel) + c];
                out[left[i] * values + c] = static_cast<T>(std::is_integral_v<T> ? std::lround(v) : v);
            }
        }
    }

    std::vector<std::vector<std::string>> groups_;
    std::vector<OwnGroup> own_; // empty when the finest group is not on the grid
    int x0_, y0_; // the grid's pixel (0, 0) in the mosaic
    RasterInfo info_;
    PlanetBody body_;
    int cacheMegabytes_;
    GeoreferencedMap grid_;
    mutable std::once_flag once_[2];
    mutable std::unique_ptr<MapMosaic> mosaics_[2];
};

// A file whose axis-aligned transform runs its rows north (south-up) or its columns west, read
// north-up: the same samples mirrored, under the transform of the same ground with t[1] > 0
// and t[5] < 0 (exactly: no resampling).
class NorthUpPixels final : public RasterPixels {
public:
    NorthUpPixels(std::unique_ptr<RasterSource> file, bool mirrorX, bool mirrorY)
        : file_(std::move(file)), mirrorX_(mirrorX), mirrorY_(mirrorY) {}

    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const override {
        read(x0, y0, x1, y1, 1, out,
             [&](int a0, int b0, int a1, int b1) { file_->readFloat(a0, b0, a1, b1, channel, out); });
    }

    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const override {
        read(x0, y0, x1, y1, c1 - c0, out,
             [&](int a0, int b0, int a1, int b1) { file_->readUInt16(a0, b0, a1, b1, c0, c1, out); });
    }

    const RasterSource* placeOf(int& x, int& y) const override {
        x = mirrorX_ ? file_->info().width - 1 - x : x;
        y = mirrorY_ ? file_->info().height - 1 - y : y;
        return file_.get();
    }

private:
    // The file's window mirroring (x0, y0)-(x1, y1) read by `fileRead` into `out`, then turned round.
    template <typename T, typename FileRead>
    void read(int x0, int y0, int x1, int y1, int values, T* out, FileRead fileRead) const {
        const int W = file_->info().width, H = file_->info().height;
        fileRead(mirrorX_ ? W - x1 : x0, mirrorY_ ? H - y1 : y0, mirrorX_ ? W - x0 : x1, mirrorY_ ? H - y0 : y1);
        const auto n = static_cast<size_t>(values), row = static_cast<size_t>(x1 - x0) * n;
        const auto rows = static_cast<size_t>(y1 - y0);
        if (mirrorY_) {
            for (size_t r = 0; r < rows / 2; ++r) {
                std::swap_ranges(out + r * row, out + (r + 1) * row, out + (rows - 1 - r) * row);
            }
        }
        if (mirrorX_) {
            for (T* line = out; line != out + rows * row; line += row) {
                for (size_t a = 0, b = row - n; a < b; a += n, b -= n) {
                    std::swap_ranges(line + a, line + a + n, line + b);
                }
            }
        }
    }

    std::unique_ptr<RasterSource> file_;
    bool mirrorX_, mirrorY_;
};

} // namespace

std::shared_ptr<const RasterPixels> resampledPixels(std::vector<std::vector<std::string>> groups,
                                                    std::vector<OwnGroup> own, int x0, int y0, RasterInfo info,
                                                    PlanetBody body, int cacheMegabytes, const Georeference& grid,
                                                    int64_t gridWidth, int64_t gridHeight, const std::string& gridName) {
    return std::make_shared<ResampledPixels>(std::move(groups), std::move(own), x0, y0, std::move(info),
                                             std::move(body), cacheMegabytes, grid, gridWidth, gridHeight, gridName);
}

// The files of one grid as one raster (RasterSource::openMosaic), north-up: a planar pyramid's
// tiles put north at the top whatever way the file's rows run (NorthUpPixels).
std::unique_ptr<RasterSource> openNorthUp(const std::vector<std::string>& group, int cacheMegabytes) {
    std::unique_ptr<RasterSource> source = RasterSource::openMosaic(group, cacheMegabytes);
    const RasterInfo& info = source->info();
    if (!info.georeference || !info.georeference->problem.empty() || !info.georeference->axisAligned()) {
        return source; // placed by no transform, or rotated (its sidecar says so)
    }
    const auto& t = info.georeference->pixelToCrs;
    const bool mirrorX = t[1] < 0.0, mirrorY = t[5] > 0.0;
    if (!mirrorX && !mirrorY) {
        return source;
    }
    RasterInfo northUp = info;
    auto& u = northUp.georeference->pixelToCrs;
    if (mirrorX) {
        u[0] += t[1] * info.width;
        u[1] = -t[1];
    }
    if (mirrorY) {
        u[3] += t[5] * info.height;
        u[5] = -t[5];
    }
    const std::string name = source->path();
    auto pixels = std::make_shared<NorthUpPixels>(std::move(source), mirrorX, mirrorY);
    return RasterSource::fromPixels(name, northUp, std::move(pixels));
}

} // namespace pyramid
