// The finest pixels of one cube face of a spherical planet (ortho_levels.hpp, "Cube faces"):
// the face grid of pixel centres, each the equirectangular input sampled bilinearly at the
// geodetic point of its cube point (face_sampler.hpp) and brought to 8 bits; 0 in every channel
// outside the input's extent. The face has pixels beyond its edges too (folded onto the
// neighbouring faces), from which its tiles take their borders.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/encode/ortho/pixel_source.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/face_sampler.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

class FacePixels final : public PixelSource {
public:
    // Face `face` (1..6) of `body`, `width` pixels across at the finest level, from the first
    // `channels` channels of `source` (which must outlive this object) placed by `placement`.
    // With `map`, the pixels come from it (several rasters each placed by its own
    // georeferencing, sphere/map_mosaic.hpp: channels [0, channels) read as UInt16, of the
    // sample type of `source`) instead of `source` itself.
    FacePixels(const RasterSource& source, const MapPlacement& placement, const PlanetBody& body, int face, int channels,
               int64_t width, const GeodeticMap* map = nullptr);
    FacePixels(const FacePixels&) = delete; // map_ and face_ refer to the members before them
    FacePixels& operator=(const FacePixels&) = delete;

    Image8 sample(int64_t x0, int64_t y0, int w, int h) const override;
    // Known when the pixels lie wholly outside the map's geographic extent
    // (FaceSampler::mayHaveValues): a face, or part of one, that a small map does not reach.
    bool knownBlank(int64_t x0, int64_t y0, int64_t w, int64_t h) const override {
        return w > 0 && h > 0 && !face_.mayHaveValues(x0, y0, x0 + w - 1, y0 + h - 1);
    }
    // Tiles at every level up to l take their borders from beyond the face, and reducing level l
    // to level 0 halves the margin l times, down to the border.
    int64_t margin(int l) const override { return int64_t{kTileBorder} << l; }
    int64_t borderPixel(int64_t p, int64_t) const override { return p; }
    const std::string& sampling() const override { return sampling_; }
    // A mosaic of several resolutions (GeodeticMap::severalResolutions): a level l of width
    // W = T << l is needed by the members more than 2 W pixels around the equator fine, the
    // rule that gives the finest member its level (a face spans a quarter of the equator).
    bool severalLevels() const override { return map_.severalResolutions(); }
    bool mayNeedLevel(int64_t levelWidth, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const override;
    Image8 sampleAt(int64_t levelWidth, int64_t x0, int64_t y0, int w, int h) const override;

private:
    // The face's grid of pixel centres `levelWidth` across (the finest one's width halved).
    const FaceSampler& at(int64_t levelWidth) const;
    Image8 sampleWith(const FaceSampler& grid, int64_t x0, int64_t y0, int w, int h) const;

    int channels_ = 0;
    bool sixteen_ = false;
    PlanetBody body_;
    std::unique_ptr<EquirectSampler> own_; // the map of `source`, unless one was given
    const GeodeticMap& map_;
    FaceSampler face_;
    std::vector<std::unique_ptr<FaceSampler>> coarser_; // widths W / 2, W / 4, ... down to 1
    std::string sampling_;
};

} // namespace pyramid
