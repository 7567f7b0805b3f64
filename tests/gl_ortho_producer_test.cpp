// The GL ortho producers: plain tiles of the original tools' RGB.dat sampled back unchanged,
// DXT tiles uploaded as compressed textures whose bytes read back unchanged and whose GPU
// decoding stays within the documented tolerance of the CPU decoder, and colour-residual tiles
// rebuilt on the GPU bit for bit as the CPU ColourProducer rebuilds them, also below the
// file's deepest level.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <random>

#include "formats/dxt_codec.hpp"
#include "formats/ortho_file.hpp"
#include "libpyramid/gl/gl_ortho_producer.hpp"
#include "libpyramid/gl/gl_colour_producer.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "tests/support/gl_test_context.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

// A smooth colour field with some noise: the kind of image DXT is meant for.
std::vector<uint8_t> image(int side, int channels, int seed) {
    std::mt19937 rng(static_cast<unsigned>(seed));
    std::uniform_int_distribution<int> noise(-12, 12);
    std::vector<uint8_t> p(static_cast<size_t>(side * side * channels));
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            for (int c = 0; c < channels; ++c) {
                const int v = (x * (3 + c) + y * (5 - c) + seed * 31) % 256 + noise(rng);
                p[static_cast<size_t>((y * side + x) * channels + c)] = static_cast<uint8_t>(std::clamp(v, 0, 255));
            }
        }
    }
    return p;
}

// Writes a 2-level ortho file (5 tiles) of the given flags.
std::string writeOrtho(const test::TempDir& dir, int tileSize, int channels, uint32_t flags,
                       const std::function<std::vector<uint8_t>(int, int, int)>& pixels) {
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = tileSize;
    h.channels = channels;
    h.flags = flags;
    const std::string path = dir.file("ortho" + std::to_string(channels) + "-" + std::to_string(flags) + ".dat");
    OrthoFileWriter writer(path, h);
    for (int level = 0; level <= 1; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                writer.writeTile(level, tx, ty, pixels(level, tx, ty));
            }
        }
    }
    writer.commit();
    return path;
}

TEST(GlOrthoProducer, PlainTilesOfTheOriginalFileSampleBackUnchanged) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    const std::string path = test::dataPath("proland/RGB.dat");
    GlOrthoProducer gl(std::make_shared<const OrthoProducer>(path));
    auto reader = OrthoFileReader::open(path);
    int tiles = 0;
    for (int level = 0; level <= reader->header().maxLevel; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                auto t = gl.tile(level, tx, ty);
                EXPECT_EQ(t->size, 196);
                EXPECT_FALSE(t->compressed);
                EXPECT_EQ(gl.readPixels(*t), reader->readTile(level, tx, ty)) << level << "," << tx << "," << ty;
                ++tiles;
            }
        }
    }
    EXPECT_EQ(tiles, 5);
    EXPECT_THROW(gl.tile(2, 0, 0), Error);
}

// GPU S3TC decoders may round the two interpolated palette colours (and DXT5's interpolated
// alphas) differently from libsquish: (2*c0 + c1)/3 computed on 5/6-bit or 8-bit endpoints,
// rounded or truncated. The end-point colours themselves must agree exactly; the allowed
// difference per channel is doc/gl-producers.md's bound.
constexpr int kDxtTolerance = 3;

