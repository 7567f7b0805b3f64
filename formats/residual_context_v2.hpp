// Version 2 of the context-coded residual tile (doc/format.md, 1.8): each value's magnitude from
// the sample's activity table, its sign as a binary decision in the context of its neighbours'
// signs and its prediction's, and the top bits of large magnitudes as binary decisions too; and
// version 3, the same coding predicted from the tile's parent plane (modes 3 and 4), or of each
// sample's index in the list of the tile's heights (mode 5).
// Internal to formats/residual_context*.cpp; formats/residual_context.hpp is the interface.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pyramid::context_coding {

// The blob of size x size residuals in version 2 and `mode` (0, 1 or 2), header included.
std::vector<uint8_t> encodeVersion2(std::span<const int16_t> residuals, int size, uint8_t mode);
// The residuals of a version-2 blob whose header has been checked; throws Error with `where`.
std::vector<int16_t> decodeVersion2(std::span<const uint8_t> blob, int size, uint8_t mode, const std::string& where);

// Version 3, the parent modes: version 2's coding of each value, predicted from the tile's parent
// plane (`parent`, size x size: formats/residual_shadow.hpp) and the shadows of the samples coded
// before it; `mode` 3, 4 or 5, or -1: mode 3, or mode 4 (steps) where the tile has a shore's step,
// or mode 5 (terraces) where it is terraced, whichever is smallest. Header included; the
// decoder's header has been checked (mode 3, 4 or 5).
std::vector<uint8_t> encodeParentMode(std::span<const int16_t> residuals, int size, std::span<const int32_t> parent,
                                      int mode);
std::vector<int16_t> decodeParentMode(std::span<const uint8_t> blob, int size, std::span<const int32_t> parent,
                                      const std::string& where);

// Version 3's mode 5, the terrace mode: the tile's distinct shadows (its terraces, at most
// kMaxTerraces) and each sample's terrace index. Whether a tile is terraced: its shadows take at
// most half of the integers of their range, and at most kMaxTerraces values (the encoder tries
// mode 5 on those tiles only).
inline constexpr size_t kMaxTerraces = 65536;
bool isTerraced(std::span<const int16_t> residuals, std::span<const int32_t> parent);
std::vector<uint8_t> encodeTerraceMode(std::span<const int16_t> residuals, int size, std::span<const int32_t> parent);
std::vector<int16_t> decodeTerraceMode(std::span<const uint8_t> blob, int size, std::span<const int32_t> parent,
                                       const std::string& where);

} // namespace pyramid::context_coding
