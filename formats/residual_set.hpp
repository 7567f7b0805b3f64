// A residual pyramid written as a region set (doc/format.md 1.4 and 1.5): the main file holds
// the top levels and each subtree below them is a region file named after its root tile
// (DEM.dat, DEM-L6-12-40.dat, ...), every file at most a given size; an index beside the main
// file (DEM.dat.regions.json) lists them. The tiles are the whole pyramid's, byte for byte:
// regions hold the residuals the whole pyramid holds (its residuals are already relative to
// the reconstruction above them), so a set rebuilds exactly what the single file would.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"

namespace pyramid {

// One file of a set: its name (relative to the main file's directory) and header.
struct ResidualSetFile {
    std::string name;
    ResidualHeader header;
    uint64_t bytes = 0;
};

// The header of the file of a set of the root pyramid `whole` rooted at absolute tile `root`,
// down to absolute level `last`: the main file (root level 0) keeps the whole header to `last`;
// a region file has minLevel 0, its root in the header, and levels counted from it (doc/format.md
// 1.4). Not validated.
ResidualHeader residualRegionHeader(const ResidualHeader& whole, const RegionRoot& root, int last);

// Writes the pyramid `whole` holds (every tile written, past 4 GiB if need be; it must be a
// root pyramid, rootLevel 0) as a set named after `mainName`: the main file takes the most top
// levels that fit in `maxFileBytes`, from level 0 to at least minLevel - 1; each subtree below
// is one region file, or is split the same way when it does not fit (regions nest). File
// `name` is written to place(name) and committed there (atomically), named as
// formats/pyramid_set.hpp names region files; the index is not written (writeRegionIndex).
// Returns the files, the main first, then the regions by (level, tx, ty). Throws Error when a
// file cannot fit (a single tile, or the main file's levels below minLevel, larger than the
// limit). The cut is formats/set_splitter.hpp's, the one rule for both kinds of file.
std::vector<ResidualSetFile> writeResidualSet(const ResidualFileWriter& whole, const std::string& mainName,
                                              uint64_t maxFileBytes,
                                              const std::function<std::string(const std::string&)>& place);

} // namespace pyramid
