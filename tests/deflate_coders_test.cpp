// The Deflate coders of image strips: literals only (formats/deflate_literals.*), literals and
// runs (formats/deflate_runs.*), and the choice between them and libdeflate for the strips of
// TIFF tiles (formats/tiff_strip_bytes.*).
#include <gtest/gtest.h>

#include <libdeflate.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include "formats/deflate_literals.hpp"
#include "formats/deflate_run_starts.hpp"
#include "formats/deflate_runs.hpp"
#include "formats/tiff_strip_bytes.hpp"
#include "formats/tiff_tile.hpp"

namespace pyramid {
namespace {

// Inflates `stream` with zlib and with libdeflate; both must give `bytes` exactly.
void expectInflatesTo(const std::vector<uint8_t>& stream, size_t size, const std::vector<uint8_t>& bytes) {
    std::vector<uint8_t> back(bytes.size() + 1);
    uLongf length = back.size();
    ASSERT_EQ(uncompress(back.data(), &length, stream.data(), size), Z_OK) << bytes.size() << " bytes";
    ASSERT_EQ(length, bytes.size());
    EXPECT_TRUE(std::equal(bytes.begin(), bytes.end(), back.begin()));
    libdeflate_decompressor* d = libdeflate_alloc_decompressor();
    size_t got = 0;
    std::fill(back.begin(), back.end(), uint8_t{0});
    EXPECT_EQ(libdeflate_zlib_decompress(d, stream.data(), size, back.data(), back.size(), &got), LIBDEFLATE_SUCCESS);
    libdeflate_free_decompressor(d);
    EXPECT_EQ(got, bytes.size());
    EXPECT_TRUE(std::equal(bytes.begin(), bytes.end(), back.begin()));
}

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

