// The pixel blocks of an ERDAS Imagine layer (HFA's Edms_State): each block bw x bh pixels, row
// by row, stored as is (little-endian; pixels of 1, 2 or 4 bits packed from each byte's low
// bits) or run-length compressed ("ESRI GRID compression"): the minimum (32 bits), the count of
// runs (-1: none, every pixel's value packed in turn), the values' offset and their bits (0, 1, 2,
// 4, 8, 16 or 32; 16 and 32 big-endian), then the runs' lengths (1 to 4 bytes each, the first
// byte's top two bits giving the extra bytes) and one value per run. A value is the minimum plus
// its bits, in 32 bits, of which the pixel type keeps its own (two's complement for the signed
// types: GDAL writes an int16 block as a minimum of 0 and each value's 16 bits). A block whose
// runs do not decode to exactly its pixels, within its bytes, is an error.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

// Where a layer's block lies: its bytes in the file that holds them (offset and size), whether the
// file wrote it (else it is nodata) and whether it is run-length compressed.
struct HfaBlockPlace {
    uint64_t offset = 0;
    uint32_t size = 0;
    bool valid = false, compressed = false;
};

// HFA's pixel types, in its order.
enum class HfaPixel { U1, U2, U4, U8, S8, U16, S16, U32, S32, F32, F64, C64, C128 };

// The sample type a layer of pixel type `p` is read as: UInt8 (u1 to u8), Int16 (s8, s16),
// UInt16, Float32 (u32, s32, f32, f64: each value to the nearest float); Other for complex.
SampleType hfaSampleType(HfaPixel p);
size_t hfaStoredBytes(HfaPixel p, size_t pixels); // an uncompressed block's bytes

// Decodes one block's `stored` bytes into `pixels` samples of hfaSampleType(p) at `out`. Throws
// Error("PATH: ...") naming the block for a damaged or unconvertible one.
void decodeHfaBlock(HfaPixel p, bool compressed, const std::vector<uint8_t>& stored, size_t pixels, uint8_t* out,
                    const std::string& path, const std::string& block);

// `nodata` (a layer's non-initialised value) as a sample of hfaSampleType(p), for blocks the
// file never wrote; zero without one, or where it is not such a sample.
void fillHfaBlock(HfaPixel p, const std::optional<double>& nodata, size_t pixels, uint8_t* out);

} // namespace pyramid
