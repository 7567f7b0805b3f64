// The DXT encoders (libpyramid's colour fit, libsquish, and stb_dxt's alpha blocks): used by
// the ortho encoders only, so that the runtime, which only decodes (dxt_codec.cpp), links
// none of them.
#include "formats/dxt_codec.hpp"

#include <squish.h>
#include <stb/stb_dxt.h>

#include <algorithm>
#include <array>

#include "formats/dxt_colour_fit.hpp"
#include "formats/error.hpp"

namespace pyramid {

namespace {

// Quality levels 2 and 3: libsquish's fits. (Its range fit is not offered: the colour fit is
// both faster and closer.)
int squishFlags(DxtFormat format, int quality) {
    const int flags = format == DxtFormat::Dxt1 ? squish::kDxt1 : squish::kDxt5;
    return flags | (quality >= 3 ? squish::kColourIterativeClusterFit : squish::kColourClusterFit);
}

// Quality levels 0 and 1: libpyramid's colour fit (dxt_colour_fit.hpp), with one or two
// least-squares refinements.
bool usesColourFit(int quality) { return quality <= 1; }

// One 4 x 4 block as the encoders take it, RGBA: grey replicated into R, G and B, alpha
// opaque but for 4 channels (DXT1 stores none: a grey+alpha image's alpha is dropped).
// Pixels of a partial block beyond the image repeat the nearest pixel inside; the result is
// the mask of the pixels inside (bit i + 4 j).
template <int C>
int gatherBlock(const uint8_t* pixels, int width, int height, int bx, int by, uint8_t* block) {
    const auto expand = [](const uint8_t* p, uint8_t* q) {
        q[0] = p[0];
        q[1] = C >= 3 ? p[1] : p[0];
        q[2] = C >= 3 ? p[2] : p[0];
        q[3] = C == 4 ? p[3] : 255;
    };
    const size_t rowBytes = static_cast<size_t>(width) * C;
    if (bx + 4 <= width && by + 4 <= height) { // a whole block: no clamping
        for (int j = 0; j < 4; ++j) {
            const uint8_t* row = pixels + static_cast<size_t>(by + j) * rowBytes + static_cast<size_t>(bx) * C;
            for (int i = 0; i < 4; ++i) {
                expand(row + i * C, block + 4 * (i + 4 * j));
            }
        }
        return 0xffff;
    }
    int mask = 0;
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            const int x = std::min(bx + i, width - 1), y = std::min(by + j, height - 1);
            expand(pixels + static_cast<size_t>(y) * rowBytes + static_cast<size_t>(x) * C, block + 4 * (i + 4 * j));
            mask |= (bx + i < width && by + j < height) ? 1 << (i + 4 * j) : 0;
        }
    }
    return mask;
}

// The squared differences between a block's pixels inside the image and its decoded pixels:
// R, G and B (DXT1), and A (DXT5). Over the block's 64 bytes at once, each weighed 1 or 0 (a
// loop of fixed length, which the compiler vectorises).
int64_t blockSquaredError(const uint8_t* block, int mask, const uint8_t* encoded, DxtFormat format) {
    uint8_t decoded[64];
    decodeDxtBlock(encoded, format, decoded);
    const int samples = format == DxtFormat::Dxt1 ? 3 : 4;
    const auto weights = [](int m, int n) {
        std::array<uint8_t, 64> w{};
        for (int k = 0; k < 64; ++k) {
            w[static_cast<size_t>(k)] = static_cast<uint8_t>(((m >> (k / 4)) & 1) && k % 4 < n);
        }
        return w;
    };
    static constexpr std::array<uint8_t, 64> kWholeDxt1 = weights(0xffff, 3), kWholeDxt5 = weights(0xffff, 4);
    const std::array<uint8_t, 64> keep = mask != 0xffff ? weights(mask, samples) : samples == 3 ? kWholeDxt1 : kWholeDxt5;
    int squares = 0; // at most 64 x 255^2
    for (int k = 0; k < 64; ++k) {
        const int d = (static_cast<int>(block[k]) - static_cast<int>(decoded[k])) * keep[k];
        squares += d * d;
    }
    return squares;
}

