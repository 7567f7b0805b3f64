#include "libpyramid/encode/ortho/sparse_level.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

constexpr int64_t B = kSparseBlock;

} // namespace

void BlockMask::store(int64_t bx, int64_t by) {
    if (all_) {
        return;
    }
    const int64_t key = by * across_ + bx;
    if (!keys_.empty() && key <= keys_.back()) {
        sealed_ = false;
    }
    keys_.push_back(key);
}

void BlockMask::seal() {
    if (!sealed_) {
        std::sort(keys_.begin(), keys_.end());
        keys_.erase(std::unique(keys_.begin(), keys_.end()), keys_.end());
        sealed_ = true;
    }
}

void BlockMask::requireSealed() const {
    if (!sealed_) {
        throw std::logic_error("BlockMask: read before seal()");
    }
}

int64_t BlockMask::slot(int64_t bx, int64_t by) const {
    if (bx < 0 || by < 0 || bx >= across_ || by >= across_) {
        return -1;
    }
    if (all_) {
        return by * across_ + bx;
    }
    requireSealed();
    const int64_t key = by * across_ + bx;
    const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
    return it != keys_.end() && *it == key ? it - keys_.begin() : -1;
}

bool BlockMask::meets(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    const int64_t bx0 = std::max<int64_t>(0, x0 / B), bx1 = std::min(across_ - 1, x1 / B);
    const int64_t by0 = std::max<int64_t>(0, y0 / B), by1 = std::min(across_ - 1, y1 / B);
    if (bx0 > bx1 || by0 > by1) {
        return false;
    }
    if (all_) {
        return true;
    }
    requireSealed();
    // Jumps from stored block to stored block: as many steps as rows with blocks in the range.
    auto it = std::lower_bound(keys_.begin(), keys_.end(), by0 * across_ + bx0);
    while (it != keys_.end() && *it <= by1 * across_ + bx1) {
        const int64_t by = *it / across_, bx = *it % across_;
        if (bx >= bx0 && bx <= bx1) {
            return true;
        }
        const int64_t next = bx < bx0 ? by * across_ + bx0 : (by + 1) * across_ + bx0;
        it = std::lower_bound(it, keys_.end(), next);
    }
    return false;
}

std::vector<int64_t> BlockMask::rowsFromTop() const {
    std::vector<int64_t> rows;
    if (all_) {
        for (int64_t by = across_ - 1; by >= 0; --by) {
            rows.push_back(by);
        }
        return rows;
    }
    requireSealed();
    for (auto it = keys_.rbegin(); it != keys_.rend(); ++it) {
        if (rows.empty() || rows.back() != *it / across_) {
            rows.push_back(*it / across_);
        }
    }
    return rows;
}

SparseLevel::SparseLevel(int64_t side, int channels, BlockMask stored)
    : side_(side), across_(blocks(side)), channels_(channels), mask_(std::move(stored)) {
    if (mask_.across() != across_) {
        throw std::logic_error("SparseLevel: a block mask of the wrong size");
    }
    mask_.seal();
    blocks_.resize(static_cast<size_t>(mask_.count()));
    for (PixelBytes& block : blocks_) {
        block.assign(static_cast<size_t>(B * B * channels), 0);
    }
}

uint8_t* SparseLevel::pixel(int64_t x, int64_t y) {
    const int64_t k = mask_.slot(x / B, y / B);
    return k < 0 ? nullptr : blocks_[static_cast<size_t>(k)].data() + ((y % B) * B + x % B) * channels_;
}

void SparseLevel::read(int64_t x, int64_t y, int64_t n, uint8_t* out) const {
    const auto c = static_cast<size_t>(channels_);
    while (n > 0) {
        const int64_t run = std::min(n, B - x % B); // within one block
        const int64_t k = mask_.slot(x / B, y / B);
        if (k < 0) {
            std::fill_n(out, static_cast<size_t>(run) * c, uint8_t{0});
        } else {
            std::copy_n(blocks_[static_cast<size_t>(k)].data() + static_cast<size_t>((y % B) * B + x % B) * c,
                        static_cast<size_t>(run) * c, out);
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
    // A block is stored when one of the four under it is.
    out.mask_ = BlockMask(out.side_, mask_.all() ? 1 : 0);
    if (!mask_.all()) {
        for (int64_t k = 0; k < mask_.count(); ++k) {
            const auto [bx, by] = mask_.block(k);
            out.mask_.store(bx / 2, by / 2);
        }
        out.mask_.seal();
    }
    out.blocks_.resize(static_cast<size_t>(out.mask_.count()));
    const auto c = static_cast<size_t>(channels_);
    parallelFor(out.mask_.count(), threads, [&](int64_t b) {
        const auto [bx, by] = out.mask_.block(b);
        // The four blocks under it as one image of 2B x 2B (0 where not stored), halved.
        Image8 four(static_cast<int>(2 * B), static_cast<int>(2 * B), channels_);
        for (int q = 0; q < 4; ++q) {
            const int64_t k = mask_.slot(2 * bx + (q & 1), 2 * by + (q >> 1));
            if (k < 0) {
                continue;
            }
            const PixelBytes& block = blocks_[static_cast<size_t>(k)];
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
