#include "formats/tiff_plain_writer.hpp"

#include <algorithm>
#include <string>

#include "formats/error.hpp"

namespace pyramid {

std::vector<uint8_t> writePlainTiff(std::span<const uint8_t> deflated, const PlainTiffShape& s) {
    if (s.width < 1 || s.width > 65535 || s.height < 1 || s.height > 65535 || s.channels < 1 || s.channels > 4 ||
        (s.bits != 8 && !(s.bits == 16 && s.channels == 1))) {
        fail("", "TIFF tile of " + std::to_string(s.width) + "x" + std::to_string(s.height) + "x" +
                     std::to_string(s.channels) + " samples of " + std::to_string(s.bits) + " bits: not a plain tile");
    }
    struct Field {
        uint16_t tag, type;
        uint32_t count, value; // a SHORT value in the low half; 2 SHORTs as low | high << 16
    };
    const auto channels = static_cast<uint32_t>(s.channels);
    const auto bits = static_cast<uint32_t>(s.bits);
    const bool outOfLine = channels > 2; // BitsPerSample's SHORTs beyond the entry's 4 bytes
    Field fields[14] = {
        {256, 3, 1, static_cast<uint32_t>(s.width)},            // ImageWidth
        {257, 3, 1, static_cast<uint32_t>(s.height)},           // ImageLength
        {258, 3, channels, channels == 2 ? bits | bits << 16 : bits}, // BitsPerSample (offset below)
        {259, 3, 1, 8},                                          // Compression: Adobe Deflate
        {262, 3, 1, s.photometric},                              // PhotometricInterpretation
        {273, 4, 1, 8},                                          // StripOffsets
        {274, 3, 1, 4},                                          // Orientation: bottom-left
        {277, 3, 1, channels},                                   // SamplesPerPixel
        {278, 3, 1, static_cast<uint32_t>(s.height)},           // RowsPerStrip
        {279, 4, 1, static_cast<uint32_t>(deflated.size())},    // StripByteCounts
        {284, 3, 1, 1},                                          // PlanarConfiguration: contiguous
    };
    int count = 11;
    if (s.predictor) {
        fields[count++] = {317, 3, 1, 2}; // Predictor: horizontal
    }
    if (s.extraSample) {
        fields[count++] = {338, 3, 1, 0}; // ExtraSamples: unspecified
    }
    if (s.bits == 16) {
        fields[count++] = {339, 3, 1, 2}; // SampleFormat: signed integer
    }
    const size_t directory = (8 + deflated.size() + 1) & ~size_t{1};
    const size_t values = directory + 2 + 12 * static_cast<size_t>(count) + 4;
    if (outOfLine) {
        fields[2].value = static_cast<uint32_t>(values);
    }
    std::vector<uint8_t> out(values + (outOfLine ? 2 * channels : 0), 0);
    const auto put16 = [&](size_t at, uint32_t v) {
        out[at] = static_cast<uint8_t>(v);
        out[at + 1] = static_cast<uint8_t>(v >> 8);
    };
    const auto put32 = [&](size_t at, uint32_t v) {
        put16(at, v & 0xffffu);
        put16(at + 2, v >> 16);
    };
    out[0] = 'I';
    out[1] = 'I';
    put16(2, 42);
    put32(4, static_cast<uint32_t>(directory));
    std::copy(deflated.begin(), deflated.end(), out.begin() + 8);
    put16(directory, static_cast<uint32_t>(count));
    for (int k = 0; k < count; ++k) {
        const Field& f = fields[k];
        const size_t at = directory + 2 + 12 * static_cast<size_t>(k);
        put16(at, f.tag);
        put16(at + 2, f.type);
        put32(at + 4, f.count);
        put32(at + 8, f.value);
    }
    for (uint32_t c = 0; outOfLine && c < channels; ++c) {
        put16(values + 2 * c, bits);
    }
    return out; // the next directory's offset: 0
}

} // namespace pyramid
