// The DXT encoder's own error measure (encodeDxt with squaredError, which the ortho encoder
// reports as each level's dxt_psnr_db) against decoding the whole tile again; its blocks
// against direct per-block calls of the colour fit on every layout the encoder gathers blocks
// from (1 to 4 channels, whole and partial blocks) and for blocks of one colour; and the colour fit itself: the best colour
// 5:6:5 can give a flat block, exact blocks for colours on a 5:6:5 palette, lanes that do not
// see each other, no more error than stb_dxt's high-quality mode, and the error it reports.
#include <gtest/gtest.h>
#include <stb/stb_dxt.h>

#include <algorithm>
#include <array>
#include <memory>
#include <random>

#include "formats/dxt_codec.hpp"
#include "formats/dxt_colour_fit.hpp"
#include "formats/error.hpp"
#include "tests/support/dxt_blocks.hpp"

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
// the colour fit makes of their RGBA expansion, one block at a time (edge pixels repeated,
// alpha opaque without 4 channels; DXT5: stb_dxt's BC4 alpha block first).
TEST(DxtEncoder, ColourFitBlocksFromEveryLayout) {
    const int width = 46, height = 13; // 12 blocks a row: a group of 8 lanes and one of 4
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
                    test::referenceDxtBlock(block, channels == 4, quality, out);
                    expected.insert(expected.end(), out, out + blockBytes);
                }
            }
            EXPECT_EQ(encodeDxt(pixels, width, height, channels, format, quality), expected)
                << channels << " channels, quality " << quality;
        }
    }
}

// Blocks of one colour (copied from the encoder's per-thread table of those it has fitted)
// are the blocks the colour fit makes of them, whatever fitted before: thousands of colours,
// repeated, colliding in the table and evicting each other, between blocks of several colours,
// with varying alpha for DXT5; and the error reported is the decoded tile's.
TEST(DxtEncoder, OneColourBlocksAreTheColourFitsWhateverCameBefore) {
    const int width = 256, height = 256;
    for (const int channels : {3, 4}) {
        std::mt19937 random(60u + static_cast<unsigned>(channels));
        std::vector<uint32_t> palette(6000);
        for (uint32_t& c : palette) {
            c = random() & 0xffffffu;
        }
        std::vector<uint8_t> pixels(static_cast<size_t>(width) * height * channels);
        for (int by = 0; by < height; by += 4) {
            for (int bx = 0; bx < width; bx += 4) {
                const bool oneColour = random() % 4 != 0;
                const uint32_t colour = palette[random() % (random() % 2 == 0 ? 40 : palette.size())];
                for (int j = 0; j < 4; ++j) {
                    for (int i = 0; i < 4; ++i) {
                        uint8_t* p = &pixels[(static_cast<size_t>(by + j) * width + static_cast<size_t>(bx + i)) * channels];
                        const uint32_t c = oneColour ? colour : static_cast<uint32_t>(random());
                        for (int k = 0; k < channels; ++k) {
                            p[k] = static_cast<uint8_t>(k == 3 ? random() : c >> (8 * k));
                        }
                    }
                }
            }
        }
        const DxtFormat format = channels == 4 ? DxtFormat::Dxt5 : DxtFormat::Dxt1;
        const size_t blockBytes = channels == 4 ? 16 : 8;
        for (int quality = 0; quality <= 1; ++quality) {
            int64_t squares = -1;
            const std::vector<uint8_t> blob = encodeDxt(pixels, width, height, channels, format, quality, &squares);
            ASSERT_EQ(blob.size(), static_cast<size_t>(width / 4) * (height / 4) * blockBytes);
            size_t at = 0;
            for (int by = 0; by < height; by += 4) {
                for (int bx = 0; bx < width; bx += 4, at += blockBytes) {
                    uint8_t block[64];
                    for (int j = 0; j < 4; ++j) {
                        for (int i = 0; i < 4; ++i) {
                            const uint8_t* p = &pixels[(static_cast<size_t>(by + j) * width + static_cast<size_t>(bx + i)) * channels];
                            std::copy_n(p, 3, block + 4 * (i + 4 * j));
                            block[4 * (i + 4 * j) + 3] = channels == 4 ? p[3] : 255;
                        }
                    }
                    uint8_t out[16];
                    test::referenceDxtBlock(block, channels == 4, quality, out);
                    ASSERT_TRUE(std::equal(out, out + blockBytes, blob.begin() + static_cast<std::ptrdiff_t>(at)))
                        << channels << " channels, quality " << quality << ", block " << bx << "," << by;
                }
            }
            const std::vector<uint8_t> back = decodeDxt(blob, width, height, format, "t");
            int64_t expected = 0;
            for (size_t k = 0; k < back.size(); ++k) {
                const int d = static_cast<int>(back[k]) - static_cast<int>(pixels[k]);
                expected += d * d;
            }
            EXPECT_EQ(squares, expected) << channels << " channels, quality " << quality;
        }
    }
}

