#include "formats/dxt_colour_fit.hpp"

// The vectors here never cross a call boundary between code built for different CPUs (the
// helpers are inlined into each clone), which is what the compilers' ABI note is about.
#pragma GCC diagnostic ignored "-Wpsabi"

#include <array>
#include <bit>
#include <cstdlib>
#include <cstring>

#include "formats/vector_clones.hpp"

namespace pyramid {

namespace {

constexpr int kLanes = kDxtColourLanes;
// One value per block of a call, one block per lane.
using floats = float __attribute__((vector_size(4 * kLanes)));
using ints = int __attribute__((vector_size(4 * kLanes)));
using uints = unsigned __attribute__((vector_size(4 * kLanes)));

constexpr int expand5(int q) { return (q << 3) | (q >> 2); }
constexpr int expand6(int q) { return (q << 2) | (q >> 4); }

// For each 8-bit value, the endpoints (a, b) of `Bits` bits whose colour at index 2,
// (2 E(a) + E(b)) / 3, is closest to it; of equally close pairs, the one with the closest
// endpoints (then the lowest a and b).
struct SolidPair {
    uint8_t a = 0, b = 0;
};

// Built from the colours the pairs can make: for each colour c, the pair making it
// with the closest endpoints (the first in (a, b) order of those); then for each value, the
// closest colour, equally close ones by their pair's endpoints, then order. The same table as
// trying every pair for every value, in 256 x 256 steps instead of 256 x 4096.
template <int Bits>
std::array<SolidPair, 256> solidPairs() {
    constexpr int n = 1 << Bits;
    const auto expand = [](int q) { return Bits == 5 ? expand5(q) : expand6(q); };
    std::array<int, 256> spread{}, order{}; // per colour; spread -1: no pair makes it
    spread.fill(-1);
    for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
            const int ea = expand(a), eb = expand(b);
            const auto c = static_cast<size_t>((2 * ea + eb) / 3);
            const int s = std::abs(ea - eb);
            if (spread[c] < 0 || s < spread[c]) {
                spread[c] = s;
                order[c] = a * n + b;
            }
        }
    }
    std::array<SolidPair, 256> table{};
    for (int v = 0; v < 256; ++v) {
        int best = 1 << 30, pair = 0;
        for (int c = 0; c < 256; ++c) {
            const auto k = static_cast<size_t>(c);
            if (spread[k] < 0) {
                continue;
            }
            const int cost = std::abs(c - v) * 256 + spread[k];
            if (cost < best || (cost == best && order[k] < pair)) {
                best = cost;
                pair = order[k];
            }
        }
        table[static_cast<size_t>(v)] = {static_cast<uint8_t>(pair / n), static_cast<uint8_t>(pair % n)};
    }
    return table;
}

struct SolidTables {
    std::array<SolidPair, 256> five = solidPairs<5>();
    std::array<SolidPair, 256> six = solidPairs<6>();
};

// Built on first use, so that programs which never write DXT do not build them at start-up.
const SolidTables& solidTables() {
    static const SolidTables tables;
    return tables;
}

#define PYRAMID_INLINE [[gnu::always_inline]] inline

PYRAMID_INLINE floats splat(float v) { return floats{} + v; }
PYRAMID_INLINE ints splat(int v) { return ints{} + v; }
PYRAMID_INLINE floats vmin(floats a, floats b) { return a < b ? a : b; }
PYRAMID_INLINE floats vmax(floats a, floats b) { return a > b ? a : b; }
PYRAMID_INLINE floats magnitude(floats v) { return v < 0.0f ? -v : v; }
PYRAMID_INLINE floats truncated(floats v) { return __builtin_convertvector(__builtin_convertvector(v, ints), floats); }

// The 16 pixels of the lanes' blocks: r[k] holds pixel k of every block.
struct Pixels {
    floats r[16], g[16], b[16];
    floats squares; // the sum of the pixels' squared channels
};

// A candidate's endpoint codes (c0 >= c1), indices (pixel k's in bits 2k and 2k + 1) and
// squared error, per lane.
struct Fit {
    ints c0, c1;
    uints indices;
    floats error;
};

// The sum of 16 vectors, in a fixed order (a balanced tree).
PYRAMID_INLINE floats sum16(const floats* v) {
    floats s[8];
    for (int k = 0; k < 8; ++k) {
        s[k] = v[2 * k] + v[2 * k + 1];
    }
    return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
}

