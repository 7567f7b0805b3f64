#include "formats/zlib_strip.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include <libdeflate.h>

namespace pyramid {

namespace {

struct DecompressorDeleter {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

libdeflate_decompressor* decompressor() {
    thread_local std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> d(libdeflate_alloc_decompressor());
    return d.get();
}

// Whether a stream that holds more than `want` bytes is whole: it inflates, in full, with its
// Adler-32 right.
bool longerStreamIntact(std::span<const uint8_t> stream, size_t want) {
    thread_local std::vector<uint8_t> scratch;
    const size_t most = stream.size() * 1032 + 64; // Deflate's largest expansion, with margin
    for (size_t room = std::max<size_t>(want * 2, 4096);; room = std::min(room * 4, most)) {
        scratch.resize(room);
        size_t inflated = 0; // asked for: libdeflate checks the Adler-32 of a shorter stream only then
        const libdeflate_result r =
            libdeflate_zlib_decompress(decompressor(), stream.data(), stream.size(), scratch.data(), room, &inflated);
        if (r == LIBDEFLATE_SUCCESS) {
            return true;
        }
        if (r != LIBDEFLATE_INSUFFICIENT_SPACE || room == most) {
            return false;
        }
    }
}

} // namespace

StripInflate inflateStrip(std::span<const uint8_t> stream, std::span<uint8_t> out) {
    size_t inflated = 0;
    const libdeflate_result r =
        libdeflate_zlib_decompress(decompressor(), stream.data(), stream.size(), out.data(), out.size(), &inflated);
    if (r == LIBDEFLATE_SUCCESS) {
        return inflated == out.size() ? StripInflate::Inflated : StripInflate::OtherLength;
    }
    if (r == LIBDEFLATE_INSUFFICIENT_SPACE) {
        return longerStreamIntact(stream, out.size()) ? StripInflate::OtherLength : StripInflate::Damaged;
    }
    return StripInflate::Damaged;
}

void undoTiffPredictor(std::span<uint8_t> strip, size_t rowBytes, int channels, int bits, bool swapped, bool horizontal) {
    if (bits == 16 && swapped) {
        for (size_t k = 0; k + 1 < strip.size(); k += 2) {
            std::swap(strip[k], strip[k + 1]);
        }
    }
    if (!horizontal) {
        return;
    }
    const auto c = static_cast<size_t>(channels);
    for (size_t at = 0; at + rowBytes <= strip.size(); at += rowBytes) {
        uint8_t* row = strip.data() + at;
        if (bits == 8) {
            for (size_t k = c; k < rowBytes; ++k) {
                row[k] = static_cast<uint8_t>(row[k] + row[k - c]);
            }
            continue;
        }
        for (size_t k = c; k < rowBytes / 2; ++k) {
            uint16_t a = 0, b = 0;
            std::memcpy(&a, row + 2 * k, 2);
            std::memcpy(&b, row + 2 * (k - c), 2);
            a = static_cast<uint16_t>(a + b);
            std::memcpy(row + 2 * k, &a, 2);
        }
    }
}

} // namespace pyramid
