// Deflate streams of literals only (formats/deflate_literals.*) and the TIFF tiles that use them.
#include <gtest/gtest.h>

#include <libdeflate.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "formats/deflate_literals.hpp"
#include "formats/tiff_tile.hpp"

namespace pyramid {
namespace {

// Bytes of several kinds: empty, one value, two values, Gaussian noise of several widths,
// uniform noise, rare outliers in a constant run.
std::vector<std::vector<uint8_t>> samples() {
    std::mt19937 random(52);
    std::vector<std::vector<uint8_t>> out = {{}, {7}, std::vector<uint8_t>(70000, 0), {1, 2}};
    for (const double sigma : {0.5, 3.0, 8.5, 40.0}) {
        std::normal_distribution<double> noise(0, sigma);
        std::vector<uint8_t> bytes(50000 + static_cast<size_t>(sigma * 1000));
        for (uint8_t& b : bytes) {
            b = static_cast<uint8_t>(std::lround(noise(random)));
        }
        out.push_back(bytes);
    }
    std::vector<uint8_t> uniform(100003), outliers(90000, 9);
    for (uint8_t& b : uniform) {
        b = static_cast<uint8_t>(random());
    }
    for (size_t k = 0; k < outliers.size(); k += 977) {
        outliers[k] = static_cast<uint8_t>(random());
    }
    out.push_back(uniform);
    out.push_back(outliers);
    return out;
}

TEST(DeflateLiterals, StreamsAreReadByZlibAndLibdeflate) {
    for (const std::vector<uint8_t>& bytes : samples()) {
        const LiteralCost cost = literalCost(bytes);
        std::vector<uint8_t> stream;
        const size_t size = deflateLiterals(bytes, cost, stream);
        // The block's data bits as sized, its header (at most ~250 bytes), the frame (6 bytes).
        EXPECT_LE(size, cost.bits / 8 + 300);
        EXPECT_GE(size * 8, cost.bits);

        std::vector<uint8_t> back(bytes.size() + 1);
        uLongf length = back.size();
        ASSERT_EQ(uncompress(back.data(), &length, stream.data(), size), Z_OK) << bytes.size() << " bytes";
        ASSERT_EQ(length, bytes.size());
        EXPECT_TRUE(std::equal(bytes.begin(), bytes.end(), back.begin()));

        libdeflate_decompressor* d = libdeflate_alloc_decompressor();
        size_t got = 0;
        EXPECT_EQ(libdeflate_zlib_decompress(d, stream.data(), size, back.data(), back.size(), &got), LIBDEFLATE_SUCCESS);
        libdeflate_free_decompressor(d);
        EXPECT_EQ(got, bytes.size());
        EXPECT_TRUE(std::equal(bytes.begin(), bytes.end(), back.begin()));
    }
}

TEST(DeflateLiterals, CodesAreLimitedTo15Bits) {
    // Frequencies 1, 2, 4, ... would give codes of up to 20 bits without the limit.
    std::vector<uint8_t> bytes;
    for (int v = 0; v < 20; ++v) {
        bytes.insert(bytes.end(), size_t{1} << v, static_cast<uint8_t>(v));
    }
    const LiteralCost cost = literalCost(bytes);
    for (const uint8_t length : cost.lengths) {
        EXPECT_LE(length, 15);
    }
    std::vector<uint8_t> stream;
    const size_t size = deflateLiterals(bytes, cost, stream);
    std::vector<uint8_t> back(bytes.size());
    uLongf length = back.size();
    ASSERT_EQ(uncompress(back.data(), &length, stream.data(), size), Z_OK);
    EXPECT_EQ(back, bytes);
}

// A 196^2 RGB tile: smooth gradients and sensor noise of sigma 6, or the gradients alone.
std::vector<uint8_t> gradientTile(double sigma) {
    std::mt19937 random(6);
    std::normal_distribution<double> noise(0, sigma);
    std::vector<uint8_t> pixels(196 * 196 * 3);
    for (size_t k = 0; k < pixels.size(); ++k) {
        const double x = static_cast<double>(k / 3 % 196), y = static_cast<double>(k / 3 / 196);
        const double v = 60 + x / 3 + y / 4 + 10 * static_cast<double>(k % 3) + (sigma > 0 ? noise(random) : 0);
        pixels[k] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
    return pixels;
}

TEST(DeflateLiterals, NoisyTilesAtTheFastLevelsDecodeToTheirPixelsAndStaySmall) {
    for (const double sigma : {0.0, 6.0}) {
        const std::vector<uint8_t> pixels = gradientTile(sigma);
        for (const bool predictor : {true, false}) {
            const std::vector<uint8_t> fast = encodeTiff8(pixels, 196, 196, 3, TiffCompression::Deflate, 90, 1, predictor);
            const std::vector<uint8_t> slow = encodeTiff8(pixels, 196, 196, 3, TiffCompression::Deflate, 90, 6, predictor);
            const TiffImage image = decodeTiff(fast, 196, 196, "tile");
            EXPECT_EQ(image.pixels, pixels) << sigma << " " << predictor;
            // The strip (written first, after the 8-byte TIFF header) is a block of literals: the
            // zlib header 78 01, then a final dynamic block (bits 1, 10) with 257 literal/length codes.
            const bool literals = fast.size() > 11 && fast[8] == 0x78 && fast[9] == 0x01 && fast[10] == 0x05;
            EXPECT_EQ(literals, sigma > 0) << sigma << " " << predictor;
            if (sigma > 0) {
                // Noise: within 4 % of libdeflate level 6's stream (1 % with the predictor).
                EXPECT_LE(static_cast<double>(fast.size()), (predictor ? 1.01 : 1.04) * static_cast<double>(slow.size()));
            }
            EXPECT_EQ(encodeTiff8(pixels, 196, 196, 3, TiffCompression::Deflate, 90, 1, predictor), fast);
        }
    }
}

} // namespace
} // namespace pyramid
