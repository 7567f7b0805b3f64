#include "formats/deflate_runs.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

#include "formats/deflate_huffman.hpp"
#include "formats/deflate_run_starts.hpp"
#include "formats/error.hpp"

namespace pyramid {

namespace {

using deflate::load64;

constexpr size_t kMinRun = 4;
constexpr size_t kMaxRun = 258;
constexpr int kEndOfBlock = 256;

// The length symbols (257..284; 285 is 258) and their extra bits, by length - 3.
struct LengthCode {
    uint16_t symbol;
    uint8_t extraBits;
    uint8_t base; // length - 3 of the symbol's first length
};

const std::array<LengthCode, 256>& lengthCodes() {
    static const std::array<LengthCode, 256> codes = [] {
        std::array<LengthCode, 256> c{};
        int symbol = 257, base = 0;
        for (int len3 = 0; len3 < 256; ++len3) {
            // Symbols 257..264 cover one length each, then four symbols per extra bit, to 284.
            const int extra = symbol < 265 ? 0 : (symbol - 261) / 4;
            if (len3 >= base + (1 << extra)) {
                base += 1 << extra;
                ++symbol;
            }
            const int e = symbol < 265 ? 0 : (symbol - 261) / 4;
            c[static_cast<size_t>(len3)] = {static_cast<uint16_t>(symbol), static_cast<uint8_t>(e), static_cast<uint8_t>(base)};
        }
        c[255] = {285, 0, 255}; // 258, Deflate's longest match, has a symbol of its own
        return c;
    }();
    return codes;
}

// A run: `length` bytes from `position` repeating those `distance` bytes before.
struct Run {
    uint32_t position;
    uint16_t length;
    uint16_t distance;
};

// The runs of at least kMinRun bytes at distance `pixel` or 1 (the first where both start),
// taken greedily from the first byte on (deflate_run_starts.hpp finds where they start).
void findRuns(const uint8_t* p, size_t n, size_t pixel, std::vector<Run>& runs) {
    runs.clear();
    if (n < kMaxRun + 80) {
        return; // a strip this short is coded as literals
    }
    const size_t last = n - kMaxRun - 72; // runs extend eight bytes at a time; starts read 64
    size_t i = pixel;
    while (true) {
        const RunStart start = nextRunStart(p, i, last, pixel);
        if (start.at >= last) {
            break;
        }
        i = start.at;
        const size_t distance = start.distance;
        const uint8_t* a = p + i;
        size_t length = kMinRun;
        while (length < kMaxRun) {
            const uint64_t x = load64(a + length) ^ load64(a + length - distance);
            if (x != 0) {
                length += static_cast<size_t>(std::countr_zero(x) >> 3);
                break;
            }
            length += 8;
        }
        length = std::min(length, kMaxRun);
        runs.push_back({static_cast<uint32_t>(i), static_cast<uint16_t>(length), static_cast<uint16_t>(distance)});
        i += length;
    }
}

} // namespace

size_t deflateRuns(std::span<const uint8_t> bytes, int pixelBytes, std::vector<uint8_t>& out) {
    if (pixelBytes < 1 || pixelBytes > 4) {
        fail("", "runs at a distance of " + std::to_string(pixelBytes) + " bytes: not 1 to 4");
    }
    const uint8_t* p = bytes.data();
    const size_t n = bytes.size();
    thread_local std::vector<Run> runs;
    findRuns(p, n, static_cast<size_t>(pixelBytes), runs);

    // Symbol counts: the bytes between runs (those inside runs are not coded as literals); a
    // length and a distance per run. Distances 1 to 4 are symbols 0 to 3 (no extra bits).
    std::array<uint32_t, 286> literalFreq{};
    std::array<uint32_t, 30> distanceFreq{};
    const auto& lengths = lengthCodes();
    {
        deflate::ByteCounts counts;
        size_t at = 0;
        for (const Run& r : runs) {
            counts.add(p + at, r.position - at);
            at = r.position + r.length;
            ++literalFreq[lengths[r.length - 3u].symbol];
            ++distanceFreq[r.distance - 1u];
        }
        counts.add(p + at, n - at);
        counts.addTo(literalFreq.data());
    }
    literalFreq[kEndOfBlock] = 1;
    if (std::count_if(literalFreq.begin(), literalFreq.end(), [](uint32_t f) { return f != 0; }) < 2) {
        ++literalFreq[0]; // a code needs two symbols
    }
    // Two distance symbols at least, so that the distance code is complete.
    for (size_t s = 0; std::count_if(distanceFreq.begin(), distanceFreq.end(), [](uint32_t f) { return f != 0; }) < 2; ++s) {
        distanceFreq[s] = std::max<uint32_t>(distanceFreq[s], 1);
    }
    int literalCount = 286, distanceCount = 4;
    while (literalFreq[static_cast<size_t>(literalCount - 1)] == 0) {
        --literalCount;
    }
    while (distanceFreq[static_cast<size_t>(distanceCount - 1)] == 0) {
        --distanceCount;
    }
    std::array<uint8_t, 286> literalBits{};
    std::array<uint8_t, 4> distanceBits{};
    std::array<uint16_t, 286> literalCodes{};
    std::array<uint16_t, 4> distanceCodes{};
    deflate::huffmanLengths(literalFreq.data(), literalCount, 15, literalBits.data());
    deflate::huffmanLengths(distanceFreq.data(), distanceCount, 15, distanceBits.data());
    deflate::canonicalCodes(literalBits.data(), literalCount, literalCodes.data());
    deflate::canonicalCodes(distanceBits.data(), distanceCount, distanceCodes.data());
    uint64_t bits = 0;
    for (size_t s = 0; s < 286; ++s) {
        bits += static_cast<uint64_t>(literalFreq[s]) * (literalBits[s] + 5u);
    }
    for (size_t s = 0; s < 4; ++s) {
        bits += static_cast<uint64_t>(distanceFreq[s]) * distanceBits[s];
    }
    const size_t bound = 2 + deflate::kDynamicHeaderBytes + bits / 8 + 4 + 16;
    if (out.size() < bound) {
        out.resize(bound);
    }
    deflate::putZlibHeader(out.data());
    deflate::BitWriter w(out.data() + 2);
    deflate::putDynamicHeader(w, true, literalBits.data(), literalCount, distanceBits.data(), distanceCount);

    std::array<uint32_t, 256> packed{}; // code | length << 16
    int longest = 0;
    for (size_t v = 0; v < 256; ++v) {
        packed[v] = literalCodes[v] | static_cast<uint32_t>(literalBits[v]) << 16;
        longest = std::max<int>(longest, literalBits[v]);
    }
    const auto putLiterals = [&](size_t from, size_t to) { deflate::putLiterals(w, packed.data(), longest, p, from, to); };
    size_t at = 0;
    for (const Run& r : runs) {
        putLiterals(at, r.position);
        const LengthCode& c = lengths[r.length - 3u];
        w.put(literalCodes[c.symbol], literalBits[c.symbol]);
        w.put(static_cast<uint32_t>(r.length - 3u - c.base), c.extraBits);
        w.put(distanceCodes[r.distance - 1u], distanceBits[r.distance - 1u]);
        w.flush();
        at = r.position + r.length;
    }
    putLiterals(at, n);
    w.put(literalCodes[kEndOfBlock], literalBits[kEndOfBlock]);
    return static_cast<size_t>(deflate::putAdler32(w.finish(), p, n) - out.data());
}

} // namespace pyramid