// Quantisation of an endpoint channel (0..255, any real) to 5 or 6 bits: round to nearest,
// clamped before the conversion (so that a far or NaN endpoint of a near-singular fit converts
// to an integer too, the same on every CPU).
PYRAMID_INLINE ints quantise(floats v, int bits) {
    const float top = static_cast<float>((1 << bits) - 1);
    floats x = v * (top / 255.0f) + 0.5f;
    x = x > 0.0f ? x : splat(0.0f); // NaN too
    x = x < top ? x : splat(top);
    return __builtin_convertvector(x, ints);
}

PYRAMID_INLINE ints packCode(ints r, ints g, ints b) { return (r << 11) | (g << 5) | b; }

// A 5:6:5 code's colour, each channel widened to 8 bits by bit replication.
PYRAMID_INLINE void widen(ints code, floats& r, floats& g, floats& b) {
    const ints r5 = (code >> 11) & 31, g6 = (code >> 5) & 63, b5 = code & 31;
    r = __builtin_convertvector((r5 << 3) | (r5 >> 2), floats);
    g = __builtin_convertvector((g6 << 2) | (g6 >> 4), floats);
    b = __builtin_convertvector((b5 << 3) | (b5 >> 2), floats);
}

// A candidate as the decoder sees it: codes ordered, colours widened, nearest colour per pixel.
PYRAMID_INLINE Fit evaluate(const Pixels& p, ints a, ints b) {
    Fit f;
    const ints larger = a > b;
    f.c0 = larger ? a : b;
    f.c1 = larger ? b : a;
    floats pr[4], pg[4], pb[4];
    widen(f.c0, pr[0], pg[0], pb[0]);
    widen(f.c1, pr[1], pg[1], pb[1]);
    // The thirds by truncating division (exact: the quotients of integers below 2^24 by 3
    // are correctly rounded, never up to the next integer).
    pr[2] = truncated((2.0f * pr[0] + pr[1]) / 3.0f);
    pg[2] = truncated((2.0f * pg[0] + pg[1]) / 3.0f);
    pb[2] = truncated((2.0f * pb[0] + pb[1]) / 3.0f);
    const ints four = f.c0 > f.c1; // equal codes: index 3 is never taken (its colour is made index 0's)
    pr[3] = four ? truncated((pr[0] + 2.0f * pr[1]) / 3.0f) : pr[0];
    pg[3] = four ? truncated((pg[0] + 2.0f * pg[1]) / 3.0f) : pg[0];
    pb[3] = four ? truncated((pb[0] + 2.0f * pb[1]) / 3.0f) : pb[0];
    // Pixel by pixel: its nearest colour (the first of equally near ones). Colour c's squared
    // distance less |p|^2 is e = |c|^2 - 2 p.c; the least of 4 e + c over the four colours is
    // the nearest colour's e and, in its low two bits, its index (the lower index of equal e).
    // Every term is an integer below 2^24, so all of this is exact, and so is the error, |p|^2
    // summed once plus the least e of each pixel.
    floats key[4], tr[4], tg[4], tb[4];
    for (int c = 0; c < 4; ++c) {
        key[c] = (pr[c] * pr[c] + pg[c] * pg[c] + pb[c] * pb[c]) * 4.0f + static_cast<float>(c);
        tr[c] = pr[c] * 8.0f;
        tg[c] = pg[c] * 8.0f;
        tb[c] = pb[c] * 8.0f;
    }
    uints indices{};
    ints error{};
    for (int k = 0; k < 16; ++k) {
        const floats red = p.r[k], green = p.g[k], blue = p.b[k];
        floats least = key[0] - (red * tr[0] + green * tg[0] + blue * tb[0]);
        for (int c = 1; c < 4; ++c) {
            least = vmin(least, key[c] - (red * tr[c] + green * tg[c] + blue * tb[c]));
        }
        const ints q = __builtin_convertvector(least, ints);
        error += q >> 2;
        indices |= __builtin_convertvector(q & 3, uints) << (2 * k);
    }
    f.indices = indices;
    f.error = p.squares + __builtin_convertvector(error, floats);
    return f;
}

// Keeps, lane by lane, the candidate of lower error (`allowed` lanes only). False when no lane
// took it.
PYRAMID_INLINE bool keepBetter(Fit& best, const Fit& candidate, ints allowed) {
    const ints take = (candidate.error < best.error) & allowed;
    bool any = false;
    for (int l = 0; l < kLanes; ++l) {
        any |= take[l] != 0;
    }
    if (!any) {
        return false;
    }
    best.c0 = take ? candidate.c0 : best.c0;
    best.c1 = take ? candidate.c1 : best.c1;
    best.error = take ? candidate.error : best.error;
    best.indices = take ? candidate.indices : best.indices;
    return true;
}

