// The GLSL upsample kernels against the CPU reference arithmetic, bit for bit: the elevation
// upsample-and-add (pyramid::upsampleAndAdd) on random tiles full of values that expose any
// reassociation, fused multiply-add or flush to zero, and the integer colour upsample
// (pyramid::upsampleColour) for 1 to 4 channels.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "libpyramid/filters/elevation_upsample.hpp"
#include "libpyramid/gl/gl_elevation_upsample.hpp"
#include "libpyramid/gl/gl_colour_upsample.hpp"
#include "libpyramid/filters/colour_upsample.hpp"
#include "tests/support/gl_test_context.hpp"

namespace pyramid {
namespace {

// Samples drawn from families that round differently under any change of operation order:
// ordinary heights, huge and tiny magnitudes side by side, signed zeros, values one ulp apart,
// the smallest normals and (optionally) subnormals.
std::vector<float> hostileTile(int side, std::mt19937& rng, bool subnormals) {
    std::uniform_int_distribution<int> family(0, subnormals ? 8 : 7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::uniform_int_distribution<uint32_t> bits;
    std::vector<float> t(static_cast<size_t>(side) * static_cast<size_t>(side));
    for (float& v : t) {
        switch (family(rng)) {
        case 0: v = unit(rng) * 9000.0f; break;                      // heights
        case 1: v = unit(rng) * 1e37f; break;                        // huge, still finite after *9
        case 2: v = unit(rng) * 1e-36f; break;                       // tiny normals
        case 3: v = (bits(rng) & 1) ? 0.0f : -0.0f; break;           // signed zeros
        case 4: v = 1.0f + static_cast<float>(bits(rng) % 8) * std::numeric_limits<float>::epsilon(); break;
        case 5: v = 16777216.0f + static_cast<float>(bits(rng) % 5) * 2.0f; break; // 2^24: ulp 2
        case 6: { // any finite float of moderate exponent, every mantissa bit random
            const uint32_t b = (bits(rng) & 0x807FFFFFu) | ((100u + bits(rng) % 60u) << 23);
            v = std::bit_cast<float>(b);
            break;
        }
        case 7: v = std::numeric_limits<float>::min() * (1.0f + unit(rng)); break; // around FLT_MIN
        default: v = std::bit_cast<float>(bits(rng) & 0x807FFFFFu); break;      // subnormals
        }
    }
    return t;
}

// The first differing sample, as "i,j: cpu bits vs gl bits", or "" when all bits agree.
std::string firstDifference(const std::vector<float>& cpu, const std::vector<float>& gl, int side) {
    for (size_t k = 0; k < cpu.size(); ++k) {
        const uint32_t a = std::bit_cast<uint32_t>(cpu[k]);
        const uint32_t b = std::bit_cast<uint32_t>(gl[k]);
        if (a != b) {
            char buf[128];
            std::snprintf(buf, sizeof buf, "sample (%d,%d): cpu %a (0x%08x) gl %a (0x%08x)", static_cast<int>(k) % side,
                          static_cast<int>(k) / side, static_cast<double>(cpu[k]), a, static_cast<double>(gl[k]), b);
            return buf;
        }
    }
    return "";
}

void expectSameUpsample(const GlElevationUpsampler& gl, int parentSide, int n, int px, int py, std::mt19937& rng,
                        bool subnormals) {
    const int side = n + 5;
    const std::vector<float> parent = hostileTile(parentSide, rng, subnormals);
    const std::vector<float> residual = hostileTile(side, rng, subnormals);
    std::vector<float> cpu = residual;
    upsampleAndAdd(parent.data(), static_cast<size_t>(parentSide), n, px, py, cpu.data(), static_cast<size_t>(side));
    const std::vector<float> onGl = gl.upsampleAndAdd(parent, parentSide, n, px, py, residual);
    ASSERT_EQ(onGl.size(), cpu.size());
    EXPECT_EQ(firstDifference(cpu, onGl, side), "") << "n " << n << " offset (" << px << "," << py << ")";
}

TEST(GlUpsample, ElevationQuadrantsAreBitIdentical) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    GlElevationUpsampler gl;
    std::mt19937 rng(20261123);
    for (int n : {192, 96, 24, 8, 2}) {
        for (int q = 0; q < 4; ++q) {
            expectSameUpsample(gl, n + 5, n, quadrantOffset(q & 1, n), quadrantOffset(q >> 1, n), rng, false);
        }
    }
}

TEST(GlUpsample, ElevationWithSubnormalsIsBitIdentical) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    GlElevationUpsampler gl;
    std::mt19937 rng(99);
    for (int q = 0; q < 4; ++q) {
        expectSameUpsample(gl, 29, 24, quadrantOffset(q & 1, 24), quadrantOffset(q >> 1, 24), rng, true);
    }
}

TEST(GlUpsample, ElevationWholeTileDoublingIsBitIdentical) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    GlElevationUpsampler gl;
    std::mt19937 rng(7);
    for (int n : {192, 48, 2}) {
        expectSameUpsample(gl, n / 2 + 5, n, 1, 1, rng, false); // a level below minLevel
    }
}

