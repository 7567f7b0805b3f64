// The pieces of a Deflate stream's dynamic-Huffman blocks (RFC 1951 3.2.7) that the stream
// writers here share (deflate_literals.hpp, deflate_runs.hpp): length-limited Huffman code
// lengths, canonical codes, a bit writer, a block's header, and the word loader of the run finders.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

namespace pyramid::deflate {

// Length-limited Huffman code lengths of `count` (at most 288) symbols: 0 for those of
// frequency 0. At least two frequencies are non-zero.
void huffmanLengths(const uint32_t* frequencies, int count, int limit, uint8_t* lengths);

// Counts of byte values over any number of spans: four tables, so that runs of one value do
// not wait on one counter.
class ByteCounts {
public:
    void add(const uint8_t* p, size_t n);
    // Adds the counts of each value to counts[0..255].
    void addTo(uint32_t* counts) const;

private:
    uint32_t tables_[4][256] = {};
};

// Counts the bytes of each value into counts[0..255].
void countBytes(std::span<const uint8_t> bytes, uint32_t* counts);

// Canonical codes of `lengths` (RFC 1951 3.2.2), bit-reversed, as Deflate sends them.
void canonicalCodes(const uint8_t* lengths, int count, uint16_t* codes);

// The eight bytes at p as one word, the first in its lowest bits (the order in which the
// writers compare and emit bytes).
inline uint64_t load64(const uint8_t* p) {
    if constexpr (std::endian::native == std::endian::little) {
        uint64_t v;
        std::memcpy(&v, p, 8);
        return v;
    }
    uint64_t v = 0;
    for (int k = 7; k >= 0; --k) {
        v = v << 8 | p[k];
    }
    return v;
}

// Bits into bytes, lowest bit first. Up to 56 bits may be pending between flushes; the output
// keeps 8 bytes of slack past the last one written.
class BitWriter {
public:
    explicit BitWriter(uint8_t* out) : out_(out) {}
    void put(uint32_t bits, int count) {
        buffer_ |= static_cast<uint64_t>(bits) << pending_;
        pending_ += count;
    }
    void flush() {
        if constexpr (std::endian::native == std::endian::little) {
            std::memcpy(out_, &buffer_, 8);
        } else {
            for (int k = 0; k < 8; ++k) {
                out_[k] = static_cast<uint8_t>(buffer_ >> (8 * k));
            }
        }
        out_ += pending_ >> 3;
        buffer_ = (pending_ & ~7) == 64 ? 0 : buffer_ >> (pending_ & ~7);
        pending_ &= 7;
    }
    // Flushes and pads the last byte with zeros; returns the end of the bytes written.
    uint8_t* finish() {
        flush();
        if (pending_ != 0) {
            *out_++ = static_cast<uint8_t>(buffer_);
        }
        pending_ = 0;
        buffer_ = 0;
        return out_;
    }

private:
    uint8_t* out_;
    uint64_t buffer_ = 0;
    int pending_ = 0;
};

// The literal codes of bytes p[from, to), `packed` holding each byte value's code | length << 16
// and `longest` the longest of those lengths, then a flush. Between flushes (at most 7 bits
// pending after one) go as many codes as fit the writer's 64 bits: four of at most 14 bits,
// else three of at most 15. The bits are the same whatever the grouping.
inline void putLiterals(BitWriter& w, const uint32_t* packed, int longest, const uint8_t* p, size_t from, size_t to) {
    const auto put = [&](uint32_t c) { w.put(c & 0xffffu, static_cast<int>(c >> 16)); };
    if (longest <= 14) {
        for (; from + 4 <= to; from += 4) {
            const uint32_t a = packed[p[from]], b = packed[p[from + 1]], c = packed[p[from + 2]], d = packed[p[from + 3]];
            put(a);
            put(b);
            put(c);
            put(d);
            w.flush();
        }
    }
    for (; from + 3 <= to; from += 3) {
        const uint32_t a = packed[p[from]], b = packed[p[from + 1]], c = packed[p[from + 2]];
        put(a);
        put(b);
        put(c);
        w.flush();
    }
    for (; from < to; ++from) { // at most two: 30 bits
        put(packed[p[from]]);
    }
    w.flush();
}

// The most bytes putDynamicHeader writes.
constexpr size_t kDynamicHeaderBytes = 320;

// Writes a dynamic block's first bits: BFINAL (`final`), BTYPE 2, and the code lengths of its
// `literalCount` literal/length symbols (257 to 286) and `distanceCount` distance symbols (1 to
// 30), run-length coded.
void putDynamicHeader(BitWriter& w, bool final, const uint8_t* literalLengths, int literalCount,
                      const uint8_t* distanceLengths, int distanceCount);

// Writes the zlib header of a stream with a 32 KB window (2 bytes), and after `end`, the
// Adler-32 of `bytes`; returns the end of the stream.
void putZlibHeader(uint8_t* out);
uint8_t* putAdler32(uint8_t* end, const uint8_t* bytes, size_t size);

} // namespace pyramid::deflate
