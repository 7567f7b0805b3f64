#include "formats/deflate_literals.hpp"

#include <algorithm>
#include <array>

#include "formats/deflate_huffman.hpp"

namespace pyramid {

namespace {

constexpr int kEndOfBlock = 256;

} // namespace

LiteralCost literalCost(std::span<const uint8_t> bytes) {
    LiteralCost cost;
    deflate::countBytes(bytes, cost.counts);
    std::array<uint32_t, 257> frequencies{};
    std::copy_n(cost.counts, 256, frequencies.begin());
    frequencies[kEndOfBlock] = 1;
    if (bytes.empty()) {
        frequencies[0] = 1; // a code needs two symbols
    }
    deflate::huffmanLengths(frequencies.data(), 257, 15, cost.lengths);
    for (int s = 0; s < 257; ++s) {
        cost.bits += static_cast<uint64_t>(frequencies[static_cast<size_t>(s)]) * cost.lengths[s];
    }
    return cost;
}

size_t deflateLiterals(std::span<const uint8_t> bytes, const LiteralCost& cost, std::vector<uint8_t>& out) {
    // The 257 literal/length symbols' code lengths and one distance code (of 1 bit, never used:
    // RFC 1951 allows the one code of a block without matches).
    static constexpr uint8_t kDistanceLength = 1;
    std::array<uint16_t, 257> codes{};
    deflate::canonicalCodes(cost.lengths, 257, codes.data());
    const size_t bound = 2 + deflate::kDynamicHeaderBytes + static_cast<size_t>(cost.bits / 8) + 4 + 16;
    if (out.size() < bound) {
        out.resize(bound);
    }
    deflate::putZlibHeader(out.data());
    deflate::BitWriter w(out.data() + 2);
    deflate::putDynamicHeader(w, true, cost.lengths, 257, &kDistanceLength, 1);
    std::array<uint32_t, 256> packed{}; // code | length << 16
    int longest = 0;
    for (size_t v = 0; v < 256; ++v) {
        packed[v] = codes[v] | static_cast<uint32_t>(cost.lengths[v]) << 16;
        longest = std::max<int>(longest, cost.lengths[v]);
    }
    const uint8_t* p = bytes.data();
    const size_t n = bytes.size();
    deflate::putLiterals(w, packed.data(), longest, p, 0, n);
    w.put(codes[kEndOfBlock], cost.lengths[kEndOfBlock]);
    return static_cast<size_t>(deflate::putAdler32(w.finish(), p, n) - out.data());
}

} // namespace pyramid
