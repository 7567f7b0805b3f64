// The DXT encoders (libsquish and stb_dxt): used by the ortho encoders only, so that the
// runtime, which only decodes (dxt_codec.cpp), links neither.
#include "formats/dxt_codec.hpp"

#include <squish.h>
#include <stb/stb_dxt.h>

#include <algorithm>

#include "formats/error.hpp"

namespace pyramid {

namespace {

// Quality levels 2 and 3: libsquish's fits. (Its range fit is not offered: stb_dxt is both
// faster and closer.)
int squishFlags(DxtFormat format, int quality) {
    const int flags = format == DxtFormat::Dxt1 ? squish::kDxt1 : squish::kDxt5;
    return flags | (quality >= 3 ? squish::kColourIterativeClusterFit : squish::kColourClusterFit);
}

bool usesStb(int quality) { return quality <= 1; }

// The 4 x 4 blocks of an RGBA image, each compressed by libsquish's per-block
// calls in the calling thread. (squish::CompressImage does the same blocks in
// an OpenMP loop of their own: inside our own parallel loops with one thread, or a single
// tile's handful of blocks, that spawned a team per tile and spun idle threads; tiles are
// already encoded in parallel.) Pixels of partial blocks outside the image are masked out.
//
// stb_dxt takes whole blocks: the pixels of a partial block beyond the image repeat its nearest
// pixel inside, which adds no colour to the block's fit. Its DXT5 blocks are laid out as
// libsquish's (alpha block, then colour block).
void compressBlocks(const uint8_t* rgba, int width, int height, uint8_t* blocks, DxtFormat format, int quality) {
    const size_t blockBytes = format == DxtFormat::Dxt1 ? 8u : 16u;
    const int flags = squishFlags(format, quality);
    const int stbMode = quality == 0 ? STB_DXT_NORMAL : STB_DXT_HIGHQUAL;
    uint8_t block[64];
    for (int by = 0; by < height; by += 4) {
        for (int bx = 0; bx < width; bx += 4) {
            int mask = 0;
            for (int j = 0; j < 4; ++j) {
                for (int i = 0; i < 4; ++i) {
                    const int x = std::min(bx + i, width - 1), y = std::min(by + j, height - 1);
                    std::copy_n(rgba + 4 * (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)), 4,
                                block + 4 * (i + 4 * j));
                    mask |= (bx + i < width && by + j < height) ? 1 << (i + 4 * j) : 0;
                }
            }
            if (usesStb(quality)) {
                stb_compress_dxt_block(blocks, block, format == DxtFormat::Dxt5 ? 1 : 0, stbMode);
            } else {
                squish::CompressMasked(block, mask, blocks, flags);
            }
            blocks += blockBytes;
        }
    }
}

} // namespace

std::vector<uint8_t> encodeDxt(std::span<const uint8_t> pixels, int width, int height, int channels,
                               DxtFormat format, int quality) {
    if (width < 1 || height < 1 || channels < 1 || channels > 4 ||
        pixels.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(channels)) {
        fail("", "DXT tile: pixel buffer does not match " + std::to_string(width) + "x" + std::to_string(height) +
                     "x" + std::to_string(channels));
    }
    if ((channels == 4) != (format == DxtFormat::Dxt5)) {
        fail("", "DXT tile: " + std::to_string(channels) + " channels need " + (channels == 4 ? "DXT5" : "DXT1"));
    }
    // The encoders take RGBA: grey is replicated into R, G and B; missing alpha is opaque.
    const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
    std::vector<uint8_t> rgba(count * 4);
    for (size_t k = 0; k < count; ++k) {
        const uint8_t* p = pixels.data() + k * static_cast<size_t>(channels);
        uint8_t* q = rgba.data() + 4 * k;
        if (channels <= 2) {
            q[0] = q[1] = q[2] = p[0];
            q[3] = 255;
        } else {
            q[0] = p[0];
            q[1] = p[1];
            q[2] = p[2];
            q[3] = channels == 4 ? p[3] : 255;
        }
    }
    std::vector<uint8_t> blocks(dxtBytes(width, height, format));
    compressBlocks(rgba.data(), width, height, blocks.data(), format, quality);
    return blocks;
}

} // namespace pyramid
