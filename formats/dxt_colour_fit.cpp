#include "formats/dxt_colour_fit.hpp"

// The vectors here never cross a call boundary between code built for different CPUs (the
// helpers are inlined into each width's function), which is what the compilers' ABI note is about.
#pragma GCC diagnostic ignored "-Wpsabi"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <cstring>
#include <string>

#include "formats/dxt_solid_pairs.hpp"
#include "formats/error.hpp"
#include "formats/vector_clones.hpp"

namespace pyramid {

namespace {

#define PYRAMID_INLINE [[gnu::always_inline]] static inline

// Vectors of N floats, ints and unsigned ints, one specialisation per width (GCC 12 drops a
// vector_size that depends on a template's parameter).
template <int N>
struct Lanes;
#define PYRAMID_LANES(N)                                                                           \
    template <>                                                                                    \
    struct Lanes<N> {                                                                              \
        typedef float floats __attribute__((vector_size(N * 4)));                                  \
        typedef int ints __attribute__((vector_size(N * 4)));                                      \
        typedef unsigned uints __attribute__((vector_size(N * 4)));                                \
    };
PYRAMID_LANES(4)
PYRAMID_LANES(8)
PYRAMID_LANES(16)
#undef PYRAMID_LANES

// The fit of up to kLanes blocks at a time, one per lane of vectors as wide as one register of
// the CPU (encodeDxtColourBlocks picks 4, 8 or 16): wider vectors spill. On an AVX2 machine, 16
// lanes (pairs of registers) took 3.9 times as long as two calls of 8, and 2.8 times as long
// as four calls of 4 on a plain x86-64 one; the bytes are the same (bench/ortho_bench.md).
template <int kLanes>
struct LaneFit {
    // One value per block of a call, one block per lane.
    using floats = typename Lanes<kLanes>::floats;
    using ints = typename Lanes<kLanes>::ints;
    using uints = typename Lanes<kLanes>::uints;

    PYRAMID_INLINE floats splat(float v) { return floats{} + v; }
    PYRAMID_INLINE ints splat(int v) { return ints{} + v; }
    PYRAMID_INLINE floats vmin(floats a, floats b) { return a < b ? a : b; }
    PYRAMID_INLINE floats vmax(floats a, floats b) { return a > b ? a : b; }
    PYRAMID_INLINE floats magnitude(floats v) { return v < 0.0f ? -v : v; }
    PYRAMID_INLINE floats truncated(floats v) {
        return __builtin_convertvector(__builtin_convertvector(v, ints), floats);
    }

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

    PYRAMID_INLINE void encodeLanes(const uint8_t* const* blocks, uint8_t* const* out, int count, int refinements,
                                    int* squaredErrors) {
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
        const floats mr = sum16(p.r) * (1.0f / 16.0f), mg = sum16(p.g) * (1.0f / 16.0f),
                     mb = sum16(p.b) * (1.0f / 16.0f);
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
        const floats crr = sum16(prr), cgg = sum16(pgg), cbb = sum16(pbb);
        const floats crg = sum16(prg), crb = sum16(prb), cgb = sum16(pgb);

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
        const ints axisHi = packCode(quantise(mr + hi * vr, 5), quantise(mg + hi * vg, 6), quantise(mb + hi * vb, 5));
        const ints axisLo = packCode(quantise(mr + lo * vr, 5), quantise(mg + lo * vg, 6), quantise(mb + lo * vb, 5));
        Fit best = evaluate(p, axisHi, axisLo);

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

        // Least-squares endpoints for the best indices (until no lane improves). Weights in thirds:
        // index 0 is all c0 (3), 1 all c1 (0), 2 two thirds of c0 (2), 3 one third (1).
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
            const floats ar = sum16(war), ag = sum16(wag), abl = sum16(wab2);
            const floats br = sum16(wbr), bg = sum16(wbg), bbl = sum16(wbb2);
            const floats det = aa * bb - ab * ab;
            const ints solvable = det != 0.0f;
            const floats f = 3.0f / (solvable ? det : splat(1.0f));
            const ints fitA = packCode(quantise((ar * bb - br * ab) * f, 5), quantise((ag * bb - bg * ab) * f, 6),
                                       quantise((abl * bb - bbl * ab) * f, 5));
            const ints fitB = packCode(quantise((br * aa - ar * ab) * f, 5), quantise((bg * aa - ag * ab) * f, 6),
                                       quantise((bbl * aa - abl * ab) * f, 5));
            const Fit refined = evaluate(p, fitA, fitB);
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
}; // struct LaneFit

using FitFunction = void (*)(const uint8_t* const*, uint8_t* const*, int, int, int*);

// Each width compiled for the instructions that hold it in one register.
#if PYRAMID_VECTOR_CLONES_ON
[[gnu::target("avx512f")]] void fit16(const uint8_t* const* blocks, uint8_t* const* out, int count, int refinements,
                                      int* squaredErrors) {
    LaneFit<16>::encodeLanes(blocks, out, count, refinements, squaredErrors);
}
[[gnu::target("avx2")]] void fit8(const uint8_t* const* blocks, uint8_t* const* out, int count, int refinements,
                                  int* squaredErrors) {
    LaneFit<8>::encodeLanes(blocks, out, count, refinements, squaredErrors);
}
#endif
void fit4(const uint8_t* const* blocks, uint8_t* const* out, int count, int refinements, int* squaredErrors) {
    LaneFit<4>::encodeLanes(blocks, out, count, refinements, squaredErrors);
}

// The fit in vectors of `lanes`, where this machine can run them; else null.
FitFunction fitIn(int lanes) {
    switch (lanes) {
#if PYRAMID_VECTOR_CLONES_ON
    case 16: return __builtin_cpu_supports("avx512f") ? fit16 : nullptr;
    case 8: return __builtin_cpu_supports("avx2") ? fit8 : nullptr;
#endif
    case 4: return fit4;
    default: return nullptr;
    }
}

void encodeWith(FitFunction fit, int lanes, const uint8_t* const* blocks, uint8_t* const* out, int count,
                int refinements, int* squaredErrors) {
    for (int first = 0; first < count; first += lanes) {
        fit(blocks + first, out + first, std::min(lanes, count - first), refinements,
            squaredErrors != nullptr ? squaredErrors + first : nullptr);
    }
}

} // namespace

int dxtColourLanes() {
    static const int lanes = fitIn(16) != nullptr ? 16 : fitIn(8) != nullptr ? 8 : 4;
    return lanes;
}

bool dxtColourLanesAvailable(int lanes) { return fitIn(lanes) != nullptr; }

void encodeDxtColourBlocks(const uint8_t* const* blocks, uint8_t* const* out, int count, int refinements,
                           int* squaredErrors) {
    static const FitFunction fit = fitIn(dxtColourLanes());
    encodeWith(fit, dxtColourLanes(), blocks, out, count, refinements, squaredErrors);
}

void encodeDxtColourBlocksIn(int lanes, const uint8_t* const* blocks, uint8_t* const* out, int count,
                             int refinements, int* squaredErrors) {
    const FitFunction fit = fitIn(lanes);
    if (fit == nullptr) {
        fail("", "DXT colour fit: no vectors of " + std::to_string(lanes) + " lanes on this machine");
    }
    encodeWith(fit, lanes, blocks, out, count, refinements, squaredErrors);
}

} // namespace pyramid
