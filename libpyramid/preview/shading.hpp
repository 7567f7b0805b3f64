// The colours of previews (doc/cli/pyramid-preview.md): a hillshade, a hypsometric colour ramp
// and a diverging ramp, as plain functions of their inputs.
#pragma once
#include <array>
#include <cstdint>

namespace pyramid {

using Rgb8 = std::array<uint8_t, 3>;

// The light a surface of slopes (dz/dx, dz/dy) (x east, y north, z up, in the same units)
// receives from a sun at `azimuthDegrees` (clockwise from north) and `altitudeDegrees` above
// the horizon: the cosine of the angle between the surface's normal and the sun, 0 in shadow.
double hillshade(double dzdx, double dzdy, double azimuthDegrees = 315.0, double altitudeDegrees = 45.0);

// Heights from low (t = 0: lowland green) through yellow and brown to high (t = 1: white).
Rgb8 hypsometricColour(double t);
// Negative values blue (t = -1), 0 white, positive red (t = 1).
Rgb8 divergingColour(double t);
// `colour` darkened by a hillshade `light` in [0, 1] (a quarter of it stays in full shadow).
Rgb8 shaded(const Rgb8& colour, double light);

} // namespace pyramid
