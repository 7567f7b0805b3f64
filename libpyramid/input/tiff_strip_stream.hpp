// A striped TIFF (one band, or several interleaved) decoded row by row, north to south, in
// memory bounded by a few rows and a read buffer, however large its strips: for files stored as a few huge strips (one
// strip for the whole image is common), whose strips the block cache cannot hold. Deflate and
// uncompressed strips are read in chunks and inflated as a stream (zlib); strips of other
// compressions, and interleaved float32 bands with the floating-point predictor, go through
// libtiff's scanline reading, which holds one compressed strip.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

typedef struct tiff TIFF;

namespace pyramid {

// Calls `row(y, bytes)` for y = 0, 1, ... height - 1 with the row's `width` x channels
// samples (interleaved) as decoded: the file's own sample type (BitsPerSample, SampleFormat),
// in the host's byte order, predictors undone (tiff_samples.hpp converts them). `tif` is an
// open handle of `path` (named in errors), striped, of 8/16/32-bit integers or float32. Throws
// Error on a damaged strip.
void streamTiffRows(TIFF* tif, const std::string& path, const std::function<void(uint32_t, const uint8_t*)>& row);

} // namespace pyramid
