#include "libpyramid/sphere/planar_mosaic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <optional>
#include <type_traits>

#include "formats/error.hpp"
#include "libpyramid/input/raster_mosaic.hpp"
#include "libpyramid/sphere/map_mosaic.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

// The ground size of the finest pixels of a group: the shorter of a pixel's two sides at the
// group's centre, in metres (a geographic pixel's east-west side shrinks with the latitude's cosine).
double groundSide(const Georeference& g, int width, int height, const GeoreferencedMap& map) {
    const auto& t = g.pixelToCrs;
    const double across = std::hypot(t[1], t[4]), down = std::hypot(t[2], t[5]);
    if (g.projected) {
        return std::min(across, down) * g.unitInMetres;
    }
    const double metresPerUnit = g.unitInDegrees * g.semiMajorAxis * std::numbers::pi / 180.0;
    const double latitude = map.geodeticOf(width / 2.0, height / 2.0).latitude;
    return std::min(across * std::cos(latitude * std::numbers::pi / 180.0), down) * metresPerUnit;
}

// A group whose own samples the mosaic takes as they are, with its pixel (0, 0) in the mosaic.
struct OwnGroup {
    std::unique_ptr<RasterSource> source;
    int64_t x = 0, y = 0;
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
        read<float>(
            x0, y0, x1, y1, 1, gap, out,
            [&](const RasterSource& s, int a0, int b0, int a1, int b1, float* to) {
                s.readFloat(a0, b0, a1, b1, channel, to);
            },
            [](const RasterSource& s, float v) { return !isNodata(v, s.info().nodata); }, mosaic(SampleRead::Float),
            channel);
    }

    // Only the samples asked for: each group on the grid's own where it has them, the others at
    // those pixels' centres.
    void readFloatAt(const std::vector<int>& columns, const std::vector<int>& rows, int channel,
                     float* out) const override {
        const float gap = info_.nodata ? static_cast<float>(*info_.nodata) : 0.0f;
        const size_t width = columns.size();
        std::fill(out, out + width * rows.size(), gap);
        std::vector<uint8_t> done(width * rows.size(), 0);
        std::vector<float> part;
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
            part.resize(cols.size() * rws.size());
            s.readFloatAt(cols, rws, channel, part.data());
            for (size_t b = 0; b < rws.size(); ++b) {
                for (size_t a = 0; a < cols.size(); ++a) {
                    const size_t k = rj[b] * width + ci[a];
                    const float v = part[b * cols.size() + a];
                    if (!done[k] && !isNodata(v, s.info().nodata)) {
                        out[k] = v;
                        done[k] = 1;
                    }
                }
            }
        }
        sampleLeft(
            done,
            [&](size_t k) {
                return std::pair{static_cast<double>(columns[k % width] - x0_) + 0.5,
                                 static_cast<double>(rows[k / width] - y0_) + 0.5};
            },
            mosaic(SampleRead::Float), channel, 1, out);
    }

    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const override {
        read<uint16_t>(
            x0, y0, x1, y1, c1 - c0, 0, out,
            [&](const RasterSource& s, int a0, int b0, int a1, int b1, uint16_t* to) {
                s.readUInt16(a0, b0, a1, b1, c0, c1, to);
            },
            [](const RasterSource&, uint16_t) { return true; }, mosaic(SampleRead::UInt16), c0);
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

    // Values (x, y) of the window, `values` per pixel: the first group on the grid with its own
    // there (`has`), else the mosaic's at the pixel centre, else `gap`.
    template <typename T, typename Own, typename Has>
    void read(int x0, int y0, int x1, int y1, int values, T gap, T* out, Own own, Has has, const MapMosaic& map,
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
            part.resize(partWidth * static_cast<size_t>(fy1 - fy0) * n);
            own(s, fx0, fy0, fx1, fy1, part.data());
            for (int y = fy0; y < fy1; ++y) {
                for (int x = fx0; x < fx1; ++x) {
                    const size_t k = static_cast<size_t>(y + g.y - y0) * width + static_cast<size_t>(x + g.x - x0);
                    const size_t at = static_cast<size_t>(y - fy0) * partWidth + static_cast<size_t>(x - fx0);
                    const T* from = &part[at * n];
                    if (done[k] || !std::all_of(from, from + n, [&](T v) { return has(s, v); })) {
                        continue;
                    }
                    std::copy(from, from + n, out + k * n);
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

} // namespace

std::array<double, 4> PlanarTarget::parseExtent(const std::string& text) {
    const std::array<double, 4> v =
        parseOptionNumbers4(text, "extent", "MINX,MINY,MAXX,MAXY in the CRS's units", "a coordinate in the CRS's units");
    if (!(v[0] < v[2]) || !(v[1] < v[3])) {
        failOption("extent", "needs MINX < MAXX and MINY < MAXY, not " + text);
    }
    return v;
}

std::unique_ptr<RasterSource> openPlanarMosaic(const std::vector<std::string>& inputs, int cacheMegabytes,
                                               bool sameSamples, const PlanarTarget& target) {
    if (inputs.size() <= 1 && target.empty()) {
        return openNorthUp(inputs, cacheMegabytes);
    }
    if (target.extent) {
        const auto& e = *target.extent;
        if (!std::all_of(e.begin(), e.end(), [](double v) { return std::isfinite(v); }) || !(e[0] < e[2]) ||
            !(e[1] < e[3])) {
            throw OptionError("extent", "must be MINX,MINY,MAXX,MAXY with MINX < MAXX and MINY < MAXY");
        }
    }
    const std::vector<std::vector<std::string>> groups = groupByGrid(inputs);
    if (sameSamples && groups.size() > 1) {
        const RasterInfo first = RasterSource::open(groups[0][0], 1)->info();
        for (size_t k = 1; k < groups.size(); ++k) {
            const RasterInfo info = RasterSource::open(groups[k][0], 1)->info();
            if (info.channels != first.channels || info.type != first.type) {
                fail(groups[k][0], std::to_string(info.channels) + " bands of " + sampleTypeName(info.type) + ", not " +
                                       std::to_string(first.channels) + " of " + sampleTypeName(first.type) + " as " +
                                       groups[0][0]);
            }
        }
    }
    if (groups.size() == 1 && target.empty()) {
        return openNorthUp(groups[0], cacheMegabytes);
    }
    // Every group described, the finest of all, and the CRS and finest group on it.
    std::vector<std::unique_ptr<RasterSource>> described;
    std::vector<GeoreferencedMap> maps;
    size_t finest = 0;
    for (size_t k = 0; k < groups.size(); ++k) {
        described.push_back(openNorthUp(groups[k], 1));
        const RasterInfo& info = described.back()->info();
        maps.emplace_back(*info.georeference, info.width, info.height, described.back()->path());
        if (maps[k].metresPerPixel() < maps[finest].metresPerPixel() * (1.0 - 1e-9)) {
            finest = k;
        }
    }
    const Georeference crs = target.crs.empty() ? *described[0]->info().georeference : georeferenceOfCrs(target.crs);
    std::optional<size_t> onGrid; // the finest group in the CRS, when it is the finest of all
    for (size_t k = 0; k < groups.size(); ++k) {
        if (sameCrs(*described[k]->info().georeference, crs) &&
            maps[k].metresPerPixel() <= maps[finest].metresPerPixel() * (1.0 + 1e-9) &&
            (!onGrid || maps[k].metresPerPixel() < maps[*onGrid].metresPerPixel() * (1.0 - 1e-9))) {
            onGrid = k;
        }
    }
    // The grid: that group's, or square pixels of the finest ground size on whole multiples of
    // it, with pixel (0, 0) near the first group's centre (where a geographic CRS's longitudes
    // are taken from).
    Georeference grid = crs;
    int64_t gridWidth = 1, gridHeight = 1;
    if (onGrid) {
        grid = *described[*onGrid]->info().georeference;
        gridWidth = described[*onGrid]->info().width;
        gridHeight = described[*onGrid]->info().height;
    } else {
        const RasterInfo& f = described[finest]->info();
        const double metres = groundSide(*f.georeference, f.width, f.height, maps[finest]);
        const double side = crs.projected ? metres / crs.unitInMetres
                                          : metres / (crs.semiMajorAxis * std::numbers::pi / 180.0) / crs.unitInDegrees;
        grid.pixelToCrs = {0.0, 1.0, 0.0, 0.0, 0.0, -1.0};
        const RasterInfo& first = described[0]->info();
        double x = 0.0, y = 0.0;
        if (!GeoreferencedMap(grid, 1, 1, target.crs).cornerPixelOf(maps[0].geodeticOf(first.width / 2.0, first.height / 2.0), x, y)) {
            throw OptionError("crs", target.crs + " cannot place " + described[0]->path() + " (beyond its projection)");
        }
        grid.pixelToCrs = {std::floor(x / side) * side, side, 0.0, std::ceil(-y / side) * side, 0.0, -side};
    }
    const std::string gridName = onGrid ? described[*onGrid]->path() : target.crs;
    const GeoreferencedMap gridMap(grid, gridWidth, gridHeight, gridName);
    // The groups on that grid, in list order, with their pixel (0, 0) on it: that group, and any
    // other there whose sample type or nodata value kept it apart (groupByGrid).
    std::vector<std::pair<size_t, std::array<int64_t, 2>>> onTheGrid;
    for (size_t k = 0; onGrid && k < groups.size(); ++k) {
        if (const auto at = offsetOnGrid(described[*onGrid]->info(), described[k]->info())) {
            onTheGrid.emplace_back(k, *at);
        }
    }

    // The mosaic's pixels on that grid: the extent asked for, or the union of the footprints.
    constexpr double kSnap = 1e-6; // a pixel edge within this of an extent's edge is on it
    double minX = std::numeric_limits<double>::infinity(), minY = minX, maxX = -minX, maxY = -minX;
    auto add = [&](double col, double row) {
        minX = std::min(minX, col);
        maxX = std::max(maxX, col);
        minY = std::min(minY, row);
        maxY = std::max(maxY, row);
    };
    // Group k's footprint on the grid, added to the box.
    const auto addFootprint = [&](size_t k) {
        const RasterInfo& info = described[k]->info();
        const auto on = std::find_if(onTheGrid.begin(), onTheGrid.end(), [&](const auto& g) { return g.first == k; });
        if (on != onTheGrid.end()) {
            const auto [dx, dy] = on->second;
            add(static_cast<double>(dx), static_cast<double>(dy));
            add(static_cast<double>(dx + info.width), static_cast<double>(dy + info.height));
            return;
        }
        constexpr int kSide = 32; // points along each edge of the group's outline
        for (int s = 0; s <= kSide; ++s) {
            const double u = static_cast<double>(s) / kSide;
            for (const auto& [c, r] : {std::pair{u * info.width, 0.0}, std::pair{u * info.width, 1.0 * info.height},
                                       std::pair{0.0, u * info.height}, std::pair{1.0 * info.width, u * info.height}}) {
                double col = 0.0, row = 0.0;
                if (gridMap.cornerPixelOf(maps[k].geodeticOf(c, r), col, row)) {
                    add(col, row);
                }
            }
        }
    };
    std::array<double, 4> inputBox{minX, minY, maxX, maxY};
    // Each group's footprint on the grid (the box of its outline's points).
    std::vector<std::array<double, 4>> footprints;
    for (size_t k = 0; k < groups.size(); ++k) {
        const std::array<double, 4> before{minX, minY, maxX, maxY};
        minX = minY = std::numeric_limits<double>::infinity();
        maxX = maxY = -minX;
        addFootprint(k);
        footprints.push_back({minX, minY, maxX, maxY});
        minX = std::min(minX, before[0]);
        minY = std::min(minY, before[1]);
        maxX = std::max(maxX, before[2]);
        maxY = std::max(maxY, before[3]);
    }
    if (target.extent) {
        inputBox = {minX, minY, maxX, maxY};
        minX = minY = std::numeric_limits<double>::infinity();
        maxX = maxY = -minX;
        const auto& e = *target.extent;
        const auto& t = grid.pixelToCrs;
        const double det = t[1] * t[5] - t[2] * t[4];
        for (const auto& [x, y] : {std::pair{e[0], e[1]}, std::pair{e[2], e[1]}, std::pair{e[0], e[3]}, std::pair{e[2], e[3]}}) {
            add((t[5] * (x - t[0]) - t[2] * (y - t[3])) / det, (t[1] * (y - t[3]) - t[4] * (x - t[0])) / det);
        }
        if (maxX <= inputBox[0] || minX >= inputBox[2] || maxY <= inputBox[1] || minY >= inputBox[3]) {
            throw OptionError("extent", "covers none of the inputs (in " + grid.crsText() + ")");
        }
    }
    const double x0 = std::floor(minX + kSnap), y0 = std::floor(minY + kSnap);
    const double x1 = std::ceil(maxX - kSnap), y1 = std::ceil(maxY - kSnap);
    if (x1 - x0 > std::numeric_limits<int>::max() || y1 - y0 > std::numeric_limits<int>::max()) {
        fail(inputs[0], "the mosaic would be " + numberText(x1 - x0) + " x " + numberText(y1 - y0) + " pixels on the grid of " +
                            gridName + ", beyond 2^31 - 1 a side");
    }
    RasterInfo info = described[finest]->info();
    info.georeference = grid;
    info.width = static_cast<int>(x1 - x0);
    info.height = static_cast<int>(y1 - y0);
    if (onGrid && groups.size() == 1 && x0 == 0.0 && y0 == 0.0 && info.width == gridWidth && info.height == gridHeight) {
        return openNorthUp(groups[0], cacheMegabytes); // the group as it is
    }
    auto& t = info.georeference->pixelToCrs;
    t[0] += t[1] * x0 + t[2] * y0;
    t[3] += t[4] * x0 + t[5] * y0;
    if (!info.nodata && info.type != SampleType::UInt8 && info.type != SampleType::UInt16) {
        info.nodata = std::numeric_limits<double>::quiet_NaN(); // gaps are holes
    }
    // Groups of several resolutions: where each may have samples and how coarse it is
    // (RasterInfo::parts), so that a pyramid goes no deeper than each where it alone is (a
    // coarse base is not encoded at an inset's level). Each footprint widened by the pixels its
    // interpolation reaches and a hundredth of its size (its outline is known at points).
    const double fine = maps[finest].metresPerPixel();
    if (std::any_of(maps.begin(), maps.end(), [&](const GeoreferencedMap& m) { return m.metresPerPixel() > fine * (1.0 + 1e-6); })) {
        for (size_t k = 0; k < groups.size(); ++k) {
            const std::array<double, 4>& f = footprints[k];
            if (!(f[0] <= f[2] && f[1] <= f[3])) {
                continue; // placed nowhere on the grid
            }
            const double widen = 2.0 + 0.01 * std::max(f[2] - f[0], f[3] - f[1]);
            const auto clampTo = [](double v, int64_t hi) {
                return static_cast<int64_t>(std::clamp(v, 0.0, static_cast<double>(hi)));
            };
            RasterPart part;
            part.x0 = clampTo(std::floor(f[0] - widen) - x0, info.width);
            part.y0 = clampTo(std::floor(f[1] - widen) - y0, info.height);
            part.x1 = clampTo(std::ceil(f[2] + widen) - x0, info.width);
            part.y1 = clampTo(std::ceil(f[3] + widen) - y0, info.height);
            part.pixelsPerSample = maps[k].metresPerPixel() / fine;
            if (part.x0 < part.x1 && part.y0 < part.y1) {
                info.parts.push_back(part);
            }
        }
    }
    const std::string name = inputs.size() == 1 ? inputs[0] : inputs[0] + " and " + std::to_string(inputs.size() - 1) + " more";
    const PlanetBody body(crs.name + "'s ellipsoid", crs.semiMajorAxis, crs.flattening);
    std::vector<OwnGroup> own;
    for (const auto& [k, at] : onTheGrid) {
        const int share = std::max(2, cacheMegabytes / 2 / static_cast<int>(onTheGrid.size()));
        own.push_back({openNorthUp(groups[k], share), at[0] - static_cast<int64_t>(x0),
                       at[1] - static_cast<int64_t>(y0)});
    }
    auto pixels = std::make_shared<ResampledPixels>(groups, std::move(own), static_cast<int>(-x0), static_cast<int>(-y0),
                                                    info, body, std::max(2, cacheMegabytes / 2), grid, gridWidth,
                                                    gridHeight, gridName);
    return RasterSource::fromPixels(name, info, std::move(pixels));
}

} // namespace pyramid