// The decoder's colour for 5:6:5 endpoint codes and a 2-bit index (dxt_codec.hpp), per channel.
int decodedChannel(int a, int b, int index, int bits) {
    const auto expand = [bits](int q) { return bits == 5 ? (q << 3) | (q >> 2) : (q << 2) | (q >> 4); };
    const int ea = expand(a), eb = expand(b);
    return index == 0 ? ea : index == 1 ? eb : index == 2 ? (2 * ea + eb) / 3 : (ea + 2 * eb) / 3;
}

// A block of one colour decodes, channel by channel, to the closest colour any pair of 5:6:5
// endpoints gives at one shared index (searched here over every pair).
TEST(DxtColourFit, FlatBlocksTakeTheClosestColourFiveSixFiveCanGive) {
    const auto closest = [](int v, int bits) {
        int best = 255;
        for (int a = 0; a < (1 << bits); ++a) {
            for (int b = 0; b < (1 << bits); ++b) {
                best = std::min({best, std::abs(decodedChannel(a, b, 0, bits) - v), std::abs(decodedChannel(a, b, 2, bits) - v)});
            }
        }
        return best;
    };
    std::array<int, 256> best5{}, best6{};
    for (int v = 0; v < 256; ++v) {
        best5[static_cast<size_t>(v)] = closest(v, 5);
        best6[static_cast<size_t>(v)] = closest(v, 6);
    }
    std::mt19937 random(5);
    for (int n = 0; n < 600; ++n) {
        // Every grey level, then random colours.
        const std::array<int, 3> colour = n < 256 ? std::array<int, 3>{n, n, n}
                                                  : std::array<int, 3>{static_cast<int>(random() % 256),
                                                                       static_cast<int>(random() % 256),
                                                                       static_cast<int>(random() % 256)};
        uint8_t block[64];
        for (int k = 0; k < 16; ++k) {
            for (int c = 0; c < 3; ++c) {
                block[4 * k + c] = static_cast<uint8_t>(colour[static_cast<size_t>(c)]);
            }
            block[4 * k + 3] = 255;
        }
        for (int refinements = 1; refinements <= 2; ++refinements) {
            uint8_t out[8];
            const uint8_t* in[1] = {block};
            uint8_t* o[1] = {out};
            encodeDxtColourBlocks(in, o, 1, refinements);
            uint8_t rgba[64];
            decodeDxtBlock(out, DxtFormat::Dxt1, rgba);
            for (int k = 0; k < 16; ++k) {
                for (int c = 0; c < 3; ++c) {
                    const int v = colour[static_cast<size_t>(c)];
                    EXPECT_EQ(std::abs(rgba[4 * k + c] - v), (c == 1 ? best6 : best5)[static_cast<size_t>(v)])
                        << "colour " << colour[0] << "," << colour[1] << "," << colour[2] << " channel " << c;
                }
                EXPECT_EQ(rgba[4 * k + 3], 255); // never the transparent index
            }
        }
    }
}

