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
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "libpyramid/filters/colour_average.hpp"
#include "libpyramid/filters/image8.hpp"

namespace pyramid {

inline constexpr int kSparseBlock = 64;

// Which blocks of a level `side` pixels across are stored: all of them, or those listed (in
// row order), so that a mask costs what it stores, not the level's area (a face at level 12 of
// 192-pixel tiles is 12288 blocks across).
class BlockMask {
public:
    BlockMask() = default;
    // Every block stored (value 1), or none until store() adds them.
    BlockMask(int64_t side, uint8_t value) : across_(blocks(side)), all_(value != 0) {}
    // Blocks across (and up) a level `side` pixels across.
    static int64_t blocks(int64_t side) { return (side + kSparseBlock - 1) / kSparseBlock; }

    int64_t across() const { return across_; }
    bool all() const { return all_; }
    // Adds a block, in any order; seal() then puts them in order before the mask is read.
    void store(int64_t bx, int64_t by);
    void seal();
    // False for a block beyond the level.
    bool stored(int64_t bx, int64_t by) const { return slot(bx, by) >= 0; }
    // True when a stored block meets pixels [x0, x1] x [y0, y1].
    bool meets(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const;
    // The stored blocks: every block of the level (all()), or those listed.
    int64_t count() const { return all_ ? across_ * across_ : static_cast<int64_t>(keys_.size()); }
    // Stored block number k (0 <= k < count()), in row order: (bx, by).
    std::pair<int64_t, int64_t> block(int64_t k) const {
        const int64_t key = all_ ? k : keys_[static_cast<size_t>(k)];
        return {key % across_, key / across_};
    }
    // The number of stored block (bx, by) in that order, or -1 when it is not stored.
    int64_t slot(int64_t bx, int64_t by) const;
    // The rows of blocks holding a stored block, from the top (the largest by) down.
    std::vector<int64_t> rowsFromTop() const;
    // Calls run(first, end) for each run of neighbouring stored blocks [first, end) of row `by`
    // within columns [bx0, bx1), west to east.
    template <class Run>
    void forEachRun(int64_t by, int64_t bx0, int64_t bx1, const Run& run) const {
        bx0 = std::max<int64_t>(0, bx0);
        bx1 = std::min(across_, bx1);
        if (by < 0 || by >= across_ || bx0 >= bx1) {
            return;
        }
        if (all_) {
            run(bx0, bx1);
            return;
        }
        requireSealed();
        auto it = std::lower_bound(keys_.begin(), keys_.end(), by * across_ + bx0);
        while (it != keys_.end() && *it < by * across_ + bx1) {
            const int64_t first = *it - by * across_;
            int64_t end = first + 1;
            ++it;
            while (it != keys_.end() && *it == by * across_ + end && end < bx1) {
                ++end;
                ++it;
            }
            run(first, end);
        }
    }

private:
    void requireSealed() const;
    int64_t across_ = 0;
    bool all_ = false;
    bool sealed_ = true;
    std::vector<int64_t> keys_; // by * across + bx, ascending once sealed
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
    const BlockMask& mask() const { return mask_; }
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
    std::vector<PixelBytes> blocks_; // the stored blocks, in the mask's order (BlockMask::slot)
};

} // namespace pyramid
