// Where the finest pixels of an ortho pyramid come from (ortho_levels.hpp): a plane resampled
// from an image (planar_pixels.hpp) or one cube face of a spherical planet (face_pixels.hpp).
// Everything that differs between the two is behind this interface, so that the code that
// reduces the levels and cuts the tiles (ortho_levels.cpp) is the same for both.
#pragma once
#include <cstdint>
#include <string>

#include "libpyramid/filters/colour_average.hpp"

namespace pyramid {

// Pixels of border on each side of a tile (TrueTile).
inline constexpr int kTileBorder = 2;

class PixelSource {
public:
    virtual ~PixelSource() = default;

    // Finest-level pixels [x0, x0 + w) x [y0, y0 + h) (y up), 8 bits. Thread-safe.
    virtual Image8 sample(int64_t x0, int64_t y0, int w, int h) const = 0;

    // True when finest pixels [x0, x0 + w) x [y0, y0 + h) are known, without sampling them, to
    // be 0 in every channel (beyond the input); false when they are not, or not known.
    virtual bool knownBlank(int64_t x0, int64_t y0, int64_t w, int64_t h) const = 0;

    // Pixels that exist beyond each side of level l, the map's edge: 0 for a plane. A cube face
    // has its neighbours there, and its tiles take their borders from them.
    virtual int64_t margin(int l) const = 0;

    // Coordinate p of a tile border pixel on a level `width` pixels across: the pixel whose
    // value the border takes (a plane repeats its edge pixels; a face's borders are real
    // pixels, within the margin).
    virtual int64_t borderPixel(int64_t p, int64_t width) const = 0;

    // The geometry rule applied, one sentence (reports).
    virtual const std::string& sampling() const = 0;

    // Inputs of several resolutions (ortho_levels.hpp, "Several resolutions"). True when the
    // input's parts differ in resolution: a part needs the levels down to its own, and a level's
    // pixels where no part needs the next level are sampled at their own centres.
    virtual bool severalLevels() const { return false; }
    // Whether a part that needs a level `levelWidth` pixels across (a part finer than the level of
    // half as many pixels) may have values in that level's pixels [x0, x1] x [y0, y1] (corners
    // inclusive, within a face's margin). Conservative: true says nothing. Thread-safe.
    virtual bool mayNeedLevel(int64_t levelWidth, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
        (void)levelWidth, (void)x0, (void)y0, (void)x1, (void)y1;
        return true;
    }
    // Pixels [x0, x0 + w) x [y0, y0 + h) of the level `levelWidth` pixels across (the finest
    // level's width halved some times), each the input sampled at its own centre by the rule
    // sample() applies at the finest level. Thread-safe.
    virtual Image8 sampleAt(int64_t levelWidth, int64_t x0, int64_t y0, int w, int h) const = 0;
    // A hint from a walk that reads the finest level from the north, the input's last: no
    // finest row north of row y (above it: y + 1 and up) is sampled again, so the input may
    // give back the memory of the rows only they need. By default, nothing. Thread-safe.
    virtual void passedNorthOf(int64_t y) const { (void)y; }
};

} // namespace pyramid
