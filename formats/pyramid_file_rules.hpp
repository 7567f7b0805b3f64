// What the ortho and residual files share besides the bytes of their headers
// (formats/header_bytes.hpp): the limits a header may declare, how messages name a tile, and
// the writers' check that every tile was written.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "formats/error.hpp"
#include "formats/tile_table.hpp"

namespace pyramid {

// The largest level (maxLevel, rootLevel) and tile size (without borders) either file's header
// may declare; the encoders take no larger.
constexpr int kMaxLevel = 30;
constexpr int kMaxTileSize = 8192;

// Whether (level, tx, ty) names a tile of a quadtree of levels 0 to kMaxLevel (2^level tiles a
// side): what the runtime's producers and the C API take before looking for it in a file.
constexpr bool isQuadtreeTile(int level, int tx, int ty) {
    return level >= 0 && level <= kMaxLevel && tx >= 0 && ty >= 0 && tx < (1 << level) && ty < (1 << level);
}

} // namespace pyramid

namespace pyramid::detail {

// Fails unless a file of `fileBytes` holds a header of `headerBytes`: "PATH: empty file, not a
// pyramid" or "PATH: file of N bytes, shorter than a pyramid header (H bytes)".
void requireHeader(const std::string& path, uint64_t fileBytes, size_t headerBytes);

// "PATH: tile (level,tx,ty)".
std::string tileName(const std::string& path, int level, int tx, int ty);
// Throws MissingTileError("PATH: no tile (level,tx,ty) in this file").
[[noreturn]] void throwMissingTile(const std::string& path, int level, int tx, int ty);

// Fails with "PATH: tile (level,tx,ty) was never written" for the first tile, level by level and
// row by row, that `table` has not had written (the table alone would name it by its index).
// `Header` gives maxLevel, tilesPerSide(level) and tileIndex(level, tx, ty).
template <class Header>
void requireEveryTileWritten(const Header& header, const TileTableWriter& table, const std::string& path) {
    for (int level = 0; level <= header.maxLevel; ++level) {
        const int side = static_cast<int>(header.tilesPerSide(level));
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                if (!table.written(header.tileIndex(level, tx, ty))) {
                    fail(path, "tile " + tileCoordinates(level, tx, ty) + " was never written");
                }
            }
        }
    }
}

} // namespace pyramid::detail
