// The colour-residual producer (the seeds' "Ortho producer" fed by an ortho CPU producer of
// colour residuals): the root tile is the file's plain colours; every other tile is
// upsampleColour(parent, stored residuals) (libpyramid/filters/colour_upsample.hpp, doc/format.md
// section 4), and beyond the files' deepest level the residuals are "none" (128), which keeps
// refining smoothly. Results are kept in an LRU cache. Thread-safe.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "libpyramid/runtime/ortho_producer.hpp"

namespace pyramid {

class ColourProducer {
public:
    // The residual tiles must have 2-pixel borders and be TIFF (lossless or JPEG) tiles.
    explicit ColourProducer(std::shared_ptr<const OrthoProducer> residuals, size_t cacheCapacity = 256);
    ~ColourProducer();

    int tilePixels() const; // tileSize + 4
    int channels() const;
    // (tileSize+4)^2 x channels bytes, row 0 = bottom.
    std::shared_ptr<const std::vector<uint8_t>> tile(int level, int tx, int ty);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