// Blocks whose pixels are a 5:6:5 pair's four colours, both endpoints among them, are found
// exactly: no error at all.
TEST(DxtColourFit, BlocksOnAFiveSixFivePaletteAreExact) {
    std::mt19937 random(11);
    for (int n = 0; n < 500; ++n) {
        const int a[3] = {static_cast<int>(random() % 32), static_cast<int>(random() % 64), static_cast<int>(random() % 32)};
        int b[3] = {static_cast<int>(random() % 32), static_cast<int>(random() % 64), static_cast<int>(random() % 32)};
        if (a[0] == b[0] && a[1] == b[1] && a[2] == b[2]) {
            b[1] ^= 1;
        }
        uint8_t block[64];
        for (int k = 0; k < 16; ++k) {
            const int index = k < 4 ? k : static_cast<int>(random() % 4); // every colour present
            for (int c = 0; c < 3; ++c) {
                block[4 * k + c] = static_cast<uint8_t>(decodedChannel(a[c], b[c], index, c == 1 ? 6 : 5));
            }
            block[4 * k + 3] = 255;
        }
        uint8_t out[8];
        const uint8_t* in[1] = {block};
        uint8_t* o[1] = {out};
        encodeDxtColourBlocks(in, o, 1, 1);
        uint8_t rgba[64];
        decodeDxtBlock(out, DxtFormat::Dxt1, rgba);
        for (int k = 0; k < 64; ++k) {
            ASSERT_EQ(rgba[k], block[k]) << "block " << n << " byte " << k;
        }
    }
}

// Eight blocks encoded side by side give each block's bytes alone, whatever the group size.
TEST(DxtColourFit, LanesDoNotSeeEachOther) {
    const auto pixels = image(4 * kDxtColourLanes, 4, 4, 21);
    std::vector<std::array<uint8_t, 64>> blocks(kDxtColourLanes);
    for (int l = 0; l < kDxtColourLanes; ++l) {
        for (int j = 0; j < 4; ++j) {
            std::copy_n(&pixels[static_cast<size_t>((j * 4 * kDxtColourLanes + 4 * l) * 4)], 16,
                        blocks[static_cast<size_t>(l)].data() + 16 * j);
        }
    }
    for (int refinements = 0; refinements <= 3; ++refinements) {
        std::vector<std::array<uint8_t, 8>> alone(kDxtColourLanes), together(kDxtColourLanes);
        for (int l = 0; l < kDxtColourLanes; ++l) {
            const uint8_t* in[1] = {blocks[static_cast<size_t>(l)].data()};
            uint8_t* o[1] = {alone[static_cast<size_t>(l)].data()};
            encodeDxtColourBlocks(in, o, 1, refinements);
        }
        for (int count = 1; count <= kDxtColourLanes; ++count) {
            const uint8_t* in[kDxtColourLanes];
            uint8_t* o[kDxtColourLanes];
            for (int l = 0; l < count; ++l) {
                in[l] = blocks[static_cast<size_t>(l)].data();
                o[l] = together[static_cast<size_t>(l)].data();
            }
            encodeDxtColourBlocks(in, o, count, refinements);
            for (int l = 0; l < count; ++l) {
                EXPECT_EQ(together[static_cast<size_t>(l)], alone[static_cast<size_t>(l)])
                    << "lane " << l << " of " << count << ", " << refinements << " refinements";
            }
        }
    }
}

