// The part that residual and ortho files share: a fixed header, an offset table of
// 2 x tileCount offsets (uint32 for residual files, int64 for ortho files) relative to
// the end of the table, then the tile bytes. Tile i is the byte range
// [offsets[2i], offsets[2i+1]); several tiles may share a range (doc/format.md).
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "formats/byte_source.hpp"

namespace pyramid {

class TileTable {
public:
    struct Range {
        uint64_t begin = 0; // relative to dataStart()
        uint64_t end = 0;
        uint64_t size() const { return end - begin; }
    };

    // Reads `tileCount` offset pairs of `offsetBytes` (4 or 8) starting at byte `tableStart` of
    // `source`, and validates every pair against the source's size: the table must fit in it
    // (checked before anything is allocated for it), begin <= end <= bytes of tile data.
    // Throws Error("NAME: ...") otherwise. The table is read in one read into one allocation
    // of its own size, kept as stored (little-endian) and decoded by range(). The table keeps
    // the source.
    static std::unique_ptr<TileTable> open(std::shared_ptr<const ByteSource> source, uint64_t tableStart,
                                           int64_t tileCount, int offsetBytes);
    // The same over the file `path` (openFileSource).
    static std::unique_ptr<TileTable> open(const std::string& path, uint64_t tableStart, int64_t tileCount,
                                           int offsetBytes);
    ~TileTable();
    TileTable(const TileTable&) = delete;
    TileTable& operator=(const TileTable&) = delete;

    const std::string& path() const { return source_->name(); } // the source's name
    const ByteSource& source() const { return *source_; }
    int64_t tileCount() const { return tileCount_; }
    // Throws Error for an index outside [0, tileCount()).
    Range range(int64_t index) const;
    uint64_t dataStart() const { return dataStart_; }
    uint64_t fileSize() const { return fileSize_; }
    // Number of tiles with a non-empty byte range (the others are left out).
    int64_t storedTiles() const;
    // Number of distinct non-empty byte ranges (tiles sharing bytes count once, tiles left out as
    // an empty range not at all): never more than the tiles stored.
    int64_t distinctRanges() const;
    // The bytes of tile `index` (positional read: safe from many threads at once).
    // Throws MissingTileError for an empty range ("PATH: tile N is missing").
    std::vector<uint8_t> read(int64_t index) const;
    // Reads `size` bytes at absolute offset `offset` of the source (used by header readers).
    void readAt(uint64_t offset, void* out, size_t size) const;

private:
    TileTable() = default;
    std::shared_ptr<const ByteSource> source_;
    uint64_t dataStart_ = 0;
    uint64_t fileSize_ = 0;
    int64_t tileCount_ = 0;
    int offsetBytes_ = 4;
    std::vector<uint8_t> table_; // the offset table as stored: 2 * offsetBytes_ per tile
};

// Streams a pyramid file to a temporary next to `path`: the header and a zeroed table
// first, then each tile's bytes as they arrive (any order, from any thread: calls are
// serialised). Identical blobs are stored once (content hash, confirmed byte for byte).
// commit() checks that every tile was written, writes the table and renames the temporary
// onto `path`. Destroyed without commit(), it removes the temporary.
class TileTableWriter {
public:
    // `maxOffset` is the largest offset the table can hold (UINT32_MAX for residual files);
    // passing it is an error naming `path`, never a wrap-around.
    TileTableWriter(const std::string& path, std::span<const uint8_t> header, int64_t tileCount,
                    int offsetBytes, uint64_t maxOffset);
    ~TileTableWriter();
    TileTableWriter(const TileTableWriter&) = delete;
    TileTableWriter& operator=(const TileTableWriter&) = delete;

    void write(int64_t index, std::span<const uint8_t> blob);
    // Tile `index` takes the bytes of tile `earlier`, already written (as write() of the same
    // bytes would, without comparing them): for a caller that knows the two tiles alike, such as
    // the many blank tiles of a pyramid of millions.
    void writeSameAs(int64_t index, int64_t earlier);
    // Tile `index` is left out: an empty byte range, which readers take as no tile (ortho) or
    // zero residuals (doc/format.md 1.5, "Sparse sets").
    void leaveOut(int64_t index);
    bool written(int64_t index) const;
    // Everything but the rename: checks every tile, writes the table, flushes the file.
    void finish();
    void commit(); // finish() unless done, then the rename

    uint64_t bytesWritten() const; // tile bytes, shared tiles counted once
    int64_t sharedTiles() const;

    // Lets tile data pass `maxOffset`: writes go on, finish() then refuses the file, and the
    // tiles stay readable (range, read) for a writer that splits them into files that fit
    // (formats/set_splitter.hpp). Call before the first write.
    void allowPastLimit();
    bool pastLimit() const; // the data passed maxOffset
    // Where tile `index` lies among the tile bytes (tiles sharing bytes share the range), and its
    // bytes, read back from the temporary. The tile must have been written.
    TileTable::Range range(int64_t index) const;
    std::vector<uint8_t> read(int64_t index) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