TEST(GlUpsample, ElevationOfSmoothTerrainIsBitIdentical) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    GlElevationUpsampler gl;
    const int n = 24, side = n + 5;
    std::vector<float> parent(side * side), residual(side * side);
    for (int j = 0; j < side; ++j) {
        for (int i = 0; i < side; ++i) {
            parent[i + j * side] = 1234.5f + 0.1f * static_cast<float>(i * i) - 0.3f * static_cast<float>(j);
            residual[i + j * side] = 0.1f * static_cast<float>((i * 7 + j * 3) % 11 - 5);
        }
    }
    std::vector<float> cpu = residual;
    upsampleAndAdd(parent.data(), side, n, quadrantOffset(1, n), quadrantOffset(0, n), cpu.data(), side);
    const std::vector<float> onGl = gl.upsampleAndAdd(parent, side, n, quadrantOffset(1, n), quadrantOffset(0, n), residual);
    EXPECT_EQ(firstDifference(cpu, onGl, side), "");
    EXPECT_NE(cpu[3 + 3 * side], residual[3 + 3 * side]); // the prediction did contribute
}

TEST(GlUpsample, OrthoIsBitIdentical) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    GlColourUpsampler gl;
    std::mt19937 rng(42);
    std::uniform_int_distribution<int> byte(0, 255);
    std::uniform_int_distribution<int> extreme(0, 3);
    for (int tileSize : {192, 24, 4}) {
        const int side = tileSize + 4;
        for (int channels = 1; channels <= 4; ++channels) {
            const size_t bytes = static_cast<size_t>(side * side * channels);
            for (int q = 0; q < 4; ++q) {
                std::vector<uint8_t> parent(bytes), residual(bytes);
                for (size_t k = 0; k < bytes; ++k) {
                    // A quarter of the values at 0 or 255 so that the clamps are exercised.
                    const int e = extreme(rng);
                    parent[k] = static_cast<uint8_t>(e == 0 ? (byte(rng) & 1) * 255 : byte(rng));
                    residual[k] = static_cast<uint8_t>(e == 1 ? (byte(rng) & 1) * 255 : byte(rng));
                }
                const int tx = q & 1, ty = q >> 1;
                std::vector<uint8_t> cpu(bytes), cpuFlat(bytes);
                upsampleColour(parent.data(), tileSize, channels, tx, ty, residual.data(), cpu.data());
                upsampleColour(parent.data(), tileSize, channels, tx, ty, nullptr, cpuFlat.data());
                EXPECT_EQ(gl.upsample(parent, tileSize, channels, tx, ty, residual), cpu)
                    << "tileSize " << tileSize << " channels " << channels << " quadrant " << q;
                EXPECT_EQ(gl.upsample(parent, tileSize, channels, tx, ty, {}), cpuFlat)
                    << "no residual, tileSize " << tileSize << " channels " << channels << " quadrant " << q;
            }
        }
    }
}

} // namespace
} // namespace pyramid
