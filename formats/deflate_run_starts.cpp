#include "formats/deflate_run_starts.hpp"

#include <bit>
#include <cstring>

#include "formats/deflate_huffman.hpp"
#include "formats/vector_clones.hpp"

#if PYRAMID_VECTOR_CLONES_ON
#include <immintrin.h>
#endif

namespace pyramid {

namespace {

using deflate::load64;

// Bit k set where byte k of `x` (the k-th in memory) is zero.
uint32_t zeroBytes(uint64_t x) {
    constexpr uint64_t kLow7 = 0x7f7f7f7f7f7f7f7full;
    const uint64_t high = ~(((x & kLow7) + kLow7) | x | kLow7); // bit 7 of each zero byte
    return static_cast<uint32_t>(((high >> 7) * 0x0102040810204080ull) >> 56);
}

// The start among `count` places from `at` whose bits are set in `pixelStarts | byteStarts`
// (bit k: place at + k), if any before `last`.
bool firstStart(uint64_t pixelStarts, uint64_t byteStarts, size_t at, size_t last, size_t pixel, RunStart& found) {
    const uint64_t starts = pixelStarts | byteStarts;
    if (starts == 0) {
        return false;
    }
    const int k = std::countr_zero(starts);
    found = at + static_cast<size_t>(k) < last
                ? RunStart{at + static_cast<size_t>(k), (pixelStarts >> k & 1u) != 0 ? pixel : 1}
                : RunStart{last, 0};
    return true;
}

} // namespace

RunStart nextRunStartWords(const uint8_t* p, size_t from, size_t last, size_t pixel) {
    for (size_t i = from; i < last; i += 5) {
        const uint64_t w = load64(p + i);
        const uint32_t zp = zeroBytes(w ^ load64(p + i - pixel));
        const uint32_t z1 = zeroBytes(w ^ load64(p + i - 1));
        // Places 0..4 of the word have their four bytes inside it.
        const uint32_t sp = zp & zp >> 1 & zp >> 2 & zp >> 3 & 0x1fu;
        const uint32_t s1 = z1 & z1 >> 1 & z1 >> 2 & z1 >> 3 & 0x1fu;
        RunStart found{};
        if (firstStart(sp, s1, i, last, pixel, found)) {
            return found;
        }
    }
    return {last, 0};
}

#if PYRAMID_VECTOR_CLONES_ON

namespace {

__attribute__((target("avx2"))) uint64_t equalMask(const uint8_t* a, const uint8_t* b) {
    const __m256i x0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a));
    const __m256i y0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b));
    const __m256i x1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + 32));
    const __m256i y1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + 32));
    const auto low = static_cast<uint32_t>(_mm256_movemask_epi8(_mm256_cmpeq_epi8(x0, y0)));
    const auto high = static_cast<uint32_t>(_mm256_movemask_epi8(_mm256_cmpeq_epi8(x1, y1)));
    return low | static_cast<uint64_t>(high) << 32;
}

__attribute__((target("avx2"))) RunStart nextRunStartAvx2(const uint8_t* p, size_t from, size_t last, size_t pixel) {
    constexpr uint64_t kPlaces = (uint64_t{1} << 60) - 1; // places 0..59 have their four bytes in the 64
    for (size_t i = from; i < last; i += 60) {
        const uint64_t mp = equalMask(p + i, p + i - pixel);
        const uint64_t m1 = equalMask(p + i, p + i - 1);
        const uint64_t sp = mp & mp >> 1 & mp >> 2 & mp >> 3 & kPlaces;
        const uint64_t s1 = m1 & m1 >> 1 & m1 >> 2 & m1 >> 3 & kPlaces;
        RunStart found{};
        if (firstStart(sp, s1, i, last, pixel, found)) {
            return found;
        }
    }
    return {last, 0};
}

} // namespace

RunStart nextRunStartWide(const uint8_t* p, size_t from, size_t last, size_t pixel) {
    static const bool avx2 = __builtin_cpu_supports("avx2");
    return avx2 ? nextRunStartAvx2(p, from, last, pixel) : nextRunStartWords(p, from, last, pixel);
}

#else

RunStart nextRunStartWide(const uint8_t* p, size_t from, size_t last, size_t pixel) {
    return nextRunStartWords(p, from, last, pixel);
}

#endif

RunStart nextRunStart(const uint8_t* p, size_t from, size_t last, size_t pixel) {
    return nextRunStartWide(p, from, last, pixel);
}

} // namespace pyramid
