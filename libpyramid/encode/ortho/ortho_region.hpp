// How an ortho build encodes one region (OrthoEncodeOptions::region, doc/planet-scale.md "One
// region at a time"): which walk of the levels reaches it while reading the least input, which
// tiles are encoded, and the colour reconstruction its root is predicted from. The tiles are
// the whole pyramid's, byte for byte: TIFF and DXT tiles do not depend on the rest of the
// pyramid, and a colour residual tile depends only on its parent's reconstruction, which is
// either encoded from the input along the root's ancestors, or read from the enclosing
// residual pyramid (`parent`) through the runtime's colour producer, bit-exact with the encoder.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_levels.hpp"

namespace pyramid {

struct OrthoRegionPlan {
    RegionRoot root;
    OrthoLevels::WalkOrder order = OrthoLevels::WalkOrder::CoarseFirst;
    OrthoLevels::Range range;           // the subtree items that reach the region
    bool ancestors = false;             // the root's ancestors are encoded too (for their reconstruction)
    std::vector<uint8_t> parentRecon;   // from `parent`: the root's parent, (tileSize+4)^2 x channels
    int64_t tiles = 0;                  // the region's

    // With parentRecon: what checkParent compares it with, and how it names what it expects.
    struct ParentCheck {
        std::string name;                // the parent's name in messages (PyramidSet::name)
        std::string expected;            // "residuals/RGB.dat": the build's colour residuals
        ColourSpace colourSpace = ColourSpace::Srgb;
        int tileSize = 0, channels = 0;
        int maxError = 1;                // Deflate: the residual coding's bound on a rebuilt colour
        // A parent whose tile is JPEG: its stored (decoded) tile, the rebuilt tile of its own
        // parent (empty at level 0) and, for each channel, the bound its quantisation tables set
        // on the error of the stored samples of one 8 x 8 block (the root of its sum of squares).
        std::vector<uint8_t> jpegStored, jpegGrandparent;
        std::vector<double> jpegBlockBound;
    } parent;

    // Whether the tile goes into the region's files.
    bool holds(int level, int tx, int ty) const { return regionHolds(root, level, tx, ty); }
    // Whether the tile is encoded: the region's tiles, and with `ancestors` the root's ancestors.
    bool needed(int level, int tx, int ty) const;
    // The parent (parentRecon) must be this input's: its quarter over the root is the root's
    // true tile 2x2 averaged (levels are averages, ortho_levels.hpp), within the error the
    // closed loop of the colour residuals leaves (doc/ortho-encoding.md, "Colour residuals"):
    // with Deflate, its rebuilt colours within maxError; with JPEG, its stored residuals (the
    // true tile's, against the prediction from its own parent's rebuilt colours) within the
    // loss its quantisation tables allow, block by block.
    // Throws OptionError("parent") naming the parent file when it is not; nothing without a
    // parent. `root` is the root's true tile.
    void checkParent(const TrueTile& root) const;

private:
    // checkParent for a JPEG parent: `quarter` is the truth over the root, at (x0, y0) in the
    // parent's tile.
    void checkJpegParent(const Image8& quarter, int x0, int y0) const;
};

// Checks the request against the pyramid (one-line errors naming the option or the parent file)
// and plans it. Throws OptionError or Error.
OrthoRegionPlan planOrthoRegion(const OrthoLevels& levels, const OrthoEncodeOptions& o);

} // namespace pyramid
