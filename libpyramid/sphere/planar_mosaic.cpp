#include "libpyramid/sphere/planar_mosaic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <type_traits>

#include "formats/error.hpp"
#include "libpyramid/input/raster_mosaic.hpp"
#include "libpyramid/sphere/map_mosaic.hpp"
#include "libpyramid/sphere/map_placement.hpp"

namespace pyramid {

namespace {

class ResampledPixels final : public RasterPixels {
public:
    ResampledPixels(std::vector<std::vector<std::string>> groups, std::unique_ptr<RasterSource> finest, int x0, int y0,
                    RasterInfo info, PlanetBody body, int cacheMegabytes)
        : groups_(std::move(groups)), finest_(std::move(finest)), x0_(x0), y0_(y0), info_(std::move(info)),
          body_(std::move(body)), cacheMegabytes_(cacheMegabytes),
          grid_(*finest_->info().georeference, finest_->info().width, finest_->info().height, finest_->path()) {}

    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const override {
        const float gap = info_.nodata ? static_cast<float>(*info_.nodata) : 0.0f;
        const std::optional<double> own = finest_->info().nodata;
        read<float>(x0, y0, x1, y1, 1, gap, out,
                    [&](int a0, int b0, int a1, int b1, float* to) { finest_->readFloat(a0, b0, a1, b1, channel, to); },
                    [&](float v) { return !(own && (v == static_cast<float>(*own) || (std::isnan(*own) && std::isnan(v)))); },
                    mosaic(SampleRead::Float), channel);
    }

    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const override {
        read<uint16_t>(x0, y0, x1, y1, c1 - c0, 0, out,
                       [&](int a0, int b0, int a1, int b1, uint16_t* to) { finest_->readUInt16(a0, b0, a1, b1, c0, c1, to); },
                       [](uint16_t) { return true; }, mosaic(SampleRead::UInt16), c0);
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

    // Values (x, y) of the window, `values` per pixel: the finest group's own where it has one
    // (`has`), else the mosaic's at the pixel centre, else `gap`.
    template <typename T, typename Own, typename Has>
    void read(int x0, int y0, int x1, int y1, int values, T gap, T* out, Own own, Has has, const MapMosaic& map,
              int firstChannel) const {
        const size_t width = static_cast<size_t>(x1 - x0);
        const auto n = static_cast<size_t>(values);
        std::fill(out, out + width * static_cast<size_t>(y1 - y0) * n, gap);
        std::vector<uint8_t> done(width * static_cast<size_t>(y1 - y0), 0);
        // The finest group's pixels: the window within it, shifted by its place in the mosaic.
        const RasterInfo& f = finest_->info();
        const int fx0 = std::max(x0 - x0_, 0), fx1 = std::min(x1 - x0_, f.width);
        const int fy0 = std::max(y0 - y0_, 0), fy1 = std::min(y1 - y0_, f.height);
        if (fx0 < fx1 && fy0 < fy1) {
            std::vector<T> part(static_cast<size_t>(fx1 - fx0) * static_cast<size_t>(fy1 - fy0) * n);
            own(fx0, fy0, fx1, fy1, part.data());
            for (int y = fy0; y < fy1; ++y) {
                for (int x = fx0; x < fx1; ++x) {
                    const T* from = &part[(static_cast<size_t>(y - fy0) * static_cast<size_t>(fx1 - fx0) + static_cast<size_t>(x - fx0)) * n];
                    if (!std::all_of(from, from + n, has)) {
                        continue;
                    }
                    const size_t k = static_cast<size_t>(y + y0_ - y0) * width + static_cast<size_t>(x + x0_ - x0);
                    std::copy(from, from + n, out + k * n);
                    done[k] = 1;
                }
            }
        }
        // The others at the centres of the pixels left.
        std::vector<size_t> left;
        std::vector<GeodeticPoint> points;
        for (size_t k = 0; k < done.size(); ++k) {
            if (!done[k]) {
                left.push_back(k);
                const double col = static_cast<double>(x0 - x0_) + static_cast<double>(k % width) + 0.5;
                const double row = static_cast<double>(y0 - y0_) + static_cast<double>(k / width) + 0.5;
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
            for (size_t c = 0; c < n; ++c) {
                const float v = sampled[i * channels + static_cast<size_t>(firstChannel) + c];
                out[left[i] * n + c] = static_cast<T>(std::is_integral_v<T> ? std::lround(v) : v);
            }
        }
    }

    std::vector<std::vector<std::string>> groups_;
    std::unique_ptr<RasterSource> finest_;
    int x0_, y0_; // the finest group's first pixel in the mosaic
    RasterInfo info_;
    PlanetBody body_;
    int cacheMegabytes_;
    GeoreferencedMap grid_;
    mutable std::once_flag once_[2];
    mutable std::unique_ptr<MapMosaic> mosaics_[2];
};

} // namespace

std::unique_ptr<RasterSource> openPlanarMosaic(const std::vector<std::string>& inputs, int cacheMegabytes,
                                               bool sameSamples) {
    if (inputs.size() <= 1) {
        return RasterSource::openMosaic(inputs, cacheMegabytes);
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
    if (groups.size() == 1) {
        return RasterSource::openMosaic(groups[0], cacheMegabytes);
    }
    // The finest group, and every group's footprint on its grid.
    std::vector<std::unique_ptr<RasterSource>> described;
    size_t finest = 0;
    double finestMetres = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < groups.size(); ++k) {
        described.push_back(RasterSource::openMosaic(groups[k], 1));
        const RasterInfo& info = described.back()->info();
        const GeoreferencedMap map(*info.georeference, info.width, info.height, described.back()->path());
        if (map.metresPerPixel() < finestMetres * (1.0 - 1e-9)) {
            finestMetres = map.metresPerPixel();
            finest = k;
        }
    }
    const RasterInfo target = described[finest]->info();
    const Georeference& g = *target.georeference;
    const PlanetBody body("the finest input's ellipsoid", g.semiMajorAxis, g.flattening);
    const GeoreferencedMap grid(g, target.width, target.height, described[finest]->path());
    double minX = 0.0, minY = 0.0, maxX = target.width, maxY = target.height;
    for (size_t k = 0; k < groups.size(); ++k) {
        if (k == finest) {
            continue;
        }
        const RasterInfo& info = described[k]->info();
        const GeoreferencedMap other(*info.georeference, info.width, info.height, described[k]->path());
        constexpr int kSide = 32; // points along each edge of the group's outline
        for (int s = 0; s <= kSide; ++s) {
            const double u = static_cast<double>(s) / kSide;
            for (const auto& [c, r] : {std::pair{u * info.width, 0.0}, std::pair{u * info.width, 1.0 * info.height},
                                       std::pair{0.0, u * info.height}, std::pair{1.0 * info.width, u * info.height}}) {
                double col = 0.0, row = 0.0;
                if (grid.cornerPixelOf(other.geodeticOf(c, r), col, row)) {
                    minX = std::min(minX, col);
                    maxX = std::max(maxX, col);
                    minY = std::min(minY, row);
                    maxY = std::max(maxY, row);
                }
            }
        }
    }
    const double x0 = std::floor(minX), y0 = std::floor(minY), x1 = std::ceil(maxX), y1 = std::ceil(maxY);
    if (x1 - x0 > std::numeric_limits<int>::max() || y1 - y0 > std::numeric_limits<int>::max()) {
        fail(inputs[0], "the mosaic would be " + std::to_string(x1 - x0) + " x " + std::to_string(y1 - y0) +
                            " pixels on the grid of " + described[finest]->path() + ", beyond 2^31 - 1 a side");
    }
    RasterInfo info = target;
    info.width = static_cast<int>(x1 - x0);
    info.height = static_cast<int>(y1 - y0);
    auto& t = info.georeference->pixelToCrs;
    t[0] += t[1] * x0 + t[2] * y0;
    t[3] += t[4] * x0 + t[5] * y0;
    if (!info.nodata && info.type != SampleType::UInt8 && info.type != SampleType::UInt16) {
        info.nodata = std::numeric_limits<double>::quiet_NaN(); // gaps are holes
    }
    const std::string name = inputs[0] + " and " + std::to_string(inputs.size() - 1) + " more";
    auto finestSource = RasterSource::openMosaic(groups[finest], std::max(2, cacheMegabytes / 2));
    auto pixels = std::make_shared<ResampledPixels>(groups, std::move(finestSource), static_cast<int>(-x0),
                                                    static_cast<int>(-y0), info, body, std::max(2, cacheMegabytes / 2));
    return RasterSource::fromPixels(name, info, std::move(pixels));
}

} // namespace pyramid
