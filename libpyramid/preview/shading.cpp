#include "libpyramid/preview/shading.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pyramid {

double hillshade(double dzdx, double dzdy, double azimuthDegrees, double altitudeDegrees) {
    const double az = azimuthDegrees * std::numbers::pi / 180.0;
    const double alt = altitudeDegrees * std::numbers::pi / 180.0;
    // The sun's direction (east, north, up) and the surface's normal (-dz/dx, -dz/dy, 1).
    const double lx = std::sin(az) * std::cos(alt), ly = std::cos(az) * std::cos(alt), lz = std::sin(alt);
    const double norm = std::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
    return std::max(0.0, (-dzdx * lx - dzdy * ly + lz) / norm);
}

namespace {

struct Stop {
    double t;
    double r, g, b;
};

Rgb8 ramp(const Stop* stops, int count, double t) {
    t = std::clamp(t, stops[0].t, stops[count - 1].t);
    int k = 0;
    while (k + 2 < count && t > stops[k + 1].t) {
        ++k;
    }
    const Stop& a = stops[k];
    const Stop& b = stops[k + 1];
    const double f = (t - a.t) / (b.t - a.t);
    const auto mix = [f](double x, double y) { return static_cast<uint8_t>(std::lround(x + (y - x) * f)); };
    return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

} // namespace

Rgb8 hypsometricColour(double t) {
    static const Stop stops[] = {{0.0, 46, 110, 58},    {0.2, 112, 163, 82},  {0.45, 222, 206, 128},
                                 {0.7, 160, 116, 74},   {0.88, 190, 180, 172}, {1.0, 250, 250, 250}};
    return ramp(stops, 6, t);
}

Rgb8 divergingColour(double t) {
    static const Stop stops[] = {{-1.0, 33, 84, 170}, {0.0, 247, 247, 247}, {1.0, 180, 30, 38}};
    return ramp(stops, 3, t);
}

Rgb8 shaded(const Rgb8& colour, double light) {
    const double f = 0.25 + 0.75 * std::clamp(light, 0.0, 1.0);
    return {static_cast<uint8_t>(std::lround(colour[0] * f)), static_cast<uint8_t>(std::lround(colour[1] * f)),
            static_cast<uint8_t>(std::lround(colour[2] * f))};
}

} // namespace pyramid