PYRAMID_WIDE_VECTOR_CLONES // the same bytes in wider vectors where the CPU has them
void encodeLanes(const uint8_t* const* blocks, uint8_t* const* out, int count, int refinements, int* squaredErrors) {
    // Pixel k of every lane's block as one word (R, G, B, A from its lowest byte): a transposition
    // of words, then the channels split and converted a vector at a time (not byte by byte).
    alignas(64) uint32_t words[16][kLanes];
    int rounded[3][kLanes];
    const SolidTables& solid = solidTables();
    for (int l = 0; l < kLanes; ++l) {
        uint32_t pixels[16]; // in memory order: R, G, B, A from the lowest byte on little-endian machines
        std::memcpy(pixels, blocks[l < count ? l : 0], sizeof(pixels));
        for (int k = 0; k < 16; ++k) {
            const uint32_t v = pixels[k];
            words[k][l] = std::endian::native == std::endian::little
                              ? v
                              : (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
        }
    }
    Pixels p;
    for (int k = 0; k < 16; ++k) {
        ints w;
        std::memcpy(&w, words[k], sizeof(w));
        p.r[k] = __builtin_convertvector(w & 255, floats);
        p.g[k] = __builtin_convertvector((w >> 8) & 255, floats);
        p.b[k] = __builtin_convertvector((w >> 16) & 255, floats); // alpha, in the top byte, ignored
    }
    p.squares = splat(0.0f);
    for (int k = 0; k < 16; ++k) {
        p.squares += p.r[k] * p.r[k] + p.g[k] * p.g[k] + p.b[k] * p.b[k];
    }

    // The mean (exact: a sum of integers over 16) and the covariance, in a fixed order.
    const floats mr = sum16(p.r) * (1.0f / 16.0f), mg = sum16(p.g) * (1.0f / 16.0f), mb = sum16(p.b) * (1.0f / 16.0f);
    floats dr[16], dg[16], db[16], t[16];
    floats prr[16], pgg[16], pbb[16], prg[16], prb[16], pgb[16];
    for (int k = 0; k < 16; ++k) {
        dr[k] = p.r[k] - mr;
        dg[k] = p.g[k] - mg;
        db[k] = p.b[k] - mb;
        prr[k] = dr[k] * dr[k];
        pgg[k] = dg[k] * dg[k];
        pbb[k] = db[k] * db[k];
        prg[k] = dr[k] * dg[k];
        prb[k] = dr[k] * db[k];
        pgb[k] = dg[k] * db[k];
    }
    const floats crr = sum16(prr), cgg = sum16(pgg), cbb = sum16(pbb), crg = sum16(prg), crb = sum16(prb), cgb = sum16(pgb);

    // The principal axis: power iteration from the covariance's largest column.
    const ints fromR = (crr >= cgg) & (crr >= cbb), fromG = ~fromR & (cgg >= cbb);
    floats vr = fromR ? crr : fromG ? crg : crb;
    floats vg = fromR ? crg : fromG ? cgg : cgb;
    floats vb = fromR ? crb : fromG ? cgb : cbb;
    for (int it = 0; it < 4; ++it) {
        const floats nr = crr * vr + crg * vg + crb * vb;
        const floats ng = crg * vr + cgg * vg + cgb * vb;
        const floats nb = crb * vr + cgb * vg + cbb * vb;
        const floats m = vmax(magnitude(nr), vmax(magnitude(ng), magnitude(nb)));
        const ints moved = m > 0.0f;
        const floats inverse = 1.0f / (moved ? m : splat(1.0f));
        vr = moved ? nr * inverse : vr;
        vg = moved ? ng * inverse : vg;
        vb = moved ? nb * inverse : vb;
    }
    const floats length2 = vr * vr + vg * vg + vb * vb;
    for (int k = 0; k < 16; ++k) {
        t[k] = dr[k] * vr + dg[k] * vg + db[k] * vb;
    }
    floats lo = t[0], hi = t[0];
    for (int k = 1; k < 16; ++k) {
        lo = vmin(lo, t[k]);
        hi = vmax(hi, t[k]);
    }
    const ints axis = length2 > 0.0f;
    const floats safeLength2 = axis ? length2 : splat(1.0f);
    lo = axis ? lo / safeLength2 : splat(0.0f);
    hi = axis ? hi / safeLength2 : splat(0.0f);
    Fit best = evaluate(p, packCode(quantise(mr + hi * vr, 5), quantise(mg + hi * vg, 6), quantise(mb + hi * vb, 5)),
                        packCode(quantise(mr + lo * vr, 5), quantise(mg + lo * vg, 6), quantise(mb + lo * vb, 5)));

    // The mean colour's best pair per channel.
    const ints meanR = __builtin_convertvector(mr + 0.5f, ints), meanG = __builtin_convertvector(mg + 0.5f, ints),
             meanB = __builtin_convertvector(mb + 0.5f, ints);
    for (int l = 0; l < kLanes; ++l) {
        rounded[0][l] = meanR[l];
        rounded[1][l] = meanG[l];
        rounded[2][l] = meanB[l];
    }
    ints solidA, solidB;
    for (int l = 0; l < kLanes; ++l) {
        const SolidPair r = solid.five[static_cast<size_t>(rounded[0][l])];
        const SolidPair g = solid.six[static_cast<size_t>(rounded[1][l])];
        const SolidPair b = solid.five[static_cast<size_t>(rounded[2][l])];
        solidA[l] = (r.a << 11) | (g.a << 5) | b.a;
        solidB[l] = (r.b << 11) | (g.b << 5) | b.b;
    }
    keepBetter(best, evaluate(p, solidA, solidB), splat(-1));

    // Least-squares endpoints for the best indices (until no lane improves). Weights in thirds: index 0 is all c0 (3),
    // 1 all c1 (0), 2 two thirds of c0 (2), 3 one third (1).
    for (int it = 0; it < refinements; ++it) {
        floats waa[16], wab[16], wbb[16], war[16], wag[16], wab2[16], wbr[16], wbg[16], wbb2[16];
        for (int k = 0; k < 16; ++k) {
            const ints i = __builtin_convertvector((best.indices >> (2 * k)) & 3u, ints);
            const floats a = __builtin_convertvector(i == 0 ? splat(3) : i == 1 ? splat(0) : 4 - i, floats);
            const floats b = 3.0f - a;
            waa[k] = a * a;
            wab[k] = a * b;
            wbb[k] = b * b;
            war[k] = a * p.r[k];
            wag[k] = a * p.g[k];
            wab2[k] = a * p.b[k];
            wbr[k] = b * p.r[k];
            wbg[k] = b * p.g[k];
            wbb2[k] = b * p.b[k];
        }
        const floats aa = sum16(waa), ab = sum16(wab), bb = sum16(wbb);
        const floats ar = sum16(war), ag = sum16(wag), abl = sum16(wab2), br = sum16(wbr), bg = sum16(wbg), bbl = sum16(wbb2);
        const floats det = aa * bb - ab * ab;
        const ints solvable = det != 0.0f;
        const floats f = 3.0f / (solvable ? det : splat(1.0f));
        const Fit refined = evaluate(p,
                                     packCode(quantise((ar * bb - br * ab) * f, 5), quantise((ag * bb - bg * ab) * f, 6),
                                              quantise((abl * bb - bbl * ab) * f, 5)),
                                     packCode(quantise((br * aa - ar * ab) * f, 5), quantise((bg * aa - ag * ab) * f, 6),
                                              quantise((bbl * aa - abl * ab) * f, 5)));
        if (!keepBetter(best, refined, solvable)) {
            break; // the same indices again: another step would give the same endpoints
        }
    }

    const uints indices = best.indices;
    for (int l = 0; l < count; ++l) {
        uint8_t* o = out[l];
        const auto c0 = static_cast<uint32_t>(best.c0[l]), c1 = static_cast<uint32_t>(best.c1[l]);
        const uint32_t packed = indices[l];
        o[0] = static_cast<uint8_t>(c0);
        o[1] = static_cast<uint8_t>(c0 >> 8);
        o[2] = static_cast<uint8_t>(c1);
        o[3] = static_cast<uint8_t>(c1 >> 8);
        o[4] = static_cast<uint8_t>(packed);
        o[5] = static_cast<uint8_t>(packed >> 8);
        o[6] = static_cast<uint8_t>(packed >> 16);
        o[7] = static_cast<uint8_t>(packed >> 24);
        if (squaredErrors != nullptr) {
            squaredErrors[l] = static_cast<int>(best.error[l]);
        }
    }
}

} // namespace

void encodeDxtColourBlocks(const uint8_t* const* blocks, uint8_t* const* out, int count, int refinements,
                           int* squaredErrors) {
    encodeLanes(blocks, out, count, refinements, squaredErrors);
}

} // namespace pyramid
