// An ortho pyramid written as a region set (doc/format.md 1.4 and 1.5), as residual pyramids
// are (formats/residual_set.hpp): the main file holds the top levels and each subtree below
// them is a region file named after its root tile (RGB.dat, RGB-L6-12-40.dat, ...), every file
// at most a given size; an index beside the main file (RGB.dat.regions.json) lists them. The
// tiles are the whole pyramid's, byte for byte. Ortho files have 64-bit offsets, so a single
// file has no size limit of its own: the limit is the caller's.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"

namespace pyramid {

// One file of a set: its name (relative to the main file's directory) and header.
struct OrthoSetFile {
    std::string name;
    OrthoHeader header;
    uint64_t bytes = 0;
};

// The header of the file of a set rooted at absolute tile `root` ((0, 0, 0): the main file) down
// to absolute level `last`: `whole`'s tile size, channels and flags, and its root.
OrthoHeader orthoRegionHeader(const OrthoHeader& whole, const RegionRoot& root, int last);

// Writes the pyramid `whole` holds (every tile written; a root pyramid, rootLevel 0) as a set
// named after `mainName`: the main file takes the most top levels that fit in `maxFileBytes`
// (at least level 0); each subtree below is one region file with the main file's tile size,
// channels and flags, or is split the same way when it does not fit (regions nest). File `name`
// is written to place(name) and committed there (atomically); the index is not written
// (writeRegionIndex). Returns the files, the main first, then the regions by (level, tx, ty).
// Throws Error when a file cannot fit (a single tile, or level 0, larger than the limit). The
// cut is formats/set_splitter.hpp's, the one rule for both kinds of file. Messages name the
// pyramid `name` (default: whole.path(), which may be a staging directory's).
std::vector<OrthoSetFile> writeOrthoSet(const OrthoFileWriter& whole, const std::string& mainName, uint64_t maxFileBytes,
                                        const std::function<std::string(const std::string&)>& place,
                                        const std::string& name = {});

} // namespace pyramid
