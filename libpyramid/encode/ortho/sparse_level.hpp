// A level of an ortho pyramid's levels 0..C held whole (ortho_levels.hpp, "Order and memory"),
// stored in square blocks of kSparseBlock pixels of which only those the map may reach are
// kept: the others are 0 in every channel and take no memory. A face that a small map barely
// touches keeps a few blocks of its levels instead of the whole face (at level 7 with 192-pixel
// tiles, about 2.4 GB of RGBA), and a plane, or a map that reaches everywhere, keeps them all.
//
// Pixel (x, y), y up, of a level `side` pixels across is pixel (x mod B, y mod B) of block
// (x / B, y / B), B = kSparseBlock; blocks are B x B even at the level's far edges, the pixels
// past the side being 0.
#pragma once
#include <cstdint>
#include <vector>

#include "libpyramid/filters/colour_average.hpp"
#include "libpyramid/filters/image8.hpp"

namespace pyramid {

inline constexpr int kSparseBlock = 64;

// Which blocks of a level `side` pixels across are stored: blocks(side) across, then up.
class BlockMask {
public:
    BlockMask() = default;
    BlockMask(int64_t side, uint8_t value) : across_(blocks(side)), stored_(static_cast<size_t>(across_ * across_), value) {}
    // Blocks across (and up) a level `side` pixels across.
    static int64_t blocks(int64_t side) { return (side + kSparseBlock - 1) / kSparseBlock; }

    int64_t across() const { return across_; }
    // False for a block beyond the level.
    bool stored(int64_t bx, int64_t by) const {
        return bx >= 0 && by >= 0 && bx < across_ && by < across_ && stored_[static_cast<size_t>(by * across_ + bx)];
    }
    void store(int64_t bx, int64_t by) { stored_[static_cast<size_t>(by * across_ + bx)] = 1; }
    // True when a stored block meets pixels [x0, x1] x [y0, y1].
    bool meets(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const;

private:
    int64_t across_ = 0;
    std::vector<uint8_t> stored_;
};

class SparseLevel {
public:
    SparseLevel() = default;
    // A level `side` pixels across, 0 everywhere, storing the blocks `stored` marks (a mask of
    // the level's size).
    SparseLevel(int64_t side, int channels, BlockMask stored);

    static int64_t blocks(int64_t side) { return BlockMask::blocks(side); }

    int64_t side() const { return side_; }
    int channels() const { return channels_; }
    bool stored(int64_t bx, int64_t by) const { return mask_.stored(bx, by); }
    // True when no stored block meets pixels [x0, x1] x [y0, y1]: they are all 0.
    bool blank(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const { return !mask_.meets(x0, y0, x1, y1); }
    // Pixels (x, y) .. (x + n - 1, y) into `out` (n x channels bytes), 0 where no block is stored.
    void read(int64_t x, int64_t y, int64_t n, uint8_t* out) const;
    // Writes `part` with its pixel (0, 0) at (x, y) into the stored blocks. What falls on a block
    // not stored must be 0 (the map does not reach it); std::logic_error if not.
    void write(const Image8& part, int64_t x, int64_t y);

    // The next coarser level: each pixel the 2x2 average of its four (`averager`), blocks of four
    // blocks not stored left unstored (blankStaysBlank: the average of 0s is 0). In parallel.
    SparseLevel reduced(const ColourAverager& averager, int threads) const;

private:
    uint8_t* pixel(int64_t x, int64_t y);
    int64_t side_ = 0, across_ = 0;
    int channels_ = 0;
    BlockMask mask_;
    std::vector<PixelBytes> blocks_; // empty: not stored
};

} // namespace pyramid
