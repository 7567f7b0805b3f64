// The DXT encoder's own error measure (encodeDxt with squaredError, which the ortho encoder
// reports as each level's dxt_psnr_db) against decoding the whole tile again, and its blocks
// against direct per-block stb_dxt calls on every layout the encoder gathers blocks from
// (1 to 4 channels, whole and partial blocks).
#include <gtest/gtest.h>
#include <stb/stb_dxt.h>

#include <algorithm>
#include <random>

#include "formats/dxt_codec.hpp"

namespace pyramid {
namespace {

// A smooth colour field with grain: blocks of every kind (flat, graded, noisy).
std::vector<uint8_t> image(int width, int height, int channels, unsigned seed) {
    std::mt19937 random(seed);
    std::vector<uint8_t> pixels;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < channels; ++c) {
                const int smooth = (x * (3 + c) + y * (5 - c)) * 4 % 256;
                const int grain = static_cast<int>(random() % 41) - 20;
                const bool flat = (x / 4 + y / 4) % 5 == 0; // some constant blocks
                pixels.push_back(static_cast<uint8_t>(flat ? 90 + 20 * c : std::clamp(smooth + grain, 0, 255)));
            }
        }
    }
    return pixels;
}

// The samples a DXT tile is compared with: RGB (grey replicated) for DXT1, RGBA for DXT5.
std::vector<uint8_t> reference(const std::vector<uint8_t>& pixels, int channels) {
    if (channels >= 3) {
        return pixels;
    }
    std::vector<uint8_t> rgb;
    for (size_t k = 0; k < pixels.size(); k += static_cast<size_t>(channels)) {
        rgb.insert(rgb.end(), {pixels[k], pixels[k], pixels[k]});
    }
    return rgb;
}

TEST(DxtEncoder, SquaredErrorIsTheDecodedTilesError) {
    for (const auto& [width, height] : {std::pair{16, 16}, std::pair{10, 7}, std::pair{4, 4}, std::pair{1, 3}}) {
        for (int channels = 1; channels <= 4; ++channels) {
            const auto pixels = image(width, height, channels, static_cast<unsigned>(width * 10 + channels));
            const DxtFormat format = channels == 4 ? DxtFormat::Dxt5 : DxtFormat::Dxt1;
            for (int quality = 0; quality < kDxtQualityLevels; ++quality) {
                int64_t squares = -1;
                const auto blob = encodeDxt(pixels, width, height, channels, format, quality, &squares);
                EXPECT_EQ(blob, encodeDxt(pixels, width, height, channels, format, quality));
                const auto back = decodeDxt(blob, width, height, format, "t");
                const auto ref = reference(pixels, channels);
                ASSERT_EQ(back.size(), ref.size());
                int64_t expected = 0;
                for (size_t k = 0; k < back.size(); ++k) {
                    const int d = static_cast<int>(back[k]) - static_cast<int>(ref[k]);
                    expected += d * d;
                }
                EXPECT_EQ(squares, expected) << width << "x" << height << "x" << channels << " quality " << quality;
            }
        }
    }
}

// The blocks gathered from 1- to 4-channel pixels, partial blocks included, are the blocks
// stb_dxt makes of their RGBA expansion (edge pixels repeated, alpha opaque without 4 channels).
TEST(DxtEncoder, StbBlocksFromEveryLayout) {
    const int width = 22, height = 13;
    for (int channels = 1; channels <= 4; ++channels) {
        const auto pixels = image(width, height, channels, 7u + static_cast<unsigned>(channels));
        const DxtFormat format = channels == 4 ? DxtFormat::Dxt5 : DxtFormat::Dxt1;
        const size_t blockBytes = channels == 4 ? 16 : 8;
        for (int quality = 0; quality <= 1; ++quality) {
            std::vector<uint8_t> expected;
            for (int by = 0; by < height; by += 4) {
                for (int bx = 0; bx < width; bx += 4) {
                    uint8_t block[64];
                    for (int j = 0; j < 4; ++j) {
                        for (int i = 0; i < 4; ++i) {
                            const int x = std::min(bx + i, width - 1), y = std::min(by + j, height - 1);
                            const uint8_t* p = &pixels[static_cast<size_t>((y * width + x) * channels)];
                            uint8_t* q = block + 4 * (i + 4 * j);
                            q[0] = p[0];
                            q[1] = channels >= 3 ? p[1] : p[0];
                            q[2] = channels >= 3 ? p[2] : p[0];
                            q[3] = channels == 4 ? p[3] : 255;
                        }
                    }
                    uint8_t out[16];
                    stb_compress_dxt_block(out, block, channels == 4, quality == 0 ? STB_DXT_NORMAL : STB_DXT_HIGHQUAL);
                    expected.insert(expected.end(), out, out + blockBytes);
                }
            }
            EXPECT_EQ(encodeDxt(pixels, width, height, channels, format, quality), expected)
                << channels << " channels, quality " << quality;
        }
    }
}

TEST(DxtEncoder, OneBlockDecodesAsTheTile) {
    for (const DxtFormat format : {DxtFormat::Dxt1, DxtFormat::Dxt5}) {
        const int channels = format == DxtFormat::Dxt1 ? 3 : 4;
        const auto blob = encodeDxt(image(4, 4, channels, 3), 4, 4, channels, format, 1);
        uint8_t rgba[64];
        decodeDxtBlock(blob.data(), format, rgba);
        const auto tile = decodeDxt(blob, 4, 4, format, "t");
        for (int k = 0; k < 16; ++k) {
            for (int c = 0; c < channels; ++c) {
                EXPECT_EQ(rgba[4 * k + c], tile[static_cast<size_t>(k * channels + c)]);
            }
        }
    }
}

} // namespace
} // namespace pyramid