// Every vector width this machine runs (4 lanes everywhere, 8 with AVX2, 16 with AVX-512) gives
// the 4-lane fit's bytes and errors, whole groups and groups that leave lanes idle alike; and
// encodeDxtColourBlocks is the widest of them.
TEST(DxtColourFit, EveryVectorWidthGivesTheSameBlocks) {
    const int side = 64;
    const auto pixels = image(side, side, 4, 7);
    std::vector<std::array<uint8_t, 64>> blocks;
    for (int by = 0; by < side; by += 4) {
        for (int bx = 0; bx < side; bx += 4) {
            auto& block = blocks.emplace_back();
            for (int j = 0; j < 4; ++j) {
                std::copy_n(&pixels[static_cast<size_t>(((by + j) * side + bx) * 4)], 16, block.data() + 16 * j);
            }
        }
    }
    const auto encodeAll = [&](int lanes, int group, int refinements, std::vector<int>& errors) {
        std::vector<uint8_t> bytes(blocks.size() * 8);
        errors.assign(blocks.size(), -1);
        for (size_t first = 0; first < blocks.size(); first += static_cast<size_t>(group)) {
            const int count = static_cast<int>(std::min(blocks.size() - first, static_cast<size_t>(group)));
            const uint8_t* in[kDxtColourLanes];
            uint8_t* out[kDxtColourLanes];
            for (int l = 0; l < count; ++l) {
                in[l] = blocks[first + static_cast<size_t>(l)].data();
                out[l] = &bytes[(first + static_cast<size_t>(l)) * 8];
            }
            if (lanes == 0) {
                encodeDxtColourBlocks(in, out, count, refinements, &errors[first]);
            } else {
                encodeDxtColourBlocksIn(lanes, in, out, count, refinements, &errors[first]);
            }
        }
        return bytes;
    };
    EXPECT_TRUE(dxtColourLanesAvailable(4));
    EXPECT_TRUE(dxtColourLanesAvailable(dxtColourLanes()));
    EXPECT_FALSE(dxtColourLanesAvailable(5));
    EXPECT_THROW(encodeAll(5, 16, 1, *std::make_unique<std::vector<int>>()), Error);
    for (int refinements = 0; refinements <= 2; ++refinements) {
        for (int group : {16, 13, 3}) {
            std::vector<int> expectedErrors, errors;
            const auto expected = encodeAll(4, group, refinements, expectedErrors);
            EXPECT_EQ(std::count(expectedErrors.begin(), expectedErrors.end(), -1), 0);
            for (int lanes : {0, 8, 16}) {
                if (lanes != 0 && !dxtColourLanesAvailable(lanes)) {
                    continue;
                }
                EXPECT_EQ(encodeAll(lanes, group, refinements, errors), expected)
                    << lanes << " lanes, groups of " << group << ", " << refinements << " refinements";
                EXPECT_EQ(errors, expectedErrors) << lanes << " lanes";
            }
        }
    }
}

// On an image with flat, graded and noisy blocks, the default level's blocks are no further
// from the pixels than stb_dxt's high-quality blocks, and the fastest level's no further than
// stb_dxt's normal ones.
TEST(DxtColourFit, NoMoreErrorThanStbDxt) {
    const int width = 64, height = 64;
    const auto pixels = image(width, height, 4, 99);
    for (int quality = 0; quality <= 1; ++quality) {
        int64_t ours = 0, stb = 0, reported = 0;
        for (int by = 0; by < height; by += 4) {
            for (int bx = 0; bx < width; bx += 4) {
                uint8_t block[64];
                for (int j = 0; j < 4; ++j) {
                    for (int i = 0; i < 4; ++i) {
                        const uint8_t* p = &pixels[static_cast<size_t>(((by + j) * width + bx + i) * 4)];
                        std::copy_n(p, 3, block + 4 * (i + 4 * j));
                        block[4 * (i + 4 * j) + 3] = 255;
                    }
                }
                uint8_t a[8], b[8], da[64], db[64];
                const uint8_t* in[1] = {block};
                uint8_t* o[1] = {a};
                int error = -1;
                encodeDxtColourBlocks(in, o, 1, quality + 1, &error);
                reported += error;
                stb_compress_dxt_block(b, block, 0, quality == 0 ? STB_DXT_NORMAL : STB_DXT_HIGHQUAL);
                decodeDxtBlock(a, DxtFormat::Dxt1, da);
                decodeDxtBlock(b, DxtFormat::Dxt1, db);
                for (int k = 0; k < 64; ++k) {
                    if (k % 4 != 3) {
                        ours += (da[k] - block[k]) * (da[k] - block[k]);
                        stb += (db[k] - block[k]) * (db[k] - block[k]);
                    }
                }
            }
        }
        EXPECT_LE(ours, stb) << "quality " << quality;
        EXPECT_EQ(reported, ours); // the fit's own error is the decoded blocks' error
        EXPECT_GT(ours, 0); // the grain is not representable: a real comparison
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
