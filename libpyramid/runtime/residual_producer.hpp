// The CPU residual producer of the seeds ("Residual producer"): serves residual tiles as
// float32 (tileSize+5)^2 arrays, scaled to height units, from a main residual file and any
// nested region files. Thread-safe.
//
// Quadtree coordinates (level, tx, ty) are the producer's; tile (level, tx, ty) is file tile
// (level + delta, tx, ty) of the deepest file that holds it. With delta > 0 the root tile
// (0, 0, 0) is the upsample-and-add of file levels 0..delta (doc/format.md). Tiles of levels
// below the file's minLevel are smaller: they are returned in the lower-left corner of the
// (tileSize+5)^2 array, the rest being zero.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "formats/byte_source.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/filters/elevation_upsample.hpp"

namespace pyramid {

struct ResidualProducerOptions {
    int delta = 0; // 0 .. minLevel of the main file
    // The seeds' `scale` attribute: multiplies every residual. Each file's residuals are served
    // as float(r) * (fileScale * scale), the product of the file's own header scale and this one
    // taken once in float32 (one rounding), so region files keep their own scales relative to
    // each other. Finite and non-zero (1: the files' residuals as they are).
    float scale = 1.0f;
    // Throws OptionError("scale: ...") for a non-finite or zero scale. (delta is checked against
    // the main file by the producer, and so is the product with each file's scale: every residual
    // times it must be a finite non-zero float.)
    void validate() const;
};

class ResidualProducer {
public:
    // `regions`: region files nested in the main file (each rooted at a tile of the main
    // pyramid, minLevel 0, same tileSize). Region files nested in region files are found by
    // their roots: a tile is served by the deepest file whose pyramid contains it.
    ResidualProducer(const std::string& mainFile, const std::vector<std::string>& regions = {},
                     const ResidualProducerOptions& options = {});
    // The same over byte sources (files, memory, callbacks): each is kept while the producer
    // lives, and read from the threads that ask for tiles.
    ResidualProducer(std::shared_ptr<const ByteSource> mainFile,
                     const std::vector<std::shared_ptr<const ByteSource>>& regions,
                     const ResidualProducerOptions& options = {});
    ~ResidualProducer();

    const ResidualHeader& header() const; // the main file's
    const std::string& path() const;      // the main file's, for messages
    int tileSize() const;                 // residual tileSize (without the +5)
    int delta() const;
    int maxLevel() const;                 // deepest producer level any file holds
    // True when some file holds the producer tile (level, tx, ty) with residuals: false beyond every
    // file and where the deepest file holding it leaves it out (an empty byte range, zero residuals:
    // region_lookup.hpp, storesTile). The root with delta > 0 has residuals when one of the file
    // levels 0..delta it folds has. The elevation producers' residual, CPU and GL.
    bool hasTile(int level, int tx, int ty) const;
    // Samples per side of the data inside the returned array ((tileSize >> k) + 5).
    int tileSamples(int level) const;
    // The scaled residuals: float(r) * scale, (tileSize+5)^2 floats, row 0 = bottom.
    // Throws MissingTileError if no file holds the tile; zeros where it is left out (!hasTile).
    std::vector<float> tile(int level, int tx, int ty) const;
    // Samples [x0, x0 + side) x [y0, y0 + side) of tile(level, tx, ty) into `out`, rows
    // `outStride` apart: what the elevation producers read, without a whole tile's copy.
    void window(int level, int tx, int ty, int x0, int y0, int side, float* out, size_t outStride) const;
    // The same window's residuals as stored, unscaled (ResidualWindow says how they are served),
    // for upsampleAndAddResiduals: no copy at all. Valid until this thread's next call into a
    // residual producer. Not of the root with delta > 0 (several levels folded: fails).
    ResidualWindow storedWindow(int level, int tx, int ty, int x0, int y0, int side) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