TEST(GlOrthoProducer, DxtTilesKeepTheirBytesAndDecodeWithinTolerance) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    test::TempDir dir;
    for (int channels : {3, 4}) {
        const int tileSize = 60; // 64 pixels with borders: whole 4x4 blocks
        const std::string path = writeOrtho(dir, tileSize, channels, OrthoHeader::kFlagDxt, [&](int l, int x, int y) {
            return image(tileSize + 4, channels, l * 4 + x + 2 * y);
        });
        GlOrthoProducer gl(std::make_shared<const OrthoProducer>(path));
        auto reader = OrthoFileReader::open(path);
        const DxtFormat format = channels == 4 ? DxtFormat::Dxt5 : DxtFormat::Dxt1;
        int worst = 0;
        size_t exact = 0, total = 0;
        for (int level = 0; level <= 1; ++level) {
            for (int ty = 0; ty < (1 << level); ++ty) {
                for (int tx = 0; tx < (1 << level); ++tx) {
                    auto t = gl.tile(level, tx, ty);
                    ASSERT_TRUE(t->compressed);
                    ASSERT_EQ(t->channels, channels);
                    const std::vector<uint8_t> blocks = reader->readTileBytes(level, tx, ty);
                    EXPECT_EQ(GlOrthoProducer::readCompressed(*t), blocks);
                    const std::vector<uint8_t> onGl = gl.readPixels(*t);
                    const std::vector<uint8_t> onCpu = decodeDxt(blocks, 64, 64, format, path);
                    ASSERT_EQ(onGl.size(), onCpu.size());
                    for (size_t k = 0; k < onGl.size(); ++k) {
                        const int d = std::abs(static_cast<int>(onGl[k]) - static_cast<int>(onCpu[k]));
                        worst = std::max(worst, d);
                        exact += d == 0 ? 1 : 0;
                    }
                    total += onGl.size();
                }
            }
        }
        std::cerr << "DXT" << (channels == 4 ? 5 : 1) << ": GPU vs libsquish decoding, largest difference " << worst
                  << ", " << exact << " of " << total << " bytes identical\n";
        EXPECT_LE(worst, kDxtTolerance);
        EXPECT_GT(exact, total * 9 / 10); // end points and exact palette entries agree
    }
}

TEST(GlColourProducer, ColourResidualsRebuildBitForBit) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    test::TempDir dir;
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int channels = 1; channels <= 4; ++channels) {
        const int tileSize = 28;
        const std::string path = writeOrtho(dir, tileSize, channels, 0, [&](int level, int, int) {
            std::vector<uint8_t> p = image(tileSize + 4, channels, level);
            if (level > 0) { // residuals: mostly near 128, some extreme to hit the clamps
                for (uint8_t& v : p) {
                    const int r = byte(rng);
                    v = static_cast<uint8_t>(r < 16 ? 0 : r > 240 ? 255 : 128 + (r % 9) - 4);
                }
            }
            return p;
        });
        auto residuals = std::make_shared<const OrthoProducer>(path);
        GlColourProducer gl(residuals);
        ColourProducer cpu(residuals);
        auto reader = OrthoFileReader::open(path);
        for (int level = 0; level <= 3; ++level) { // levels 2 and 3 have no residuals
            for (int ty = 0; ty < (1 << level); ++ty) {
                for (int tx = 0; tx < (1 << level); ++tx) {
                    const std::vector<uint8_t> expected = *cpu.tile(level, tx, ty);
                    ASSERT_EQ(GlColourProducer::read(*gl.tile(level, tx, ty)), expected)
                        << "channels " << channels << " tile " << level << "," << tx << "," << ty;
                    if (level == 1) {
                        EXPECT_NE(expected, reader->readTile(level, tx, ty)); // the parent contributed
                    }
                }
            }
        }
        // A hand-checked pixel: tile (1,0,0), pixel (2,2) channel 0 is predicted from parent
        // pixels (1..2, 1..2) with weights 1, 3, 3, 9 (the nearest, (2,2), gets 9).
        const std::vector<uint8_t> root = reader->readTile(0, 0, 0);
        const std::vector<uint8_t> stored = reader->readTile(1, 0, 0);
        auto at = [&](const std::vector<uint8_t>& t, int x, int y) {
            return static_cast<int>(t[static_cast<size_t>((y * 32 + x) * channels)]);
        };
        const int prediction = (1 * at(root, 1, 1) + 3 * at(root, 2, 1) + 3 * at(root, 1, 2) + 9 * at(root, 2, 2)) >> 4;
        const int value = std::clamp(prediction + 2 * (at(stored, 2, 2) - 128), 0, 255);
        EXPECT_EQ(at(GlColourProducer::read(*gl.tile(1, 0, 0)), 2, 2), value);
    }
}

TEST(GlColourProducer, RejectsDxtFiles) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    test::TempDir dir;
    const std::string path = writeOrtho(dir, 60, 3, OrthoHeader::kFlagDxt, [](int, int, int) { return image(64, 3, 1); });
    EXPECT_THROW(GlColourProducer{std::make_shared<const OrthoProducer>(path)}, Error);
}

} // namespace
} // namespace pyramid
