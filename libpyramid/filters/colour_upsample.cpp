#include "libpyramid/filters/colour_upsample.hpp"

#include <algorithm>
#include <cstring>
#include <vector>

#include "formats/vector_clones.hpp"

namespace pyramid {

namespace {

// The loops over samples below are plain loops, which GCC vectorises at -O2 and -O3 alike under
// the build's dynamic cost model (CMakeLists.txt). Loops cut into fixed chunks of 16 were fully
// unrolled at -O3 before the vectoriser saw them, and stayed scalar in a Release build.

// The parent rows by and by + 1 blended with weights wy0 and wy1 (at most 4 x 255 x 4 = 4080):
// `count` samples.
PYRAMID_VECTOR_CLONES
void blendRows(const uint8_t* __restrict r0, const uint8_t* __restrict r1, unsigned wy0, unsigned wy1, size_t count,
               uint16_t* __restrict out) {
    for (size_t k = 0; k < count; ++k) {
        out[k] = static_cast<uint16_t>(wy0 * r0[k] + wy1 * r1[k]);
    }
}

// out[s] = (a p[s] + b p[s + step]) >> 4 for s < count: `count` predictions from a blended row.
[[gnu::always_inline]] inline void weightedRun(const uint16_t* __restrict p, size_t step, unsigned a, unsigned b, size_t count,
                 uint8_t* __restrict out) {
    for (size_t s = 0; s < count; ++s) {
        out[s] = static_cast<uint8_t>((a * p[s] + b * p[s + step]) >> 4);
    }
}

// Child pixels x = 0..side-1 from the blended parent row `v` (parent column j at v[j * C]):
// x even (x = 2m) takes columns (m + rx, m + rx + 1) with weights (1, 3), x odd (x = 2m - 1)
// takes (m + rx, m + rx + 1) with weights (3, 1). Computed as two runs of samples, the even
// pixels' and the odd pixels' (each a vectorised loop over consecutive samples of the blended
// row), then interleaved pixel by pixel: the same sums as pixel by pixel.
template <int C>
[[gnu::always_inline]] inline void predictFromBlend(const uint16_t* __restrict v, int rx, int side, uint8_t* __restrict out) {
    const uint16_t* w = v + static_cast<size_t>(rx) * C;
    const size_t evenSamples = static_cast<size_t>((side + 1) / 2) * C; // x = 2m: m < (side + 1) / 2
    const size_t oddSamples = static_cast<size_t>(side / 2) * C;        // x = 2m + 1: m < side / 2
    thread_local std::vector<uint8_t> runs;
    runs.resize(evenSamples + oddSamples);
    uint8_t* even = runs.data();
    uint8_t* odd = even + evenSamples;
    // Pixel x = 2m: 1 x column m + rx, 3 x column m + rx + 1 (sample s = m C + c); pixel
    // x = 2m + 1: bx = m + 1 + rx, so 3 x column m + rx + 1, 1 x column m + rx + 2.
    weightedRun(w, C, 1u, 3u, evenSamples, even);
    weightedRun(w + C, C, 3u, 1u, oddSamples, odd);
    // Interleaved pixel pair by pixel pair, by copies of a constant size done in registers (a
    // loop over the C bytes was compiled into a call to memmove per pixel). Three-byte pixels
    // move as four bytes, the fourth overwritten by the next copy: all but the last pair.
    const int pairs = side / 2;
    int m = 0;
    if constexpr (C == 3) {
        for (; m + 1 < pairs; ++m) {
            uint8_t* o = out + static_cast<size_t>(m) * 2 * C;
            std::memcpy(o, even + static_cast<size_t>(m) * C, 4);
            std::memcpy(o + C, odd + static_cast<size_t>(m) * C, 4);
        }
    }
    for (; m < pairs; ++m) {
        uint8_t* o = out + static_cast<size_t>(m) * 2 * C;
        std::memcpy(o, even + static_cast<size_t>(m) * C, C);
        std::memcpy(o + C, odd + static_cast<size_t>(m) * C, C);
    }
    if (side % 2 != 0) {
        std::memcpy(out + static_cast<size_t>(side - 1) * C, even + static_cast<size_t>(pairs) * C, C);
    }
}

// predictFromBlend for any channel count, compiled for AVX2 too (the same integers): the
// channel count known at compile time inside each clone, into which the loops above are inlined.
PYRAMID_VECTOR_CLONES
void predictFromBlendOf(const uint16_t* v, int channels, int rx, int side, uint8_t* out) {
    switch (channels) {
    case 1: return predictFromBlend<1>(v, rx, side, out);
    case 2: return predictFromBlend<2>(v, rx, side, out);
    case 3: return predictFromBlend<3>(v, rx, side, out);
    default: return predictFromBlend<4>(v, rx, side, out);
    }
}

} // namespace

int64_t encodeColourResiduals(const uint8_t* __restrict value, const uint8_t* __restrict prediction, size_t count,
                              uint8_t* __restrict stored) {
    const auto one = [&](size_t k) {
        bool clamped = false;
        stored[k] = encodeColourResidual(value[k], prediction[k], &clamped);
        return static_cast<int>(clamped);
    };
    int64_t clamped = 0;
    for (size_t k = 0; k < count; ++k) {
        clamped += one(k);
    }
    return clamped;
}

void applyColourResiduals(uint8_t* __restrict values, const uint8_t* __restrict stored, size_t count) {
    for (size_t k = 0; k < count; ++k) {
        values[k] = applyColourResidual(values[k], stored[k]);
    }
}

// Summed in 32 bits (a row of up to 2^23 samples cannot overflow them), which vectorises.
PYRAMID_VECTOR_CLONES
RebuiltRow encodeColourResidualsRebuilt(const uint8_t* __restrict value, uint8_t* __restrict rebuilt, size_t count,
                                        uint8_t* __restrict stored) {
    RebuiltRow totals;
    for (size_t first = 0; first < count; first += size_t{1} << 23) {
        const size_t last = std::min(count, first + (size_t{1} << 23));
        uint32_t odd = 0, spread = 0;
        for (size_t k = first; k < last; ++k) {
            const int v = value[k], p = rebuilt[k];
            const int s = colourResidualUnclamped(v, p), half = s - 128;
            stored[k] = static_cast<uint8_t>(s);
            rebuilt[k] = static_cast<uint8_t>(colourValueUnclamped(p, s));
            odd += static_cast<uint32_t>((v ^ p) & 1);
            spread += static_cast<uint32_t>(half < 0 ? -half : half);
        }
        totals.errors += odd;
        totals.spread += spread;
    }
    return totals;
}

void predictColourRow(const uint8_t* parent, size_t rowBytes, int channels, int rx, int ry, int y, int side,
                     uint8_t* out) {
    const size_t by = static_cast<size_t>((y + 1) / 2 + ry);
    const unsigned wy0 = (y & 1) ? 3u : 1u;
    thread_local std::vector<uint16_t> blended;
    blended.resize(rowBytes);
    blendRows(parent + by * rowBytes, parent + (by + 1) * rowBytes, wy0, 4u - wy0, rowBytes, blended.data());
    predictFromBlendOf(blended.data(), channels, rx, side, out);
}

uint8_t predictColour(const uint8_t* parent, size_t rowBytes, int channels, int channel, int rx, int ry,
                     int x, int y) {
    const size_t bx = static_cast<size_t>((x + 1) / 2 + rx);
    const size_t by = static_cast<size_t>((y + 1) / 2 + ry);
    // Weight of the bx column (the bx+1 column gets 4 minus it), likewise for rows.
    const unsigned wx0 = (x & 1) ? 3u : 1u;
    const unsigned wy0 = (y & 1) ? 3u : 1u;
    const unsigned wx1 = 4u - wx0;
    const unsigned wy1 = 4u - wy0;
    const size_t c = static_cast<size_t>(channels);
    const uint8_t* r0 = parent + by * rowBytes + static_cast<size_t>(channel);
    const uint8_t* r1 = r0 + rowBytes;
    const unsigned sum = wy0 * (wx0 * r0[bx * c] + wx1 * r0[(bx + 1) * c]) +
                         wy1 * (wx0 * r1[bx * c] + wx1 * r1[(bx + 1) * c]);
    return static_cast<uint8_t>(sum >> 4);
}

void upsampleColour(const uint8_t* parent, int tileSize, int channels, int tx, int ty,
                   const uint8_t* residual, uint8_t* out) {
    const int side = tileSize + 4;
    const size_t rowBytes = static_cast<size_t>(side) * static_cast<size_t>(channels);
    const int rx = (tx & 1) * (tileSize / 2);
    const int ry = (ty & 1) * (tileSize / 2);
    for (int y = 0; y < side; ++y) {
        uint8_t* row = out + static_cast<size_t>(y) * rowBytes;
        predictColourRow(parent, rowBytes, channels, rx, ry, y, side, row);
        if (residual) { // without, every stored value is 128: the prediction itself
            applyColourResiduals(row, residual + static_cast<size_t>(y) * rowBytes, rowBytes);
        }
    }
}

} // namespace pyramid
