// Sparse region sets (doc/format.md 1.5, "Sparse sets"): a pyramid whose data reaches only part
// of its plane or cube face is written as the files that hold that part, and nothing else. The
// encoder logs every tile it stores and every subtree it leaves empty (a subtree no data reaches:
// all residual 0, or blank ortho tiles), in its order; the one rule below then chooses the files
// (a main file of the top levels, region files nested where the data is, down to the deepest level
// that holds anything), and the writer copies each logged tile into the file that holds it. A tile
// no file holds is an empty one: readers continue the pyramid smoothly there (residual 0) or give
// no tile (ortho), which is what the empty tiles would have given. The one owner of that rule for
// both kinds of file; formats/set_splitter.hpp cuts a whole (dense) pyramid by size instead.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "formats/set_splitter.hpp"

namespace pyramid {

// What the files of a sparse set look like, whatever their kind.
struct SparseShape {
    int minLevel = 0;              // of the main file (residual files; 0 for ortho files)
    int maxLevel = 0;              // the pyramid's deepest level
    uint64_t headerBytes = 0;      // bytes before the offset table
    int offsetBytes = 4;           // bytes per offset: 4 (residual) or 8 (ortho)
    uint64_t maxOffset = 0;        // the most tile data one file's offsets address
    uint64_t maxFileBytes = 0;     // 0: no cap; else every file at most this many bytes
};

// Each file of a set costs this much in the layout's choice, beside its offset table's bytes: a
// region saves its parent file's table 8 bytes a tile, so it is only cut where it saves more
// than this (a file system block or four, and one more file to open).
inline constexpr uint64_t kSparseFileCost = 16384;

// The tiles an encoder stored and the subtrees it left empty, in the order it gave them (that
// order decides where shared bytes land in each file, so the files are the same whatever the
// threads). Blobs are spooled to a temporary file beside the output (identical ones once), not
// held in memory. Calls are serialised.
class SparseTileLog {
public:
    // `emptyBlob`: the bytes of an empty tile of a full-size level (a tile of residual 0, a blank
    // ortho tile); `spoolPath`: the temporary the blobs go to (removed with the log).
    SparseTileLog(const std::string& spoolPath, std::vector<uint8_t> emptyBlob);
    ~SparseTileLog();
    SparseTileLog(const SparseTileLog&) = delete;
    SparseTileLog& operator=(const SparseTileLog&) = delete;

    // A stored tile (absolute coordinates).
    void add(int level, int tx, int ty, std::span<const uint8_t> blob);
    // The subtree rooted at (level, tx, ty), level >= the main file's minLevel: every tile of it is
    // the empty blob, to the deepest level.
    void addEmptySubtree(int level, int tx, int ty);
    // The same, but a file holding its tiles leaves them out (TileTableWriter::leaveOut): an ortho
    // subtree beyond an input's resolution, where a reader magnifies the parent rather than show
    // a blank tile.
    void addLeftOutSubtree(int level, int tx, int ty);

    struct Item {
        int32_t tx = 0, ty = 0;
        uint64_t offset = 0; // in the spool
        uint32_t size = 0;   // 0: an empty subtree
        int8_t level = 0;
        bool empty = false;  // the blob is the empty blob
        bool leftOut = false; // an empty subtree whose tiles files leave out
    };
    const std::vector<Item>& items() const { return items_; }
    const std::vector<uint8_t>& emptyBlob() const { return emptyBlob_; }
    std::vector<uint8_t> read(const Item& item) const;
    // Tiles whose blob is not the empty one (the data).
    int64_t dataTiles() const { return dataTiles_; }

private:
    struct Spool;
    std::unique_ptr<Spool> spool_;
    std::vector<uint8_t> emptyBlob_;
    std::vector<Item> items_;
    int64_t dataTiles_ = 0;
};

// The files of the set: the main file (root (0, 0, 0)) first, holding levels 0 to at least
// minLevel, then the regions by (level, tx, ty). A tile is wanted when it or a tile below it holds
// data (a blob other than the empty one); files hold every wanted tile, and each goes no deeper
// than the deepest wanted tile below its root. Among such layouts, the one of the fewest bytes,
// counting each file's offset table and kSparseFileCost per file, whose files each fit
// shape.maxFileBytes and shape.maxOffset (ties: the fewest files). Throws Error naming `path` when
// one tile alone cannot fit. Names are left empty.
std::vector<SplitFile> chooseSparseFiles(const SparseTileLog& log, const SparseShape& shape, const std::string& path);

// Writes the files `chooseSparseFiles` chose: file `name` (the main file `mainName`, each region
// named as formats/pyramid_set.hpp names them) at place(name), committed there (atomically), each
// logged tile in the file that holds it in the log's order, the tiles of empty subtrees as the
// empty blob (left out, for addLeftOutSubtree's). Returns the files with their names and bytes. The index is not written.
std::vector<SplitFile> writeSparseSet(const SparseTileLog& log, const SparseShape& shape, std::vector<SplitFile> files,
                                      const std::string& mainName, const SplitHeaderFactory& header,
                                      const std::function<std::string(const std::string&)>& place);

} // namespace pyramid
