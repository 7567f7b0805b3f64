// A deterministic synthetic DEM for bench/dem_bench.sh and bench/sphere_bench.sh: SIZE x SIZE
// (or WIDTH x HEIGHT) float32 heights in metres, written as an uncompressed striped TIFF.
//
//   dem_synthetic_heights OUTPUT.tif [SIZE | WIDTHxHEIGHT]     (default 8193)
//
// Content: fractal value noise (octaves from 4096- down to 2-sample cells, the amplitude halving
// with the cell size) folded into ridges at the two coarsest octaves, about 0..4000 m: a
// mountain range's spectrum, so residual sizes and compression are like a real DEM's. Integer
// hashing and IEEE double arithmetic in a fixed order: the same bytes on every machine.
#include <algorithm>
#include <cmath>
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

// Value noise in [-1, 1] with cells of 2^shift samples, smoothstep-interpolated.
double valueNoise(uint32_t x, uint32_t y, int shift, uint32_t seed) {
    const uint32_t cx = x >> shift, cy = y >> shift;
    const double scale = 1.0 / static_cast<double>(1u << shift);
    auto fade = [](double t) { return t * t * (3.0 - 2.0 * t); };
    const double fx = fade(static_cast<double>(x & ((1u << shift) - 1u)) * scale);
    const double fy = fade(static_cast<double>(y & ((1u << shift) - 1u)) * scale);
    auto corner = [&](uint32_t i, uint32_t j) { return static_cast<double>(hash(i, j, seed) & 0xffffu) / 32767.5 - 1.0; };
    const double top = corner(cx, cy) + (corner(cx + 1, cy) - corner(cx, cy)) * fx;
    const double bottom = corner(cx, cy + 1) + (corner(cx + 1, cy + 1) - corner(cx, cy + 1)) * fx;
    return top + (bottom - top) * fy;
}

float height(uint32_t x, uint32_t y) {
    double h = 0.0;
    double amplitude = 1400.0;
    for (int shift = 12; shift >= 1; --shift) {
        const double v = valueNoise(x, y, shift, static_cast<uint32_t>(shift));
        h += amplitude * (shift >= 11 ? 1.0 - 2.0 * std::fabs(v) : v); // ridges at the coarsest octaves
        amplitude *= 0.5;
    }
    return static_cast<float>(std::max(0.0, h + 1800.0));
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argc > 3) {
        std::fprintf(stderr, "usage: %s OUTPUT.tif [SIZE | WIDTHxHEIGHT]\n", argv[0]);
        return 2;
    }
    int size = 8193, rows = 8193;
    if (argc == 3 && std::sscanf(argv[2], "%dx%d", &size, &rows) != 2) {
        rows = size;
    }
    if (size < 2 || size > 65537 || rows < 2 || rows > 65537) {
        std::fprintf(stderr, "%s: sides must be 2..65537\n", argv[0]);
        return 2;
    }
    auto out = OIIO::ImageOutput::create(argv[1]);
    OIIO::ImageSpec spec(size, rows, 1, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "none");
    if (!out || !out->open(argv[1], spec)) {
        std::fprintf(stderr, "%s: cannot write: %s\n", argv[1], OIIO::geterror().c_str());
        return 1;
    }
    std::vector<float> row(static_cast<size_t>(size));
    for (int y = 0; y < rows; ++y) {
        for (int x = 0; x < size; ++x) {
            row[static_cast<size_t>(x)] = height(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
        }
        if (!out->write_scanline(y, 0, OIIO::TypeDesc::FLOAT, row.data())) {
            std::fprintf(stderr, "%s: write failed: %s\n", argv[1], out->geterror().c_str());
            return 1;
        }
    }
    return out->close() ? 0 : 1;
}
