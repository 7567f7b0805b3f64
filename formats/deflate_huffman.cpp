#include "formats/deflate_huffman.hpp"

#include <algorithm>
#include <array>
#include <vector>

#include <libdeflate.h>

namespace pyramid::deflate {

namespace {

uint32_t reverseBits(uint32_t code, int bits) {
    uint32_t reversed = 0;
    for (int k = 0; k < bits; ++k) {
        reversed = (reversed << 1) | ((code >> k) & 1u);
    }
    return reversed;
}

// One code-length symbol (0..18) and its extra bits.
struct LengthSymbol {
    uint8_t symbol;
    uint8_t extra;
};

// The run-length coding of a sequence of code lengths (RFC 1951 3.2.7): runs of zeros by 17 and
// 18, repeats of a non-zero length by 16.
std::vector<LengthSymbol> runLengths(const uint8_t* lengths, int count) {
    std::vector<LengthSymbol> out;
    int i = 0;
    while (i < count) {
        const uint8_t v = lengths[i];
        int run = 1;
        while (i + run < count && lengths[i + run] == v) {
            ++run;
        }
        i += run;
        if (v == 0) {
            for (; run >= 11; run -= std::min(run, 138)) {
                out.push_back({18, static_cast<uint8_t>(std::min(run, 138) - 11)});
            }
            if (run >= 3) {
                out.push_back({17, static_cast<uint8_t>(run - 3)});
                run = 0;
            }
        } else {
            out.push_back({v, 0});
            --run;
            for (; run >= 3; run -= std::min(run, 6)) {
                out.push_back({16, static_cast<uint8_t>(std::min(run, 6) - 3)});
            }
        }
        for (; run > 0; --run) {
            out.push_back({v, 0});
        }
    }
    return out;
}

} // namespace

// Length-limited Huffman code lengths of `count` symbols (0 for those of frequency 0): the
// two-queue Huffman construction, ties to the lower symbol; while a code is longer than
// `limit`, every frequency is halved (rounded up) and the code built again. At least two
// frequencies are non-zero.
void huffmanLengths(const uint32_t* frequencies, int count, int limit, uint8_t* lengths) {
    std::array<uint32_t, 288> weights{};
    std::copy_n(frequencies, count, weights.begin());
    for (;;) {
        std::array<uint16_t, 288> leaves{};
        int used = 0;
        for (int s = 0; s < count; ++s) {
            if (weights[static_cast<size_t>(s)] != 0) {
                leaves[static_cast<size_t>(used++)] = static_cast<uint16_t>(s);
            }
        }
        std::stable_sort(leaves.begin(), leaves.begin() + used,
                         [&](uint16_t a, uint16_t b) { return weights[a] < weights[b]; });
        // Nodes 0..used-1 are the leaves in that order, used.. the internal nodes as made.
        std::array<uint64_t, 576> weight{};
        std::array<uint16_t, 576> parent{};
        for (int k = 0; k < used; ++k) {
            weight[static_cast<size_t>(k)] = weights[leaves[static_cast<size_t>(k)]];
        }
        int nextLeaf = 0, nextInternal = used, made = used;
        auto smallest = [&]() {
            if (nextLeaf < used && (nextInternal == made || weight[static_cast<size_t>(nextLeaf)] <=
                                                                weight[static_cast<size_t>(nextInternal)])) {
                return nextLeaf++;
            }
            return nextInternal++;
        };
        for (int k = 0; k < used - 1; ++k) {
            const int a = smallest(), b = smallest();
            weight[static_cast<size_t>(made)] = weight[static_cast<size_t>(a)] + weight[static_cast<size_t>(b)];
            parent[static_cast<size_t>(a)] = parent[static_cast<size_t>(b)] = static_cast<uint16_t>(made);
            ++made;
        }
        std::array<uint8_t, 576> depth{};
        int longest = 0;
        for (int node = made - 2; node >= 0; --node) { // the root, made last, has depth 0
            depth[static_cast<size_t>(node)] = static_cast<uint8_t>(depth[parent[static_cast<size_t>(node)]] + 1);
            longest = std::max<int>(longest, depth[static_cast<size_t>(node)]);
        }
        if (longest <= limit) {
            std::fill_n(lengths, count, uint8_t{0});
            for (int k = 0; k < used; ++k) {
                lengths[leaves[static_cast<size_t>(k)]] = depth[static_cast<size_t>(k)];
            }
            return;
        }
        for (int s = 0; s < count; ++s) {
            weights[static_cast<size_t>(s)] = (weights[static_cast<size_t>(s)] + 1) / 2;
        }
    }
}

// Canonical codes of `lengths` (RFC 1951 3.2.2), bit-reversed: Deflate sends a code's bits
// from its first (most significant) one, into a stream filled from each byte's lowest bit.
void canonicalCodes(const uint8_t* lengths, int count, uint16_t* codes) {
    std::array<uint16_t, 16> perLength{}, next{};
    for (int s = 0; s < count; ++s) {
        ++perLength[lengths[s]];
    }
    perLength[0] = 0;
    uint16_t code = 0;
    for (int bits = 1; bits < 16; ++bits) {
        code = static_cast<uint16_t>((code + perLength[static_cast<size_t>(bits - 1)]) << 1);
        next[static_cast<size_t>(bits)] = code;
    }
    for (int s = 0; s < count; ++s) {
        const int bits = lengths[s];
        if (bits != 0) {
            const uint16_t c = next[static_cast<size_t>(bits)]++;
            codes[s] = static_cast<uint16_t>(reverseBits(c, bits));
        }
    }
}

void putDynamicHeader(BitWriter& w, bool final, const uint8_t* literalLengths, int literalCount,
                      const uint8_t* distanceLengths, int distanceCount) {
    std::array<uint8_t, 286 + 30> all{};
    std::copy_n(literalLengths, literalCount, all.begin());
    std::copy_n(distanceLengths, distanceCount, all.begin() + literalCount);
    const std::vector<LengthSymbol> runs = runLengths(all.data(), literalCount + distanceCount);
    std::array<uint32_t, 19> frequencies{};
    for (const LengthSymbol& r : runs) {
        ++frequencies[r.symbol];
    }
    if (std::count_if(frequencies.begin(), frequencies.end(), [](uint32_t f) { return f != 0; }) < 2) {
        ++frequencies[frequencies[0] == 0 ? 0 : 1]; // a code needs two symbols
    }
    std::array<uint8_t, 19> runLengthBits{};
    std::array<uint16_t, 19> runCodes{};
    huffmanLengths(frequencies.data(), 19, 7, runLengthBits.data());
    canonicalCodes(runLengthBits.data(), 19, runCodes.data());
    static constexpr std::array<uint8_t, 19> kOrder = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
    int sent = 19;
    while (sent > 4 && runLengthBits[kOrder[static_cast<size_t>(sent - 1)]] == 0) {
        --sent;
    }
    w.put(final ? 1 : 0, 1);
    w.put(2, 2); // dynamic Huffman codes
    w.put(static_cast<uint32_t>(literalCount - 257), 5);
    w.put(static_cast<uint32_t>(distanceCount - 1), 5);
    w.put(static_cast<uint32_t>(sent - 4), 4);
    w.flush();
    for (int k = 0; k < sent; ++k) {
        w.put(runLengthBits[kOrder[static_cast<size_t>(k)]], 3);
        w.flush();
    }
    static constexpr std::array<uint8_t, 3> kExtraBits = {2, 3, 7}; // of symbols 16, 17, 18
    for (const LengthSymbol& r : runs) {
        w.put(runCodes[r.symbol], runLengthBits[r.symbol]);
        if (r.symbol >= 16) {
            w.put(r.extra, kExtraBits[static_cast<size_t>(r.symbol - 16)]);
        }
        w.flush();
    }
}

void ByteCounts::add(const uint8_t* p, size_t n) {
    const size_t quads = n / 4 * 4;
    for (size_t k = 0; k < quads; k += 4) {
        ++tables_[0][p[k]];
        ++tables_[1][p[k + 1]];
        ++tables_[2][p[k + 2]];
        ++tables_[3][p[k + 3]];
    }
    for (size_t k = quads; k < n; ++k) {
        ++tables_[0][p[k]];
    }
}

void ByteCounts::addTo(uint32_t* counts) const {
    for (size_t v = 0; v < 256; ++v) {
        counts[v] += tables_[0][v] + tables_[1][v] + tables_[2][v] + tables_[3][v];
    }
}

void countBytes(std::span<const uint8_t> bytes, uint32_t* counts) {
    ByteCounts tables;
    tables.add(bytes.data(), bytes.size());
    std::fill_n(counts, 256, 0u);
    tables.addTo(counts);
}

void putZlibHeader(uint8_t* out) {
    out[0] = 0x78; // Deflate, 32 KB window
    out[1] = 0x01; // no dictionary; (0x78 * 256 + 0x01) % 31 == 0
}

uint8_t* putAdler32(uint8_t* end, const uint8_t* bytes, size_t size) {
    const uint32_t adler = libdeflate_adler32(1, bytes, size);
    for (int k = 3; k >= 0; --k) {
        *end++ = static_cast<uint8_t>(adler >> (8 * k));
    }
    return end;
}

} // namespace pyramid::deflate
