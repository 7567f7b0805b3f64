// Context-coded residual tiles (doc/format.md, 1.8): libpyramid's own residual tile codec, an
// adaptive range coder whose probabilities depend on each sample's coded neighbours and on its
// place in the upsampling grid. About 0.6 of the bytes of the original tools' Deflate
// tiles on real terrain; read by every libpyramid reader, not by the original runtime.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pyramid {

// The blob's first four bytes; no TIFF starts with them.
inline constexpr uint8_t kContextResidualMagic[4] = {'P', 'Y', 'R', 'C'};

// True when `blob` starts with kContextResidualMagic.
bool isContextResidualBlob(std::span<const uint8_t> blob);

// Codes size x size residuals (rows as the file stores them) in the current version (2). Each
// tile is coded in every mode of its version (the residuals as they are; their differences from
// the median predictor of their left, lower and lower-left neighbours; from version 1 on, their
// differences from a fixed prediction per place in the upsampling grid) and the smallest blob is
// kept; the choice is recorded in it.
std::vector<uint8_t> encodeContextResiduals(std::span<const int16_t> residuals, int size);
// The same in a given version (0, 1 or 2), in its best mode (-1) or the one given (tests and
// comparisons).
std::vector<uint8_t> encodeContextResiduals(std::span<const int16_t> residuals, int size, int version, int mode = -1);

// Decodes a blob of encodeContextResiduals for a tile of `size` samples a side. Throws Error
// with `where` for any blob the encoder cannot have written: another size, an unknown mode or
// version (0 to 3 are read), a stream that ends early or has bytes left over, values beyond int16.
// `parentPlane`: the tile's parent plane (formats/residual_shadow.hpp), size x size, which a
// blob of version 3 is decoded with (and without which it is refused); the other versions do
// not use it.
std::vector<int16_t> decodeContextResiduals(std::span<const uint8_t> blob, int size, const std::string& where,
                                            std::span<const int32_t> parentPlane = {});

// Version 3, the parent modes (doc/format.md 1.8): the residuals coded as version 2 codes them,
// predicted from the tile's parent plane and its coded neighbours' shadows; mode 3, or mode 4
// (steps: where land meets a flat sea behind a cliff), or mode 5 (terraces: each sample's index
// in the list of the tile's heights, where they take few of the integers in their range, as an
// 8-bit map's do). `mode` 3, 4 or 5 codes in that mode; -1 in mode 3, or in mode 4 where the
// tile has such a step, or in mode 5 where it is terraced, whichever is smallest. Written by the
// pass of libpyramid/encode/residual/residual_parent_pass.hpp where it is smaller, never by
// encodeContextResiduals.
std::vector<uint8_t> encodeContextParentMode(std::span<const int16_t> residuals, int size,
                                             std::span<const int32_t> parentPlane, int mode = -1);
// True for a blob of version 3: decoding it needs the tile's parent plane.
bool contextBlobNeedsParent(std::span<const uint8_t> blob);

} // namespace pyramid
