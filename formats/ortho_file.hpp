// Ortho pyramid files: the on-disk layout of doc/format.md, section "Ortho files".
//
//   header   int32 maxLevel, tileSize, channels, rootLevel, rootTx, rootTy, flags
//   offsets  int64[2 * tileCount], relative to the end of this array
//   tiles    one TIFF (one strip, 8 bits per sample) or one raw DXT block stream per tile
//
// flags bit 0: DXT tiles. flags bit 1: tiles have NO border (the original tools' meaning,
// which is the opposite of their documentation); clear = a 2-pixel border on every side.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "formats/byte_source.hpp"
#include "formats/dxt_codec.hpp"
#include "formats/tiff_tile.hpp"
#include "formats/tile_table.hpp"

namespace pyramid {

struct OrthoHeader {
    int32_t maxLevel = 0;
    int32_t tileSize = 0;  // pixels per side without borders
    int32_t channels = 0;  // 1..4 (DXT files: max(3, source channels))
    int32_t rootLevel = 0;
    int32_t rootTx = 0;
    int32_t rootTy = 0;
    uint32_t flags = 0;

    static constexpr size_t kBytes = 28;
    static constexpr uint32_t kFlagDxt = 1u;
    static constexpr uint32_t kFlagNoBorder = 2u;

    bool dxt() const { return (flags & kFlagDxt) != 0; }
    int border() const { return (flags & kFlagNoBorder) ? 0 : 2; }
    int tilePixels() const { return tileSize + 2 * border(); } // pixels per side as stored
    int64_t tileCount() const;
    int64_t tileIndex(int level, int tx, int ty) const;
    int64_t tilesPerSide(int level) const; // 2^level
    bool contains(int level, int tx, int ty) const;
    // Throws Error (prefixed with `where`) unless sane: 0 <= maxLevel <= 30,
    // 1 <= tileSize <= 8192, 1 <= channels <= 4 (3 or 4 with DXT), tilePixels a multiple
    // of 4 with DXT, root inside its level, only flag bits 0 and 1 set.
    void validate(const std::string& where) const;
};

// The block format of a DXT file's tiles: DXT5 for 4 channels, DXT1 otherwise.
inline DxtFormat dxtFormatOf(const OrthoHeader& h) { return h.channels == 4 ? DxtFormat::Dxt5 : DxtFormat::Dxt1; }

// The header as stored: 28 little-endian bytes (not validated).
std::vector<uint8_t> packOrthoHeader(const OrthoHeader& h);

class OrthoFileReader {
public:
    static std::unique_ptr<OrthoFileReader> open(const std::string& path);
    // The same from any source (kept by the reader; path() is its name).
    static std::unique_ptr<OrthoFileReader> open(std::shared_ptr<const ByteSource> source);
    ~OrthoFileReader();

    const std::string& path() const { return path_; }
    const OrthoHeader& header() const { return header_; }
    const TileTable& table() const { return *table_; }

    // The stored bytes (a TIFF, or raw DXT1/DXT5 blocks ready for upload). Throws
    // MissingTileError for a tile outside the file or an empty byte range.
    std::vector<uint8_t> readTileBytes(int level, int tx, int ty) const;
    // The tile's byte range in the offset table (no read). Throws MissingTileError for a tile
    // outside the file.
    TileTable::Range tileRange(int level, int tx, int ty) const;
    // Decoded pixels: tilePixels()^2 x channels() bytes, row 0 = bottom. DXT tiles are decoded
    // to header().channels (3 for DXT1, 4 for DXT5).
    std::vector<uint8_t> readTile(int level, int tx, int ty) const;

private:
    OrthoFileReader() = default;
    std::string path_;
    OrthoHeader header_;
    std::unique_ptr<TileTable> table_;
};

struct OrthoTileEncoding {
    TiffCompression compression = TiffCompression::Deflate; // TIFF files
    int jpegQuality = 90;                                   // 1..100, with Jpeg
    int dxtQuality = 1;                                     // 0 fastest .. 3 best (DXT files, dxt_codec.hpp)
};

// Streaming, deduplicating, atomic writer: see ResidualFileWriter.
class OrthoFileWriter {
public:
    OrthoFileWriter(const std::string& path, const OrthoHeader& header);
    ~OrthoFileWriter();
    OrthoFileWriter(const OrthoFileWriter&) = delete;
    OrthoFileWriter& operator=(const OrthoFileWriter&) = delete;

    const OrthoHeader& header() const { return header_; }
    // `pixels`: tilePixels()^2 x channels bytes, row 0 = bottom. Encoded as a one-strip TIFF,
    // or as DXT1 (channels <= 3) / DXT5 (4 channels) when the header says DXT. Part of the
    // preprocess library (formats/ortho_tile_writer.cpp): the runtime library only decodes.
    void writeTile(int level, int tx, int ty, std::span<const uint8_t> pixels,
                   const OrthoTileEncoding& encoding = {});
    void writeTileBytes(int level, int tx, int ty, std::span<const uint8_t> blob);
    // Tile (level, tx, ty) takes the bytes of tile `earlier` (level, tx, ty), already written
    // (TileTableWriter::writeSameAs).
    void writeTileSameAs(int level, int tx, int ty, const std::array<int, 3>& earlier);
    // Fails if any tile is missing. finish() does everything but the rename (the file complete
    // and on disk); commit() does what is left.
    void finish();
    void commit();

    uint64_t bytesWritten() const;
    int64_t sharedTiles() const;
    const std::string& path() const { return path_; }
    // The tiles written so far, by index: a pyramid written as a region set
    // (formats/ortho_set.hpp) is split from them.
    const TileTableWriter& table() const { return *table_; }

private:
    std::string path_;
    OrthoHeader header_;
    std::unique_ptr<TileTableWriter> table_;
};

} // namespace pyramid
