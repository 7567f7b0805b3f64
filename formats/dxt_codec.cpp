#include "formats/dxt_codec.hpp"

#include <algorithm>

#include "formats/error.hpp"

namespace pyramid {

namespace {

// One 4 x 4 block decoded to RGBA exactly as libsquish 1.15 decodes it (squish::Decompress: the
// endpoints widened from 5:6:5 by bit replication, the interpolated colours and alphas by
// truncating integer division), without linking it: the runtime decodes, only the encoders
// need libsquish. tests/formats_tiles_test.cpp checks the two agree.
void decodeColourBlock(uint8_t* rgba, const uint8_t* bytes, bool isDxt1) {
    uint8_t codes[16];
    int endpoints[2];
    for (int e = 0; e < 2; ++e) {
        const int value = bytes[2 * e] | (bytes[2 * e + 1] << 8);
        const int red = (value >> 11) & 0x1f, green = (value >> 5) & 0x3f, blue = value & 0x1f;
        uint8_t* c = codes + 4 * e;
        c[0] = static_cast<uint8_t>((red << 3) | (red >> 2));
        c[1] = static_cast<uint8_t>((green << 2) | (green >> 4));
        c[2] = static_cast<uint8_t>((blue << 3) | (blue >> 2));
        c[3] = 255;
        endpoints[e] = value;
    }
    const bool threeColours = isDxt1 && endpoints[0] <= endpoints[1];
    for (int i = 0; i < 3; ++i) {
        const int c = codes[i], d = codes[4 + i];
        if (threeColours) {
            codes[8 + i] = static_cast<uint8_t>((c + d) / 2);
            codes[12 + i] = 0;
        } else {
            codes[8 + i] = static_cast<uint8_t>((2 * c + d) / 3);
            codes[12 + i] = static_cast<uint8_t>((c + 2 * d) / 3);
        }
    }
    codes[11] = 255;
    codes[15] = threeColours ? 0 : 255;
    for (int k = 0; k < 16; ++k) {
        const int index = (bytes[4 + k / 4] >> (2 * (k % 4))) & 3;
        std::copy_n(codes + 4 * index, 4, rgba + 4 * k);
    }
}

void decodeAlphaBlock(uint8_t* rgba, const uint8_t* bytes) {
    const int alpha0 = bytes[0], alpha1 = bytes[1];
    uint8_t codes[8] = {static_cast<uint8_t>(alpha0), static_cast<uint8_t>(alpha1)};
    if (alpha0 <= alpha1) {
        for (int i = 1; i < 5; ++i) {
            codes[1 + i] = static_cast<uint8_t>(((5 - i) * alpha0 + i * alpha1) / 5);
        }
        codes[6] = 0;
        codes[7] = 255;
    } else {
        for (int i = 1; i < 7; ++i) {
            codes[1 + i] = static_cast<uint8_t>(((7 - i) * alpha0 + i * alpha1) / 7);
        }
    }
    for (int group = 0; group < 2; ++group) {
        const uint8_t* src = bytes + 2 + 3 * group;
        const int value = src[0] | (src[1] << 8) | (src[2] << 16);
        for (int j = 0; j < 8; ++j) {
            rgba[4 * (8 * group + j) + 3] = codes[(value >> (3 * j)) & 7];
        }
    }
}

} // namespace

void decodeDxtBlock(const uint8_t* bytes, DxtFormat format, uint8_t* rgba) {
    if (format == DxtFormat::Dxt1) {
        decodeColourBlock(rgba, bytes, true);
    } else {
        decodeColourBlock(rgba, bytes + 8, false);
        decodeAlphaBlock(rgba, bytes);
    }
}

namespace {

void decompressBlocks(uint8_t* rgba, int width, int height, const uint8_t* blocks, DxtFormat format) {
    const size_t blockBytes = format == DxtFormat::Dxt1 ? 8u : 16u;
    uint8_t block[64];
    for (int by = 0; by < height; by += 4) {
        for (int bx = 0; bx < width; bx += 4) {
            decodeDxtBlock(blocks, format, block);
            blocks += blockBytes;
            for (int j = 0; j < 4 && by + j < height; ++j) {
                for (int i = 0; i < 4 && bx + i < width; ++i) {
                    std::copy_n(block + 4 * (i + 4 * j), 4,
                                rgba + 4 * (static_cast<size_t>(by + j) * static_cast<size_t>(width) + static_cast<size_t>(bx + i)));
                }
            }
        }
    }
}

} // namespace

size_t dxtBytes(int width, int height, DxtFormat format) {
    const size_t blocks = static_cast<size_t>((width + 3) / 4) * static_cast<size_t>((height + 3) / 4);
    return blocks * (format == DxtFormat::Dxt1 ? 8u : 16u);
}

std::vector<uint8_t> decodeDxt(std::span<const uint8_t> blob, int width, int height, DxtFormat format,
                               const std::string& where) {
    if (width < 1 || height < 1 || width > 65536 || height > 65536) {
        fail(where, "invalid DXT tile size " + std::to_string(width) + "x" + std::to_string(height));
    }
    const size_t expected = dxtBytes(width, height, format);
    if (blob.size() != expected) {
        fail(where, "DXT tile of " + std::to_string(blob.size()) + " bytes, expected " + std::to_string(expected));
    }
    const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
    std::vector<uint8_t> rgba(count * 4);
    decompressBlocks(rgba.data(), width, height, blob.data(), format);
    if (format == DxtFormat::Dxt5) {
        return rgba;
    }
    std::vector<uint8_t> rgb(count * 3);
    for (size_t k = 0; k < count; ++k) {
        rgb[3 * k] = rgba[4 * k];
        rgb[3 * k + 1] = rgba[4 * k + 1];
        rgb[3 * k + 2] = rgba[4 * k + 2];
    }
    return rgb;
}

} // namespace pyramid
