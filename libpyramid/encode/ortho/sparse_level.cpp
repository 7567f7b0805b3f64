#include "libpyramid/encode/ortho/sparse_level.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

constexpr int64_t B = kSparseBlock;

} // namespace

bool BlockMask::meets(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    for (int64_t by = std::max<int64_t>(0, y0 / B); by <= std::min(across_ - 1, y1 / B); ++by) {
        for (int64_t bx = std::max<int64_t>(0, x0 / B); bx <= std::min(across_ - 1, x1 / B); ++bx) {
            if (stored(bx, by)) {
                return true;
            }
        }
    }
    return false;
}

SparseLevel::SparseLevel(int64_t side, int channels, BlockMask stored)
    : side_(side), across_(blocks(side)), channels_(channels), mask_(std::move(stored)),
      blocks_(static_cast<size_t>(across_ * across_)) {
    if (mask_.across() != across_) {
        throw std::logic_error("SparseLevel: a block mask of the wrong size");
    }
    for (int64_t by = 0; by < across_; ++by) {
        for (int64_t bx = 0; bx < across_; ++bx) {
            if (mask_.stored(bx, by)) {
                blocks_[static_cast<size_t>(by * across_ + bx)].assign(static_cast<size_t>(B * B * channels), 0);
            }
        }
    }
}

uint8_t* SparseLevel::pixel(int64_t x, int64_t y) {
    PixelBytes& block = blocks_[static_cast<size_t>((y / B) * across_ + x / B)];
    return block.empty() ? nullptr : block.data() + ((y % B) * B + x % B) * channels_;
}

void SparseLevel::read(int64_t x, int64_t y, int64_t n, uint8_t* out) const {
    const auto c = static_cast<size_t>(channels_);
    while (n > 0) {
        const int64_t run = std::min(n, B - x % B); // within one block
        const PixelBytes& block = blocks_[static_cast<size_t>((y / B) * across_ + x / B)];
        if (block.empty()) {
            std::fill_n(out, static_cast<size_t>(run) * c, uint8_t{0});
        } else {
            std::copy_n(block.data() + static_cast<size_t>((y % B) * B + x % B) * c, static_cast<size_t>(run) * c, out);
        }
        out += static_cast<size_t>(run) * c;
        x += run;
        n -= run;
    }
}

void SparseLevel::write(const Image8& part, int64_t x, int64_t y) {
    const auto c = static_cast<size_t>(channels_);
    for (int j = 0; j < part.height; ++j) {
        int64_t i = 0;
        while (i < part.width) {
            const int64_t px = x + i;
            const int64_t run = std::min<int64_t>(part.width - i, B - px % B);
            const uint8_t* from = part.at(static_cast<int>(i), j);
            const size_t bytes = static_cast<size_t>(run) * c;
            if (uint8_t* to = pixel(px, y + j)) {
                std::copy_n(from, bytes, to);
            } else if (std::any_of(from, from + bytes, [](uint8_t v) { return v != 0; })) {
                throw std::logic_error("SparseLevel: colour where the map was known not to reach");
            }
            i += run;
        }
    }
}

SparseLevel SparseLevel::reduced(const ColourAverager& averager, int threads) const {
    SparseLevel out;
    out.side_ = side_ / 2;
    out.across_ = blocks(out.side_);
    out.channels_ = channels_;
    out.mask_ = BlockMask(out.side_, 0);
    out.blocks_.resize(static_cast<size_t>(out.across_ * out.across_));
    for (int64_t by = 0; by < out.across_; ++by) {
        for (int64_t bx = 0; bx < out.across_; ++bx) {
            for (int q = 0; q < 4; ++q) {
                if (stored(2 * bx + (q & 1), 2 * by + (q >> 1))) {
                    out.mask_.store(bx, by);
                }
            }
        }
    }
    const auto c = static_cast<size_t>(channels_);
    parallelFor(out.across_ * out.across_, threads, [&](int64_t b) {
        const int64_t bx = b % out.across_, by = b / out.across_;
        if (!out.stored(bx, by)) {
            return;
        }
        // The four blocks under it as one image of 2B x 2B (0 where not stored), halved.
        Image8 four(static_cast<int>(2 * B), static_cast<int>(2 * B), channels_);
        for (int q = 0; q < 4; ++q) {
            const int64_t sx = 2 * bx + (q & 1), sy = 2 * by + (q >> 1);
            if (!stored(sx, sy)) {
                continue;
            }
            const PixelBytes& block = blocks_[static_cast<size_t>(sy * across_ + sx)];
            for (int64_t j = 0; j < B; ++j) {
                std::copy_n(block.data() + static_cast<size_t>(j * B) * c, static_cast<size_t>(B) * c,
                            four.at(static_cast<int>((q & 1) * B), static_cast<int>((q >> 1) * B + j)));
            }
        }
        out.blocks_[static_cast<size_t>(b)] = std::move(averager.reduce(four).pixels);
    });
    return out;
}

} // namespace pyramid
