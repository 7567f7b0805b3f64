// The DXT encoders (libpyramid's colour fit, libsquish, and stb_dxt's alpha blocks): used by
// the ortho encoders only, so that the runtime, which only decodes (dxt_codec.cpp), links
// none of them.
#include "formats/dxt_codec.hpp"

#include <squish.h>
#include <stb/stb_dxt.h>

#include <algorithm>
#include <array>
#include <memory>

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

// The colour fit's answers for blocks of one colour, by colour and refinement count: such a
// block's code and error depend on nothing else (each lane of the fit is computed alone, and
// a block of one colour takes no refinement), so a block found here gets the bytes the fit
// would give it. Night, sea and nodata areas are mostly such blocks. Direct-mapped, per thread.
class SolidBlockCache {
public:
    bool find(uint32_t rgb, int refinements, uint8_t* code, int& error) const {
        const Entry& e = entries_[slot(rgb)];
        if (e.key != key(rgb, refinements)) {
            return false;
        }
        std::copy_n(e.code, 8, code);
        error = e.error;
        return true;
    }
    void add(uint32_t rgb, int refinements, const uint8_t* code, int error) {
        Entry& e = entries_[slot(rgb)];
        e.key = key(rgb, refinements);
        std::copy_n(code, 8, e.code);
        e.error = error;
    }

private:
    struct Entry {
        uint32_t key = 0; // 0: empty
        uint8_t code[8];
        int error;
    };
    static uint32_t key(uint32_t rgb, int refinements) { return rgb | static_cast<uint32_t>(refinements + 1) << 24; }
    static size_t slot(uint32_t rgb) { return (rgb * 2654435761u) >> 20; }
    std::array<Entry, 4096> entries_{};
};

// The colour of a gathered block whose 16 pixels have one R, G and B (alpha aside), or -1.
int64_t blockColour(const uint8_t* block) {
    const uint32_t first = block[0] | static_cast<uint32_t>(block[1]) << 8 | static_cast<uint32_t>(block[2]) << 16;
    uint32_t differ = 0;
    for (int k = 1; k < 16; ++k) {
        const uint8_t* px = block + 4 * k;
        differ |= (px[0] | static_cast<uint32_t>(px[1]) << 8 | static_cast<uint32_t>(px[2]) << 16) ^ first;
    }
    return differ == 0 ? int64_t{first} : -1;
}

// The 4 x 4 blocks of the image, gathered from its own pixels (no RGBA copy of the whole
// image), each compressed in the calling thread: by the colour fit, sixteen blocks at a time
// (DXT5: the alpha block by stb_dxt's BC4 encoder), or by libsquish's per-block call
// (squish::CompressImage does the same blocks in an OpenMP loop of its own: inside our own
// parallel loops with one thread, or a single tile's handful of blocks, that spawned a team per
// tile and spun idle threads; tiles are already encoded in parallel).
//
// The colour fit takes whole blocks: the pixels of a partial block beyond the image repeat its
// nearest pixel inside, which adds no colour to the block's fit; libsquish masks them out.
// Blocks of one colour already fitted in this thread are copied from SolidBlockCache; the
// others go to the fit in groups of kDxtColourLanes, in the stream's order (groups run on across
// the rows of blocks, so that only the tile's last group has idle lanes).
// DXT5 blocks are laid out as libsquish's: alpha block, then colour block.
template <int C>
int64_t compressBlocks(const uint8_t* pixels, int width, int height, uint8_t* blocks, DxtFormat format, int quality,
                       bool measure) {
    // Made on a thread's first DXT tile: as a thread_local object, its 64 KB (per channel count)
    // would be part of every thread's static TLS, cleared at every thread's start (OpenMP
    // workers, writer and decoder threads alike), whether it encodes DXT or not.
    thread_local std::unique_ptr<SolidBlockCache> solidCache;
    if (!solidCache) {
        solidCache = std::make_unique<SolidBlockCache>();
    }
    SolidBlockCache& solid = *solidCache;
    const size_t blockBytes = format == DxtFormat::Dxt1 ? 8u : 16u;
    const size_t colourOffset = format == DxtFormat::Dxt1 ? 0u : 8u;
    const int flags = squishFlags(format, quality);
    const int refinements = quality == 0 ? 1 : 2;
    const bool colourFit = usesColourFit(quality);
    int64_t squares = 0;
    uint8_t block[kDxtColourLanes][64];
    int masks[kDxtColourLanes];
    int fitErrors[kDxtColourLanes];
    int64_t colours[kDxtColourLanes];
    const uint8_t* lanes[kDxtColourLanes];
    uint8_t* outputs[kDxtColourLanes];
    for (int l = 0; l < kDxtColourLanes; ++l) {
        lanes[l] = block[l];
    }
    // A block's alpha (DXT5) and its error, once its colour block is written.
    const auto finish = [&](const uint8_t* pixelsOfBlock, int mask, uint8_t* out, int fitError) {
        if (colourFit && format == DxtFormat::Dxt5) {
            uint8_t alpha[16];
            for (int k = 0; k < 16; ++k) {
                alpha[k] = pixelsOfBlock[4 * k + 3];
            }
            stb_compress_bc4_block(out, alpha);
        }
        if (measure) {
            // A whole DXT1 block's error is the fit's own (the same sum); partial blocks count
            // their pixels inside only, DXT5 blocks their alpha too.
            const bool ownError = colourFit && format == DxtFormat::Dxt1 && mask == 0xffff;
            squares += ownError ? fitError : blockSquaredError(pixelsOfBlock, mask, out, format);
        }
    };
    int pending = 0;
    const auto fitPending = [&] {
        encodeDxtColourBlocks(lanes, outputs, pending, refinements, fitErrors);
        for (int l = 0; l < pending; ++l) {
            if (colours[l] >= 0) {
                solid.add(static_cast<uint32_t>(colours[l]), refinements, outputs[l], fitErrors[l]);
            }
            finish(block[l], masks[l], outputs[l] - colourOffset, fitErrors[l]);
        }
        pending = 0;
    };
    const int blocksAcross = (width + 3) / 4;
    const int64_t blockCount = int64_t{blocksAcross} * ((height + 3) / 4);
    for (int64_t k = 0; k < blockCount; ++k) {
        const int bx = static_cast<int>(k % blocksAcross) * 4, by = static_cast<int>(k / blocksAcross) * 4;
        uint8_t* out = blocks + static_cast<size_t>(k) * blockBytes;
        const int l = pending;
        masks[l] = gatherBlock<C>(pixels, width, height, bx, by, block[l]);
        if (!colourFit) {
            squish::CompressMasked(block[l], masks[l], out, flags);
            finish(block[l], masks[l], out, 0);
            continue;
        }
        colours[l] = blockColour(block[l]);
        int error = 0;
        if (colours[l] >= 0 && solid.find(static_cast<uint32_t>(colours[l]), refinements, out + colourOffset, error)) {
            finish(block[l], masks[l], out, error);
            continue;
        }
        outputs[l] = out + colourOffset;
        if (++pending == kDxtColourLanes) {
            fitPending();
        }
    }
    if (pending > 0) {
        fitPending();
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
