// What TIFF readers do to one row of decoded bytes, shared by the block reader (a strip or
// tile at a time) and the strip stream (a row at a time): undoing the predictors, and turning
// samples into float32 or 16-bit values by value (integers are never normalised).
#pragma once
#include <cstddef>
#include <cstdint>

namespace pyramid {

// Undoes TIFF's floating-point predictor (Predictor = 3, TIFF Technical Note 3) on one row of
// `count` float32 samples of one channel: the row's bytes are differences from the byte before
// them (a running sum modulo 256 restores them), laid out as planes of the samples' bytes from
// the most significant one down. The samples come out in `out` (4 x count bytes) as float32 in
// the host's byte order, whatever the file's. `bytes` is used as scratch.
void undoFloatPredictor(uint8_t* bytes, size_t count, uint8_t* out);

// Undoes the horizontal predictor (Predictor = 2) on one row of `count` pixels of `channels`
// interleaved samples of `bits` bits, already in the host's byte order: each sample is stored
// as its difference from the same channel of the pixel to its left, modulo 2^bits.
void undoHorizontalPredictor(uint8_t* row, size_t count, int bits, int channels = 1);

// Reverses the byte order of `count` samples of `bits` bits in place (a file of the other
// byte order).
void swapSampleBytes(uint8_t* row, size_t count, int bits);

// `count` samples of `bits` bits (8, 16 or 32), signed or unsigned integers, or float32 or
// float64 (`sampleFormat` as TIFF's SampleFormat: 1 unsigned, 2 signed, 3 IEEE float), host
// order, to float32 by value (float64 to the nearest float32).
void samplesToFloat(const uint8_t* raw, size_t count, int bits, int sampleFormat, float* out);

// `count` unsigned samples of 8 or 16 bits, host order, as 16-bit values (8-bit ones widened
// exactly, 0..255).
void samplesToUInt16(const uint8_t* raw, size_t count, int bits, uint16_t* out);

} // namespace pyramid
