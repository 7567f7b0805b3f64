// A map for the spherical encoders' tests: smooth RGB colours with a texture of a few pixels over
// a geographic box, no value elsewhere. It may say where it has values (extent(), the box) or
// that it may have them anywhere (everywhere()), which turns off every skip the encoders make
// where a map cannot reach; it counts the points it is asked for.
#pragma once
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>

#include "libpyramid/sphere/equirect_sampler.hpp"

namespace pyramid::test {

class BoxMap final : public GeodeticMap {
public:
    BoxMap(const GeoExtent& box, bool everywhere, std::atomic<int64_t>& points)
        : box_(box), everywhere_(everywhere), points_(points) {}
    int channels() const override { return 3; }
    const GeoExtent& extent() const override { return box_; }
    bool everywhere() const override { return everywhere_; }
    void sample(const GeodeticPoint* p, size_t count, float* out, uint8_t* valid) const override {
        points_ += static_cast<int64_t>(count);
        for (size_t k = 0; k < count; ++k) {
            const double lat = p[k].latitude, lon = p[k].longitude;
            const bool in = lat >= box_.south && lat <= box_.north && lon >= box_.west && lon <= box_.east;
            valid[k] = in ? 1 : 0;
            for (size_t i = 0; i < 3; ++i) {
                const double smooth = 128.0 + 90.0 * std::sin(lat * 0.1 + static_cast<double>(i)) * std::cos(lon * 0.07);
                const double texture = 6.0 * std::sin(lat * 400.0 + static_cast<double>(i)) * std::cos(lon * 300.0);
                out[k * 3 + i] = in ? static_cast<float>(std::clamp(std::round(smooth + texture), 1.0, 255.0)) : 0.0f;
            }
        }
    }

private:
    GeoExtent box_;
    bool everywhere_;
    std::atomic<int64_t>& points_;
};

} // namespace pyramid::test
