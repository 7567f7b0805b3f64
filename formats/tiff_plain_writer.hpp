// One-strip Deflate TIFF tiles written without libtiff: the bytes libtiff 4 writes for the same
// tags on a little-endian machine, on every machine. Opening a libtiff handle sets up its whole
// field table (sorted at every open) and builds the directory: about 20 us a tile, 3 % of the
// DEM encoder's CPU and 2 % of the ortho encoder's. tests/tiff_plain_writer_test.cpp has libtiff
// write the same tags around the same strip and compares the files.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace pyramid {

// What a tile's directory says besides its strip.
struct PlainTiffShape {
    int width = 1, height = 1; // 1 to 65535 (SHORT values, as libtiff writes them)
    int channels = 1;          // SamplesPerPixel, 1 to 4
    int bits = 8;              // BitsPerSample of every channel: 8, or 16 with one channel, signed
    uint16_t photometric = 1;  // 1: min-is-black, 2: RGB
    bool extraSample = false;  // ExtraSamples = 0 (unspecified): the last channel is extra
    bool predictor = false;    // Predictor = 2 (horizontal)
};

// The TIFF of one image in one Deflate strip, `deflated` (the strip's zlib stream): "II", the
// strip at byte 8, then the directory at the next even offset, its tags in order (ImageWidth,
// ImageLength, BitsPerSample, Compression = 8, PhotometricInterpretation, StripOffsets,
// Orientation = 4 (bottom-left), SamplesPerPixel, RowsPerStrip = height, StripByteCounts,
// PlanarConfiguration = 1, Predictor, ExtraSamples, SampleFormat = 2 for 16 bits), then
// BitsPerSample's values when they do not fit in their entry (3 or 4 channels).
std::vector<uint8_t> writePlainTiff(std::span<const uint8_t> deflated, const PlainTiffShape& shape);

} // namespace pyramid
