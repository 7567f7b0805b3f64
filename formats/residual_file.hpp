// Residual (DEM) pyramid files: the on-disk layout of doc/format.md, section "Residual files".
//
//   header   int32 minLevel, maxLevel, tileSize, rootLevel, rootTx, rootTy; float32 scale
//   offsets  uint32[2 * tileCount], relative to the end of this array
//   tiles    one TIFF per tile (2 x 8-bit samples = little-endian int16 residuals)
//
// Levels, tx and ty here are relative to the file's root tile (rootLevel, rootTx, rootTy).
// Tile arrays are row-major with row 0 = the tile's bottom row (j = 0), as stored.
#pragma once
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "formats/byte_source.hpp"
#include "formats/tile_table.hpp"

namespace pyramid {

struct ResidualHeader {
    int32_t minLevel = 0;
    int32_t maxLevel = 0;   // absolute within the file (counted from its root), not minLevel-relative
    int32_t tileSize = 0;   // samples per side without the 2-sample borders and the extra sample
    int32_t rootLevel = 0;
    int32_t rootTx = 0;
    int32_t rootTy = 0;
    float scale = 1.0f;     // height units per residual unit

    static constexpr size_t kBytes = 28;

    int64_t tileCount() const;
    // Index into the offset table; levels below minLevel hold a single tile.
    int64_t tileIndex(int level, int tx, int ty) const;
    // Samples per side of a stored tile at `level`, borders included: (tileSize >> (minLevel-level)) + 5
    // below minLevel, tileSize + 5 from minLevel on.
    int tileSamples(int level) const;
    // Tiles per side at `level` (1 below minLevel).
    int64_t tilesPerSide(int level) const;
    bool contains(int level, int tx, int ty) const;
    // Throws Error (prefixed with `where`) unless every field is sane: non-negative levels,
    // minLevel <= maxLevel <= 30, 1 <= tileSize <= 8192 and divisible by 2^minLevel,
    // root coordinates inside their level, minLevel == 0 when rootLevel > 0, finite scale > 0.
    void validate(const std::string& where) const;
};

// The header as stored: 28 little-endian bytes (not validated).
std::vector<uint8_t> packResidualHeader(const ResidualHeader& h);

// The quadrant offsets of doc/format.md 1.3: a child tile's sample (0, 0) sits on its parent's
// sample (px, py), px = 1 + (tx % 2) * n / 2 for a child of n intervals (the same for y).
inline int quadrantOffset(int t, int n) { return 1 + (t & 1) * (n / 2); }

// Tiles a residual reader keeps by their index in the file, newest first.
template <class T>
using RecentTiles = std::list<std::pair<int64_t, std::shared_ptr<const std::vector<T>>>>;

// Thread-safe reader: opens the file once, validates the header and the whole offset table
// against the file size, then serves tiles to any number of threads (positional reads).
class ResidualFileReader {
public:
    static std::unique_ptr<ResidualFileReader> open(const std::string& path);
    // The same from any source (kept by the reader; path() is its name).
    static std::unique_ptr<ResidualFileReader> open(std::shared_ptr<const ByteSource> source);
    // The header alone, validated (the offset table is neither read nor checked).
    static ResidualHeader readHeader(const std::string& path);
    static ResidualHeader readHeader(const ByteSource& source);
    ~ResidualFileReader();

    const std::string& path() const { return path_; }
    const ResidualHeader& header() const { return header_; }
    const TileTable& table() const { return *table_; }

    // The stored TIFF bytes of a tile. Throws MissingTileError for a tile outside the file or
    // an empty byte range.
    std::vector<uint8_t> readTileBytes(int level, int tx, int ty) const;
    // The tile's byte range in the offset table (no read). Throws MissingTileError for a tile
    // outside the file.
    TileTable::Range tileRange(int level, int tx, int ty) const;
    // The decoded residuals, tileSamples(level)^2 int16 values, row 0 = bottom. A context-coded
    // tile in the parent mode is decoded with its parent plane, from the tiles above it
    // (formats/residual_shadow.hpp; the last few shadows are kept).
    std::vector<int16_t> readTile(int level, int tx, int ty) const;
    // The same into `out`, tileSamples(level)^2 values (a reader's reused buffer).
    void readTileInto(int level, int tx, int ty, std::span<int16_t> out) const;
    // The tile's parent plane (formats/residual_shadow.hpp): 0 at level 0.
    std::vector<int32_t> parentPlane(int level, int tx, int ty) const;
    // The tile's shadow: its parent plane plus its residuals.
    std::shared_ptr<const std::vector<int32_t>> shadow(int level, int tx, int ty) const;

private:
    ResidualFileReader() = default;
    std::string path_;
    ResidualHeader header_;
    std::unique_ptr<TileTable> table_;
    // The shadows computed last, and the residuals of the context-coded tiles read last that
    // were not in the parent mode (a child in the parent mode needs their shadow), newest first.
    mutable std::mutex recentMutex_;
    mutable RecentTiles<int32_t> shadows_;
    mutable RecentTiles<int16_t> residuals_;
};

// Streaming writer. Tiles may be written in any order; each is appended to a temporary file
// next to the destination as soon as it arrives, identical tiles share one byte range, and
// commit() writes the offset table and renames the temporary onto `path` (atomic). A writer
// destroyed without commit() removes its temporary: nothing half-written is ever left.
class ResidualFileWriter {
public:
    ResidualFileWriter(const std::string& path, const ResidualHeader& header);
    ~ResidualFileWriter();
    ResidualFileWriter(const ResidualFileWriter&) = delete;
    ResidualFileWriter& operator=(const ResidualFileWriter&) = delete;

    const ResidualHeader& header() const { return header_; }
    // Encodes tileSamples(level)^2 residuals (row 0 = bottom) as a Deflate TIFF and appends it.
    void writeTile(int level, int tx, int ty, std::span<const int16_t> residuals);
    // Appends an already encoded tile.
    void writeTileBytes(int level, int tx, int ty, std::span<const uint8_t> blob);
    // Fails if any tile is missing or the data passed the 4 GiB limit of 32-bit offsets.
    // finish() does everything but the rename (the file complete and on disk); commit() does
    // what is left.
    void finish();
    void commit();

    uint64_t bytesWritten() const;
    int64_t sharedTiles() const; // tiles that reused another tile's bytes
    const std::string& path() const { return path_; }

    // For a pyramid written as a region set (formats/residual_set.hpp): the tile data may pass
    // the 4 GiB of one file (finish() then refuses it), and written tiles are read back.
    void allowPastLimit() { table_->allowPastLimit(); }
    bool pastLimit() const { return table_->pastLimit(); }
    TileTable::Range tileRange(int level, int tx, int ty) const { return table_->range(header_.tileIndex(level, tx, ty)); }
    std::vector<uint8_t> readTileBytes(int level, int tx, int ty) const { return table_->read(header_.tileIndex(level, tx, ty)); }
    // The tiles written so far, by index (formats/set_splitter.hpp reads them back).
    const TileTableWriter& table() const { return *table_; }

private:
    std::string path_;
    ResidualHeader header_;
    std::unique_ptr<TileTableWriter> table_;
};

} // namespace pyramid
