#include "formats/residual_tiff_plain.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "formats/error.hpp"
#include "formats/tiff_plain_writer.hpp"
#include "formats/tiff_strip_bytes.hpp"
#include "formats/zlib_strip.hpp"

namespace pyramid {

namespace {

// One directory entry's values, as unsigned integers (SHORT or LONG only).
struct Entry {
    uint16_t type = 0;
    uint32_t count = 0;
    size_t at = 0; // byte offset of the first value in the blob
};

class Directory {
public:
    Directory(std::span<const uint8_t> blob, bool big) : blob_(blob), big_(big) {}

    uint16_t u16(size_t at) const {
        return big_ ? static_cast<uint16_t>(blob_[at] << 8 | blob_[at + 1])
                    : static_cast<uint16_t>(blob_[at] | blob_[at + 1] << 8);
    }
    uint32_t u32(size_t at) const {
        return big_ ? (uint32_t{u16(at)} << 16 | u16(at + 2)) : (uint32_t{u16(at + 2)} << 16 | u16(at));
    }
    // Value i of an entry (the caller checked i < count and the entry's bounds).
    uint32_t value(const Entry& e, uint32_t i) const {
        return e.type == 3 ? u16(e.at + 2 * size_t{i}) : u32(e.at + 4 * size_t{i});
    }
    // Reads the entry at `at`; false for a type other than SHORT or LONG or values past the end.
    bool entry(size_t at, Entry& e) const {
        e.type = u16(at + 2);
        e.count = u32(at + 4);
        if ((e.type != 3 && e.type != 4) || e.count == 0) {
            return false;
        }
        const uint64_t bytes = uint64_t{e.count} * (e.type == 3 ? 2u : 4u);
        e.at = bytes <= 4 ? at + 8 : u32(at + 8);
        return e.at + bytes <= blob_.size();
    }
    // The single value of a one-value entry, or all equal values of a per-sample one.
    bool same(const Entry& e, uint32_t count, uint32_t& out) const {
        if (e.count != count) {
            return false;
        }
        out = value(e, 0);
        for (uint32_t i = 1; i < count; ++i) {
            if (value(e, i) != out) {
                return false;
            }
        }
        return true;
    }

private:
    std::span<const uint8_t> blob_;
    bool big_;
};

} // namespace

PlainDecode decodePlainResidualTiff(std::span<const uint8_t> blob, int size, std::span<int16_t> out) {
    if (blob.size() < 8 || size < 1 || out.size() != static_cast<size_t>(size) * static_cast<size_t>(size)) {
        return PlainDecode::Declined;
    }
    const bool big = blob[0] == 'M' && blob[1] == 'M';
    if (!big && !(blob[0] == 'I' && blob[1] == 'I')) {
        return PlainDecode::Declined;
    }
    const Directory d(blob, big);
    if (d.u16(2) != 42) {
        return PlainDecode::Declined;
    }
    const size_t ifd = d.u32(4);
    if (ifd < 8 || ifd + 2 > blob.size()) {
        return PlainDecode::Declined;
    }
    const uint16_t entries = d.u16(ifd);
    if (ifd + 2 + size_t{entries} * 12 + 4 > blob.size() || d.u32(ifd + 2 + size_t{entries} * 12) != 0) {
        return PlainDecode::Declined; // a second directory: another image
    }
    Entry width, length, bits, offsets, counts, rows, compression, samples, planar, predictor, format;
    bool has[12] = {};
    enum { W, L, B, O, C, R, Z, S, P, D, F };
    int lastTag = -1;
    for (uint16_t k = 0; k < entries; ++k) {
        const size_t at = ifd + 2 + size_t{k} * 12;
        const uint16_t tag = d.u16(at);
        if (static_cast<int>(tag) <= lastTag) {
            return PlainDecode::Declined; // out of order or repeated: libtiff decides
        }
        lastTag = tag;
        Entry e;
        if (!d.entry(at, e)) {
            return PlainDecode::Declined;
        }
        uint32_t v = 0;
        int which = -1;
        switch (tag) {
        // Tags that change nothing in the strips' bytes, with the values libtiff accepts without
        // a word: NewSubfileType, PhotometricInterpretation (min-is-white or black) and
        // Orientation (libtiff's strip reads ignore it).
        case 254: continue;
        case 262: if (!d.same(e, 1, v) || v > 1) return PlainDecode::Declined; continue;
        case 274: if (!d.same(e, 1, v) || v < 1 || v > 8) return PlainDecode::Declined; continue;
        case 256: width = e; which = W; break;
        case 257: length = e; which = L; break;
        case 258: bits = e; which = B; break;
        case 259: compression = e; which = Z; break;
        case 273: offsets = e; which = O; break;
        case 277: samples = e; which = S; break;
        case 278: rows = e; which = R; break;
        case 279: counts = e; which = C; break;
        case 284: planar = e; which = P; break;
        case 317: predictor = e; which = D; break;
        case 339: format = e; which = F; break;
        default: return PlainDecode::Declined;
        }
        has[which] = true;
    }
    if (!has[W] || !has[L] || !has[B] || !has[O] || !has[C]) {
        return PlainDecode::Declined;
    }
    uint32_t w = 0, h = 0, spp = 1, bps = 0, codec = 1, rps = 0xffffffffu, config = 1, pred = 1, sampleFormat = 1;
    if (!d.same(width, 1, w) || !d.same(length, 1, h) || (has[S] && !d.same(samples, 1, spp)) ||
        (has[Z] && !d.same(compression, 1, codec)) || (has[R] && !d.same(rows, 1, rps)) ||
        (has[P] && !d.same(planar, 1, config)) || (has[D] && !d.same(predictor, 1, pred))) {
        return PlainDecode::Declined;
    }
    if (w != static_cast<uint32_t>(size) || h != static_cast<uint32_t>(size) || !d.same(bits, spp, bps) ||
        (has[F] && !d.same(format, spp, sampleFormat))) {
        return PlainDecode::Declined;
    }
    const bool twoBytes = spp == 2 && bps == 8, oneShort = spp == 1 && bps == 16;
    if ((!twoBytes && !oneShort) || config != 1 || (pred != 1 && pred != 2) || (sampleFormat != 1 && sampleFormat != 2) ||
        (codec != 1 && codec != 8 && codec != 32946)) {
        return PlainDecode::Declined;
    }
    if (rps == 0 || (codec == 1 && has[D])) {
        return PlainDecode::Declined; // libtiff's own reading of these: no rows, or a predictor it ignores
    }
    rps = std::min(rps, h);
    const uint32_t strips = (h + rps - 1) / rps;
    if (offsets.count != strips || counts.count != strips) {
        return PlainDecode::Declined;
    }
    const size_t rowBytes = static_cast<size_t>(size) * 2;
    auto* bytes = reinterpret_cast<uint8_t*>(out.data());
    for (uint32_t s = 0; s < strips; ++s) {
        const uint64_t offset = d.value(offsets, s), stored = d.value(counts, s);
        const size_t want = static_cast<size_t>(std::min(rps, h - s * rps)) * rowBytes;
        if (offset == 0 || offset + stored > blob.size()) {
            return PlainDecode::Declined;
        }
        uint8_t* strip = bytes + static_cast<size_t>(s) * rps * rowBytes;
        if (codec == 1) {
            if (stored != want) {
                return PlainDecode::Declined;
            }
            std::memcpy(strip, blob.data() + offset, want);
        } else {
            switch (inflateStrip(blob.subspan(static_cast<size_t>(offset), static_cast<size_t>(stored)),
                                 std::span<uint8_t>(strip, want))) {
            case StripInflate::Inflated:
                break;
            case StripInflate::Damaged:
                return PlainDecode::Damaged;
            case StripInflate::OtherLength:
                return PlainDecode::Declined; // libtiff's reading decides
            }
        }
    }
    // The samples as the file's bytes give them, then the predictor's sums along each row
    // (libtiff's order: byte swap, then accumulate), by the TIFF tile reader's own function.
    const std::span<uint8_t> all(bytes, static_cast<size_t>(h) * rowBytes);
    if (oneShort) {
        undoTiffPredictor(all, rowBytes, 1, 16, big != (std::endian::native == std::endian::big), pred == 2);
        return PlainDecode::Decoded;
    }
    undoTiffPredictor(all, rowBytes, 2, 8, false, pred == 2);
    // Sample 0 is the low byte, sample 1 the high byte, whatever the file's byte order: on a
    // big-endian machine each pair swapped into an int16 (a no-op here otherwise).
    undoTiffPredictor(all, rowBytes, 1, 16, std::endian::native == std::endian::big, false);
    return PlainDecode::Decoded;
}

std::vector<uint8_t> encodeResidualTiff(std::span<const int16_t> residuals, int size, int deflateLevel,
                                        ResidualTiffLayout layout, bool horizontalPredictor) {
    if (size < 1 || size > 65535 || residuals.size() != static_cast<size_t>(size) * static_cast<size_t>(size)) {
        fail("", "residual tile: buffer does not match " + std::to_string(size) + "x" + std::to_string(size));
    }
    const bool oneShort = layout == ResidualTiffLayout::OneShort;
    // The strip, little-endian on every machine: two 8-bit samples per pixel (the low and the
    // high byte of the int16, with no ExtraSamples tag, exactly as the original tools write
    // them), or one 16-bit sample; the predictor's differences are the samples' (modulo 2^8 or
    // 2^16), along each row. Written without setting libtiff up (writePlainTiff).
    std::vector<uint8_t> bytes(residuals.size() * 2);
    const auto n = static_cast<size_t>(size);
    for (size_t k = 0; k < residuals.size(); ++k) {
        auto v = static_cast<uint16_t>(residuals[k]);
        if (oneShort && horizontalPredictor && k % n != 0) {
            v = static_cast<uint16_t>(v - static_cast<uint16_t>(residuals[k - 1]));
        }
        bytes[2 * k] = static_cast<uint8_t>(v & 0xffu);
        bytes[2 * k + 1] = static_cast<uint8_t>(v >> 8);
    }
    std::span<const uint8_t> strip(bytes);
    if (!oneShort && horizontalPredictor) {
        strip = horizontalDifferences(bytes.data(), bytes.size(), size, 2);
    }
    PlainTiffShape shape;
    shape.width = shape.height = size;
    shape.channels = oneShort ? 1 : 2;
    shape.bits = oneShort ? 16 : 8;
    shape.predictor = horizontalPredictor;
    return writePlainTiff(deflateStrip(strip, deflateLevel, 0), shape);
}

} // namespace pyramid