// The 4 x 4 blocks of the image, gathered from its own pixels (no RGBA copy of the whole
// image), each compressed in the calling thread: by the colour fit, a row's blocks eight at a
// time (DXT5: the alpha block by stb_dxt's BC4 encoder), or by libsquish's per-block call
// (squish::CompressImage does the same blocks in an OpenMP loop of its own: inside our own
// parallel loops with one thread, or a single tile's handful of blocks, that spawned a team per
// tile and spun idle threads; tiles are already encoded in parallel).
//
// The colour fit takes whole blocks: the pixels of a partial block beyond the image repeat its
// nearest pixel inside, which adds no colour to the block's fit; libsquish masks them out.
// DXT5 blocks are laid out as libsquish's: alpha block, then colour block.
template <int C>
int64_t compressBlocks(const uint8_t* pixels, int width, int height, uint8_t* blocks, DxtFormat format, int quality,
                       bool measure) {
    const size_t blockBytes = format == DxtFormat::Dxt1 ? 8u : 16u;
    const size_t colourOffset = format == DxtFormat::Dxt1 ? 0u : 8u;
    const int flags = squishFlags(format, quality);
    const int refinements = quality == 0 ? 1 : 2;
    int64_t squares = 0;
    uint8_t block[kDxtColourLanes][64];
    int masks[kDxtColourLanes];
    int fitErrors[kDxtColourLanes];
    const uint8_t* lanes[kDxtColourLanes];
    uint8_t* outputs[kDxtColourLanes];
    for (int l = 0; l < kDxtColourLanes; ++l) {
        lanes[l] = block[l];
    }
    // The blocks in the stream's order (row by row), kDxtColourLanes at a time: groups run on
    // across the rows of blocks, so that only the tile's last group has idle lanes.
    const int blocksAcross = (width + 3) / 4;
    const int64_t blockCount = int64_t{blocksAcross} * ((height + 3) / 4);
    for (int64_t first = 0; first < blockCount; first += kDxtColourLanes) {
        const int count = static_cast<int>(std::min<int64_t>(kDxtColourLanes, blockCount - first));
        for (int l = 0; l < count; ++l) {
            const int64_t k = first + l;
            const int bx = static_cast<int>(k % blocksAcross) * 4, by = static_cast<int>(k / blocksAcross) * 4;
            masks[l] = gatherBlock<C>(pixels, width, height, bx, by, block[l]);
            outputs[l] = blocks + static_cast<size_t>(l) * blockBytes;
        }
        if (usesColourFit(quality)) {
            for (int l = 0; l < count; ++l) {
                outputs[l] += colourOffset;
            }
            encodeDxtColourBlocks(lanes, outputs, count, refinements, measure ? fitErrors : nullptr);
            if (format == DxtFormat::Dxt5) {
                for (int l = 0; l < count; ++l) {
                    uint8_t alpha[16];
                    for (int k = 0; k < 16; ++k) {
                        alpha[k] = block[l][4 * k + 3];
                    }
                    stb_compress_bc4_block(outputs[l] - colourOffset, alpha);
                }
            }
        } else {
            for (int l = 0; l < count; ++l) {
                squish::CompressMasked(block[l], masks[l], outputs[l], flags);
            }
        }
        for (int l = 0; l < count; ++l) {
            if (measure) {
                // A whole DXT1 block's error is the fit's own (the same sum); partial blocks
                // count their pixels inside only, DXT5 blocks their alpha too.
                const bool fitError = usesColourFit(quality) && format == DxtFormat::Dxt1 && masks[l] == 0xffff;
                squares += fitError ? fitErrors[l] : blockSquaredError(block[l], masks[l], blocks, format);
            }
            blocks += blockBytes;
        }
    }
    return squares;
}

} // namespace

std::vector<uint8_t> encodeDxt(std::span<const uint8_t> pixels, int width, int height, int channels,
                               DxtFormat format, int quality) {
    return encodeDxt(pixels, width, height, channels, format, quality, nullptr);
}

std::vector<uint8_t> encodeDxt(std::span<const uint8_t> pixels, int width, int height, int channels,
                               DxtFormat format, int quality, int64_t* squaredError) {
    if (width < 1 || height < 1 || channels < 1 || channels > 4 ||
        pixels.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(channels)) {
        fail("", "DXT tile: pixel buffer does not match " + std::to_string(width) + "x" + std::to_string(height) +
                     "x" + std::to_string(channels));
    }
    if ((channels == 4) != (format == DxtFormat::Dxt5)) {
        fail("", "DXT tile: " + std::to_string(channels) + " channels need " + (channels == 4 ? "DXT5" : "DXT1"));
    }
    std::vector<uint8_t> blocks(dxtBytes(width, height, format));
    const bool measure = squaredError != nullptr;
    int64_t squares = 0;
    switch (channels) {
    case 1: squares = compressBlocks<1>(pixels.data(), width, height, blocks.data(), format, quality, measure); break;
    case 2: squares = compressBlocks<2>(pixels.data(), width, height, blocks.data(), format, quality, measure); break;
    case 3: squares = compressBlocks<3>(pixels.data(), width, height, blocks.data(), format, quality, measure); break;
    default: squares = compressBlocks<4>(pixels.data(), width, height, blocks.data(), format, quality, measure); break;
    }
    if (squaredError) {
        *squaredError = squares;
    }
    return blocks;
}

} // namespace pyramid
