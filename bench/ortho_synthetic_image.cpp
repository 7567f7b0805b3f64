// A deterministic synthetic orthophoto for bench/ortho_bench.sh and bench/sphere_bench.sh:
// SIZE x SIZE (or WIDTH x HEIGHT) RGB, 8 bits, written as an uncompressed striped TIFF.
//
//   ortho_synthetic_image OUTPUT.tif [SIZE | WIDTHxHEIGHT] [noise SIGMA]     (default 8192)
//
// Content: smooth colour fields (value noise with 2048- and 512-pixel cells) plus texture
// (64-, 16- and 4-pixel cells) and per-pixel grain, so that Deflate and JPEG compress it about
// as much as real aerial imagery. With `noise SIGMA`: smooth gradients only (linear ramps and
// value noise with 2048-pixel cells, no texture) plus sensor-like Gaussian noise of standard
// deviation SIGMA (the sum of 12 uniform variates, independent per sample), the image on which
// Deflate finds almost nothing but the noise. Integer arithmetic only: the same bytes on every
// machine.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

namespace {

uint32_t hash(uint32_t x, uint32_t y, uint32_t seed) {
    uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ seed * 0xcb1ab31fu;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return h;
}

// Value noise in 0..255 with cells of 2^shift pixels, smoothstep-interpolated in 8.8 fixed point.
int valueNoise(uint32_t x, uint32_t y, int shift, uint32_t seed) {
    const uint32_t cx = x >> shift, cy = y >> shift;
    const uint32_t mask = (1u << shift) - 1u;
    auto fade = [shift](uint32_t f) { // f in 0..2^shift -> 0..256, smoothstep
        const int64_t t = (static_cast<int64_t>(f) << 8) >> shift;
        return static_cast<int>((t * t * (768 - 2 * t)) >> 16);
    };
    const int fx = fade(x & mask), fy = fade(y & mask);
    const int v00 = static_cast<int>(hash(cx, cy, seed) & 255u);
    const int v10 = static_cast<int>(hash(cx + 1, cy, seed) & 255u);
    const int v01 = static_cast<int>(hash(cx, cy + 1, seed) & 255u);
    const int v11 = static_cast<int>(hash(cx + 1, cy + 1, seed) & 255u);
    const int top = v00 * 256 + (v10 - v00) * fx;
    const int bottom = v01 * 256 + (v11 - v01) * fx;
    return (top * 256 + (bottom - top) * fy) >> 16;
}

// Gaussian noise of standard deviation sigma (Irwin-Hall: 12 uniform 16-bit variates have a
// standard deviation of 65536), rounded to the nearest integer.
int gaussianNoise(uint32_t x, uint32_t y, uint32_t channel, int sigma) {
    int64_t sum = 0;
    for (uint32_t k = 0; k < 12; ++k) {
        sum += static_cast<int64_t>(hash(x, y, 100 + channel * 12 + k) & 0xffffu);
    }
    const int64_t centred = (sum - 12 * 32768) * sigma;
    return static_cast<int>((centred + (centred >= 0 ? 32768 : -32768)) / 65536);
}

uint8_t clampByte(int v) { return static_cast<uint8_t>(v < 0 ? 0 : v > 255 ? 255 : v); }

} // namespace

int main(int argc, char** argv) {
    int sigma = -1; // -1: the default content
    if (argc == 5 && std::string(argv[3]) == "noise") {
        sigma = std::atoi(argv[4]);
        argc = 3;
    }
    if (argc < 2 || argc > 3 || sigma < -1 || sigma > 64) {
        std::fprintf(stderr, "usage: %s OUTPUT.tif [SIZE | WIDTHxHEIGHT] [noise SIGMA (0..64)]\n", argv[0]);
        return 2;
    }
    int size = 8192, rows = 8192;
    if (argc == 3 && std::sscanf(argv[2], "%dx%d", &size, &rows) != 2) {
        rows = size;
    }
    if (size < 16 || size > 65536 || rows < 16 || rows > 65536) {
        std::fprintf(stderr, "%s: size %dx%d is not 16..65536 per side\n", argv[0], size, rows);
        return 2;
    }
    OIIO::ImageSpec spec(size, rows, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("compression", "none");
    spec.attribute("tiff:RowsPerStrip", 64);
    auto out = OIIO::ImageOutput::create(argv[1]);
    if (!out || !out->open(argv[1], spec)) {
        std::fprintf(stderr, "%s: cannot write: %s\n", argv[1], OIIO::geterror().c_str());
        return 1;
    }
    std::vector<uint8_t> row(static_cast<size_t>(size) * 3);
    for (int y = 0; y < rows; ++y) {
        const auto uy = static_cast<uint32_t>(y);
        for (int x = 0; x < size; ++x) {
            const auto ux = static_cast<uint32_t>(x);
            // Land cover: a smooth luminance field and a hue that drifts slowly.
            const int field = (valueNoise(ux, uy, 11, 1) * 5 + valueNoise(ux, uy, 9, 2) * 3) / 8;
            const int hue = valueNoise(ux, uy, 10, 3) - 128;
            const int texture = (valueNoise(ux, uy, 6, 4) - 128) / 3 + (valueNoise(ux, uy, 4, 5) - 128) / 5 +
                                (valueNoise(ux, uy, 2, 6) - 128) / 8;
            const int grain = static_cast<int>(hash(ux, uy, 7) % 7u) - 3;
            const int luma = 40 + field * 3 / 4 + texture + grain;
            uint8_t* p = &row[static_cast<size_t>(x) * 3];
            if (sigma >= 0) {
                // Smooth gradients: ramps across the image and broad value noise, per channel.
                const int rampX = static_cast<int>(static_cast<int64_t>(x) * 96 / size);
                const int rampY = static_cast<int>(static_cast<int64_t>(y) * 64 / rows);
                for (uint32_t c = 0; c < 3; ++c) {
                    const int broad = valueNoise(ux, uy, 11, 10 + c) / 2;
                    const int base = 30 + broad + (c == 0 ? rampX : c == 1 ? rampY : (rampX + rampY) / 2);
                    p[c] = clampByte(base + gaussianNoise(ux, uy, c, sigma));
                }
                continue;
            }
            p[0] = clampByte(luma + hue / 3);
            p[1] = clampByte(luma + (hue > 0 ? hue / 5 : -hue / 6));
            p[2] = clampByte(luma - hue / 3 - 12);
        }
        if (!out->write_scanline(y, 0, OIIO::TypeDesc::UINT8, row.data())) {
            std::fprintf(stderr, "%s: cannot write: %s\n", argv[1], out->geterror().c_str());
            return 1;
        }
    }
    if (!out->close()) {
        std::fprintf(stderr, "%s: cannot write: %s\n", argv[1], out->geterror().c_str());
        return 1;
    }
    return 0;
}
