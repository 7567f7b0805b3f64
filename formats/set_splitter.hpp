// The one rule by which a pyramid that does not fit in one file is cut into a region set
// (doc/format.md 1.4 and 1.5), for either kind of file: the main file takes the most top levels
// that fit, and each subtree below is one region file named after its root tile, split the same
// way when it does not fit (regions nest). The tiles are copied byte for byte from the whole
// pyramid, already written (past its one-file limit if need be) by a TileTableWriter; the
// kinds differ only in their headers, which a factory makes (formats/residual_set.hpp,
// formats/ortho_set.hpp).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "formats/tile_table.hpp"

namespace pyramid {

// Where the tiles of a file of a set lie in its offset table, levels counted from its root: one
// tile per level below minLevel, then a full quadtree (a residual main file; region files and
// ortho files have minLevel 0). The one rule for the splitter and the sparse writer
// (formats/sparse_set.hpp).
struct SetFileLayout {
    int minLevel = 0;

    int64_t tilesPerSide(int level) const { return level < minLevel ? 1 : int64_t{1} << (level - minLevel); }
    int64_t tileIndex(int level, int tx, int ty) const {
        if (level < minLevel) {
            return level;
        }
        const int l = level - minLevel;
        return minLevel + tx + static_cast<int64_t>(ty) * (int64_t{1} << l) + ((int64_t{1} << (2 * l)) - 1) / 3;
    }
};

// A root pyramid (rootLevel 0) written whole, as the splitter sees it.
struct SplitSource {
    const TileTableWriter* tiles = nullptr; // its tiles, every one written
    std::string path;                       // names it in messages
    int minLevel = 0;                       // the levels below hold one tile each (residual files; 0 for ortho)
    int maxLevel = 0;
    uint64_t headerBytes = 0;               // bytes before the offset table
    int offsetBytes = 4;                    // bytes per offset: 4 (residual) or 8 (ortho)
    uint64_t maxOffset = 0;                 // the largest offset a file's table holds
};

// One file of a set: the subtree rooted at the absolute tile `root` ((0, 0, 0) for the main file),
// its levels root.level to `last` (absolute).
struct SplitFile {
    std::string name; // relative to the main file's directory, as formats/pyramid_set.hpp names it
    RegionRoot root;
    int last = 0;
    uint64_t bytes = 0; // header, offset table and tile data
    int64_t sharedTiles = 0; // tiles that took another tile's bytes (a sparse set's files: sparse_set.hpp)
};

// The header bytes of one file of the set (the main file: root (0, 0, 0)); throws Error naming
// `path` for a header the format refuses.
using SplitHeaderFactory = std::function<std::vector<uint8_t>(const std::string& path, const SplitFile& file)>;

// Writes the pyramid `whole` holds as a set named after `mainName`: the main file takes the
// most top levels that fit in `maxFileBytes`, from level 0 to at least minLevel - 1; each
// subtree below is one region file, or is split the same way when it does not fit. File `name`
// is written to place(name) and committed there (atomically); the index is not written
// (writeRegionIndex). Returns the files, the main first, then the regions by (level, tx, ty).
// Throws Error when a file cannot fit (a single tile, or the main file's levels below minLevel,
// larger than the limit).
std::vector<SplitFile> writeSplitSet(const SplitSource& whole, const std::string& mainName, uint64_t maxFileBytes,
                                     const SplitHeaderFactory& header,
                                     const std::function<std::string(const std::string&)>& place);

// The regions' roots of a set writeSplitSet returned (every file but the first, the main).
std::vector<RegionRoot> splitRegionRoots(const std::vector<SplitFile>& files);

} // namespace pyramid
