#include "formats/tiff_strip_bytes.hpp"

#include <libdeflate.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "formats/deflate_literals.hpp"
#include "formats/deflate_runs.hpp"
#include "formats/error.hpp"

namespace pyramid {

namespace {

struct CompressorDeleter {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

} // namespace

// A zlib stream of `bytes` at libdeflate level `level` (1 to 12, 10 to 12 the slowest and
// smallest), compressed in one call as libtiff's Deflate codec does with a whole strip, but
// without allocating and initialising a compressor for every tile: one per thread and level.
// The stream is left in a buffer of the thread's, valid until its next call (libtiff copies
// it into the tile), so that no tile allocates and clears a buffer of the compression bound.
// The levels a Deflate tile may take: libdeflate's 1 to 12. Every Deflate tile's strip passes
// here (zlibCompress or deflateStrip).
static void requireDeflateLevel(int level) {
    if (level < 1 || level > 12) {
        fail("", "Deflate level " + std::to_string(level) + " is not 1..12");
    }
}

std::span<const uint8_t> zlibCompress(std::span<const uint8_t> bytes, int level) {
    requireDeflateLevel(level);
    thread_local std::unique_ptr<libdeflate_compressor, CompressorDeleter> compressors[13];
    thread_local std::vector<uint8_t> out;
    auto& compressor = compressors[level];
    if (!compressor) {
        compressor.reset(libdeflate_alloc_compressor(level));
        if (!compressor) {
            fail("", "out of memory for a Deflate compressor");
        }
    }
    const size_t bound = libdeflate_zlib_compress_bound(compressor.get(), bytes.size());
    if (out.size() < bound) {
        out.resize(bound);
    }
    const size_t size = libdeflate_zlib_compress(compressor.get(), bytes.data(), bytes.size(), out.data(), bound);
    if (size == 0) {
        fail("", "cannot deflate a tile");
    }
    return {out.data(), size};
}

namespace {

constexpr size_t kSample = 4096;
// Below this, libdeflate's stream of the sample is mostly its header and a few long matches (a
// dark, flat or blank strip), and libdeflate often codes it with the fixed codes, which need no
// header. The runs coder always writes a dynamic block whose header (code lengths) takes up to
// about kHeaderAllowance bytes: the strip pays that once, not once per 4 KB sample, so the
// comparison allows for it there.
constexpr size_t kSmallSample = 512;
constexpr size_t kHeaderAllowance = 48;

// How a strip of image bytes is best coded, judged on a sample of them (4 KB from the middle; a
// larger one decides a little better, but the sample's libdeflate run then costs more than the
// faster coders save on imagery that repeats: bench/ortho_bench.md, 2026-12-03):
//   - literals only (deflate_literals.hpp), where its literal code takes at least 3 bits a byte
//     (below that, runs and repeats are everywhere) and libdeflate's stream of the sample is no
//     smaller than that code: sensor noise after the predictor, grainy residuals;
//   - literals and runs (deflate_runs.hpp), where that coder's stream of the sample is at most
//     3 % larger than libdeflate's (with kHeaderAllowance on a small one): most natural imagery,
//     whose matches are mostly runs, and dark or flat strips;
//   - libdeflate otherwise: texture that repeats farther away, which matches well.
// Both faster coders take about half of libdeflate level 1's time or less.
enum class StripCoder { Libdeflate, Literals, Runs };

StripCoder chooseCoder(std::span<const uint8_t> bytes, int level, int pixelBytes) {
    const std::span<const uint8_t> sample = bytes.subspan((bytes.size() - kSample) / 2, kSample);
    const size_t deflated = zlibCompress(sample, level).size();
    const LiteralCost cost = literalCost(sample);
    if (cost.bits >= 3 * kSample && deflated * 8 >= cost.bits) {
        return StripCoder::Literals;
    }
    thread_local std::vector<uint8_t> out;
    const size_t allowance = deflated < kSmallSample ? kHeaderAllowance : 0;
    if (deflateRuns(sample, pixelBytes, out) * 100 <= (deflated * 103) + allowance * 100) {
        return StripCoder::Runs;
    }
    return StripCoder::Libdeflate;
}

} // namespace

// The zlib stream of a Deflate strip. With `pixelBytes` (1 to 4: 8-bit image tiles of that
// many channels; 0: others), at the fast levels (1 and 2), strips of 8 KB and more go to the
// coder chooseCoder finds for them; the rest to libdeflate.
std::span<const uint8_t> deflateStrip(std::span<const uint8_t> bytes, int level, int pixelBytes) {
    requireDeflateLevel(level);
    if (pixelBytes != 0 && level <= 2 && bytes.size() >= 2 * kSample) {
        thread_local std::vector<uint8_t> out;
        size_t size = 0; // the coders resize `out`: its data() is taken after them
        switch (chooseCoder(bytes, level, pixelBytes)) {
        case StripCoder::Literals:
            size = deflateLiterals(bytes, literalCost(bytes), out);
            return {out.data(), size};
        case StripCoder::Runs:
            size = deflateRuns(bytes, pixelBytes, out);
            return {out.data(), size};
        case StripCoder::Libdeflate:
            break;
        }
    }
    return zlibCompress(bytes, level);
}

// The strip libtiff's horizontal predictor would store for 8-bit samples: each sample minus the
// same channel of the pixel to its left, modulo 256, the first pixel of each row as it is. In
// a buffer of the thread's, valid until its next call.
std::span<const uint8_t> horizontalDifferences(const uint8_t* pixels, size_t bytes, int width, int channels) {
    thread_local std::vector<uint8_t> out;
    if (out.size() < bytes) {
        out.resize(bytes);
    }
    const size_t row = static_cast<size_t>(width) * static_cast<size_t>(channels);
    const auto c = static_cast<size_t>(channels);
    for (size_t y = 0; y < bytes / row; ++y) {
        const uint8_t* in = pixels + y * row;
        uint8_t* o = out.data() + y * row;
        std::copy_n(in, c, o);
        for (size_t k = c; k < row; ++k) {
            o[k] = static_cast<uint8_t>(in[k] - in[k - c]);
        }
    }
    return {out.data(), bytes};
}

} // namespace pyramid
