// The horizon search of the ambient aperture (aperture.hpp), shared by the planar and the
// spherical aperture (aperture.cpp, planet_aperture.cpp): the steps of a sector's search, a
// sector's horizon, and the heights of an elevation producer's levels.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "libpyramid/encode/aperture/aperture.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/level_heights.hpp"

namespace pyramid::aperture {

// The steps of a sector's search, in order: the distance in finest-level samples (1..radius on
// the finest level, then radius/2 + 1 .. radius samples of each coarser one, twice as far
// apart), while levels remain.
struct SearchStep {
    int level = 0;
    double distance = 0.0;
};

inline std::vector<SearchStep> searchSteps(const ApertureSearch& search, int finest) {
    std::vector<SearchStep> steps;
    for (int q = 0; q < search.levels && finest - q >= 0; ++q) {
        const double scale = std::ldexp(1.0, q);
        for (int k = q == 0 ? 1 : search.radius / 2 + 1; k <= search.radius; ++k) {
            steps.push_back({finest - q, k * scale});
        }
    }
    return steps;
}

// A sector's horizon: the largest of 0 and atan2(rise, run) over its steps (run > 0), taken step
// by step, nearest first. A step whose rise is not positive cannot raise the horizon, nor one
// whose slope is clearly below the steepest so far (by a millionth, far beyond atan2's rounding
// while the slope is below a million): atan2 is computed only for the others, and the horizon is
// bit for bit the largest of every step's atan2.
struct Horizon {
    double angle = 0.0, steepest = 0.0;

    void step(double rise, double run) {
        if (!(run > 0.0)) {
            angle = std::max(angle, std::atan2(rise, run)); // beyond the slopes' rule: taken as it is
            return;
        }
        if (!(rise > 0.0)) {
            return;
        }
        const double ratio = rise / run;
        if (ratio < steepest * (1.0 - 1e-6) && steepest <= 1e6) {
            return;
        }
        angle = std::max(angle, std::atan2(rise, run));
        steepest = std::max(steepest, ratio);
    }
};

// The heights of an elevation producer's levels, read bilinearly between vertices, with the
// tiles last used kept at hand (one per reading thread: no lock for most samples).
class HeightReader {
public:
    explicit HeightReader(ElevationProducer& producer) : producer_(producer), n_(producer.tileSize()) {}

    // Level `level` at vertex coordinates (x, y) of 0..n 2^level (runtime/level_heights.hpp:
    // beyond the map the edge continues).
    double at(int level, double x, double y) {
        const LevelCell cell = levelCell(n_, int64_t{1} << level, x, y);
        return cellHeight(tile(level, cell.tx, cell.ty), n_, cell);
    }

private:
    // Most reads fall in the tile of the read before: that one is looked at first.
    const float* tile(int level, int tx, int ty) {
        const Kept& last = kept_[last_];
        if (last.tile && last.level == level && last.tx == tx && last.ty == ty) {
            return last.tile->zf.data();
        }
        for (size_t i = 0; i < kept_.size(); ++i) {
            const Kept& k = kept_[i];
            if (k.tile && k.level == level && k.tx == tx && k.ty == ty) {
                last_ = i;
                return k.tile->zf.data();
            }
        }
        last_ = next_++ % kept_.size();
        kept_[last_] = {level, tx, ty, producer_.tile(level, tx, ty)};
        return kept_[last_].tile->zf.data();
    }

    struct Kept {
        int level = 0, tx = 0, ty = 0;
        std::shared_ptr<const ElevationTile> tile;
    };
    ElevationProducer& producer_;
    int n_;
    std::array<Kept, 16> kept_{};
    size_t next_ = 0, last_ = 0;
};

} // namespace pyramid::aperture