        expectInflatesTo(stream, size, bytes);
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

// Literal codes go to the stream four at a time when none is longer than 14 bits, three at a
// time otherwise (deflate_huffman.hpp, putLiterals): bytes whose longest literal code is exactly
// 14 bits, and exactly 15, decode back to themselves through both coders.
TEST(DeflateLiterals, LiteralsOfFourteenAndFifteenBitsDecode) {
    for (const int longest : {14, 15}) {
        // `longest` values with counts 1, 2, 4, ...: with the end of block (count 1), a chain of
        // longest + 1 codes, whose two rarest are `longest` bits long, under the 15-bit limit.
        std::vector<uint8_t> bytes;
        for (int v = 0; v < longest; ++v) {
            bytes.insert(bytes.end(), size_t{1} << v, static_cast<uint8_t>(v * 17));
        }
        std::shuffle(bytes.begin(), bytes.end(), std::mt19937(longest));
        const LiteralCost cost = literalCost(bytes);
        ASSERT_EQ(*std::max_element(std::begin(cost.lengths), std::begin(cost.lengths) + 256), longest);
        std::vector<uint8_t> stream;
        const size_t size = deflateLiterals(bytes, cost, stream);
        expectInflatesTo(stream, size, bytes);
        for (int pixel = 1; pixel <= 4; ++pixel) {
            expectInflatesTo(stream, deflateRuns(bytes, pixel, stream), bytes);
        }
    }
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
// Bytes made of random pieces: literals of several spreads, runs of one byte, repeats of the
// last 1 to 4 bytes, of lengths around Deflate's limits (3, 4, 258, 259 and beyond).
std::vector<uint8_t> piecewise(std::mt19937& random, size_t size) {
    std::vector<uint8_t> out;
    std::uniform_int_distribution<int> kind(0, 3), period(1, 4), spread(0, 255);
    static const int lengths[] = {1, 2, 3, 4, 5, 7, 9, 30, 257, 258, 259, 300, 700};
    while (out.size() < size) {
        const int len = lengths[random() % std::size(lengths)];
        switch (kind(random)) {
        case 0: {
            const int s = 1 + spread(random) % 64;
            for (int k = 0; k < len; ++k) {
                out.push_back(static_cast<uint8_t>(random() % static_cast<unsigned>(s)));
            }
            break;
        }
        case 1:
            out.insert(out.end(), static_cast<size_t>(len), static_cast<uint8_t>(random()));
            break;
        default: {
            const size_t p = static_cast<size_t>(period(random));
            if (out.size() < p) {
                out.push_back(0);
                break;
            }
            for (int k = 0; k < len; ++k) {
                out.push_back(out[out.size() - p]);
            }
        }
        }
    }
    out.resize(size);
    return out;
}

TEST(DeflateRuns, StreamsOfAnyBytesAreReadByZlibAndLibdeflate) {
    std::mt19937 random(53);
    std::vector<std::vector<uint8_t>> cases = {{}, {7}, {1, 2, 3}, std::vector<uint8_t>(337, 5),
                                               std::vector<uint8_t>(338, 5), std::vector<uint8_t>(100000, 0)};
    for (const size_t size : {100, 337, 338, 339, 400, 1000, 4096, 20000, 115248}) {
        for (int k = 0; k < 40; ++k) {
            cases.push_back(piecewise(random, size));
        }
    }
    std::vector<uint8_t> stream;
    for (const std::vector<uint8_t>& bytes : cases) {
        for (int pixel = 1; pixel <= 4; ++pixel) {
            const size_t size = deflateRuns(bytes, pixel, stream);
            expectInflatesTo(stream, size, bytes);
        }
    }
}

TEST(DeflateRuns, RunsAndRepeatedPixelsAreCodedAsMatches) {
    std::vector<uint8_t> stream;
    // 100,000 zeros: runs of 258 bytes at about 2 bits each, not 100,000 literals.
    const std::vector<uint8_t> zeros(100000, 0);
    EXPECT_LT(deflateRuns(zeros, 3, stream), 300u);
    // A pixel of three different bytes repeated: matches at distance 3 only (with pixel 3).
    std::vector<uint8_t> pixels;
    for (int k = 0; k < 30000; ++k) {
        pixels.insert(pixels.end(), {10, 200, 33});
    }
    EXPECT_LT(deflateRuns(pixels, 3, stream), 300u);
    const size_t asBytes = deflateRuns(pixels, 1, stream);
    EXPECT_GT(asBytes, 90000u * 3 / 16); // at least 1.5 bits a byte: literals, no run at distance 1
    expectInflatesTo(stream, asBytes, pixels);
}

// Where runs start, by definition: the first place from `from` on whose four bytes equal those
// one pixel before (that distance first), or one byte before.
RunStart runStartByDefinition(const std::vector<uint8_t>& p, size_t from, size_t last, size_t pixel) {
    for (size_t j = from; j < last; ++j) {
        if (std::equal(&p[j], &p[j + 4], &p[j - pixel])) {
            return {j, pixel};
        }
        if (std::equal(&p[j], &p[j + 4], &p[j - 1])) {
            return {j, 1};
        }
    }
    return {last, 0};
}

// The word and the AVX2 finders (the latter where the machine has it) give the definition's
// answer from every place, on bytes of every kind of piece and on noise (few starts, so that
// the finders search far).
TEST(DeflateRunStarts, BothFindersFindTheFirstStartByDefinition) {
    std::mt19937 random(52);
    std::vector<std::vector<uint8_t>> cases;
    for (int k = 0; k < 12; ++k) {
        cases.push_back(piecewise(random, 3000));
    }
    std::vector<uint8_t> noise(3000);
    for (uint8_t& b : noise) {
        b = static_cast<uint8_t>(random());
    }
    cases.push_back(noise);
    size_t starts = 0;
    for (const std::vector<uint8_t>& p : cases) {
        const size_t last = p.size() - 64;
        for (size_t pixel = 1; pixel <= 4; ++pixel) {
            for (size_t from = pixel; from <= last; ++from) {
                const RunStart expected = runStartByDefinition(p, from, last, pixel);
                const RunStart words = nextRunStartWords(p.data(), from, last, pixel);
                const RunStart wide = nextRunStartWide(p.data(), from, last, pixel);
                ASSERT_EQ(words.at, expected.at) << "from " << from << ", pixel " << pixel;
                ASSERT_EQ(words.distance, expected.distance) << "from " << from << ", pixel " << pixel;
                ASSERT_EQ(wide.at, expected.at) << "from " << from << ", pixel " << pixel;
                ASSERT_EQ(wide.distance, expected.distance) << "from " << from << ", pixel " << pixel;
                starts += expected.at < last && expected.at == from ? 1 : 0;
            }
        }
    }
    EXPECT_GT(starts, 10000u); // runs start often enough in the pieces to test both distances
}

TEST(DeflateRuns, RefusesPixelsOfOtherSizes) {
    std::vector<uint8_t> stream;
    const std::vector<uint8_t> bytes(1000, 1);
    EXPECT_THROW(deflateRuns(bytes, 0, stream), std::exception);
    EXPECT_THROW(deflateRuns(bytes, 5, stream), std::exception);
}

// A 196^2 RGB tile: a flat area (sea) left, smooth gradients with sensor noise of `sigma`
// right; or a texture of 64 random bytes repeated with a shift per row.
std::vector<uint8_t> imageTile(double sigma, bool texture) {
    std::mt19937 random(6);
    std::normal_distribution<double> noise(0, sigma);
    std::vector<uint8_t> pattern(64);
    for (uint8_t& b : pattern) {
        b = static_cast<uint8_t>(random());
    }
    std::vector<uint8_t> pixels(196 * 196 * 3);
    for (size_t k = 0; k < pixels.size(); ++k) {
        const size_t x = k / 3 % 196, y = k / 3 / 196;
        if (texture) {
            pixels[k] = pattern[(k + y * 7) % 64];
            continue;
        }
        const double v = x < 80 ? 20.0 + static_cast<double>(k % 3)
                                : 60 + static_cast<double>(x) / 3 + static_cast<double>(y) / 4 + noise(random);
        pixels[k] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
    return pixels;
}

// Whether `needle` occurs in `blob`.
bool contains(const std::vector<uint8_t>& blob, std::span<const uint8_t> needle) {
    return std::search(blob.begin(), blob.end(), needle.begin(), needle.end()) != blob.end();
}

TEST(DeflateRuns, ImageTilesAtTheFastLevelsTakeTheRunsCoderUnlessTextureRepeats) {
    std::vector<uint8_t> stream;
    for (const bool texture : {false, true}) {
        const std::vector<uint8_t> pixels = imageTile(1.5, texture);
        const std::vector<uint8_t> tile = encodeTiff8(pixels, 196, 196, 3, TiffCompression::Deflate, 90, 1, true);
        EXPECT_EQ(decodeTiff(tile, 196, 196, "tile").pixels, pixels);
        const std::vector<uint8_t> differences = [&] {
            const std::span<const uint8_t> d = horizontalDifferences(pixels.data(), pixels.size(), 196, 3);
            return std::vector<uint8_t>(d.begin(), d.end());
        }();
        const size_t runs = deflateRuns(differences, 3, stream);
        const std::vector<uint8_t> runsStream(stream.begin(), stream.begin() + static_cast<std::ptrdiff_t>(runs));
        const std::span<const uint8_t> libdeflate = zlibCompress(differences, 1);
        // The strip is the runs coder's stream for the gradients; libdeflate's for the texture,
        // which the runs coder codes at several times the size.
        EXPECT_EQ(contains(tile, runsStream), !texture);
        EXPECT_EQ(contains(tile, libdeflate), texture);
        if (texture) {
            EXPECT_GT(runs, 3 * libdeflate.size());
        } else {
            EXPECT_LE(runs, libdeflate.size() * 103 / 100);
        }
        // Above the fast levels, libdeflate alone.
        const std::vector<uint8_t> slow = encodeTiff8(pixels, 196, 196, 3, TiffCompression::Deflate, 90, 6, true);
        EXPECT_TRUE(contains(slow, zlibCompress(differences, 6)));
    }
}

// A 196^2 RGB tile of a night image: black, with a light of a few pixels every 37 pixels in
// every fourth row.
std::vector<uint8_t> darkTile() {
    std::mt19937 random(9);
    std::vector<uint8_t> pixels(196 * 196 * 3, 0);
    for (size_t y = 0; y < 196; y += 4) {
        for (size_t x = y % 37; x + 3 < 196; x += 37) {
            for (size_t k = 0; k < 9; ++k) {
                pixels[(y * 196 + x) * 3 + k] = static_cast<uint8_t>(random() % 200 + 40);
            }
        }
    }
    return pixels;
}

// A dark strip, whose sample libdeflate codes in a few hundred bytes and the runs coder a few
// dozen bytes larger (its code lengths' header, paid once by the strip), takes the runs coder:
// over the whole strip it is no larger than libdeflate's stream.
TEST(DeflateRuns, DarkTilesTakeTheRunsCoder) {
    const std::vector<uint8_t> pixels = darkTile();
    const std::vector<uint8_t> tile = encodeTiff8(pixels, 196, 196, 3, TiffCompression::Deflate, 90, 1, true);
    EXPECT_EQ(decodeTiff(tile, 196, 196, "tile").pixels, pixels);
    const std::span<const uint8_t> d = horizontalDifferences(pixels.data(), pixels.size(), 196, 3);
    const std::vector<uint8_t> differences(d.begin(), d.end());
    std::vector<uint8_t> stream;
    // The sample the choice is made on (4 KB from the middle): more than 3 % larger with the
    // runs coder, which the choice allowed nowhere before.
    const std::span<const uint8_t> sample(differences.data() + (differences.size() - 4096) / 2, 4096);
    const size_t sampleRuns = deflateRuns(sample, 3, stream);
    const size_t sampleLibdeflate = zlibCompress(sample, 1).size();
    EXPECT_LT(sampleLibdeflate, 512u);
    EXPECT_GT(sampleRuns * 100, sampleLibdeflate * 103);
    const size_t runs = deflateRuns(differences, 3, stream);
    const std::vector<uint8_t> runsStream(stream.begin(), stream.begin() + static_cast<std::ptrdiff_t>(runs));
    EXPECT_TRUE(contains(tile, runsStream));
    EXPECT_LE(runs, zlibCompress(differences, 1).size() * 103 / 100);
}

} // namespace pyramid
