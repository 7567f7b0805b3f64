// Region sets (doc/format.md, 1.5): a main pyramid file plus region files nested in it, listed
// by an index beside the main file. Here: the region files' names, the index's codec, which
// files a path given by a user names, and the rules a set must keep. No processing.
//
//   DEM.dat                  the main file (rootLevel 0)
//   DEM-L6-12-40.dat         a region file, named after its absolute root tile (6, 12, 40)
//   DEM.dat.regions.json     the index: {"format": "libpyramid region set", "version": 1,
//                            "kind": "residual", "main": "DEM.dat",
//                            "regions": [{"file": "DEM-L6-12-40.dat", "root": [6, 12, 40]}]}
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "formats/pyramid_kind.hpp"

namespace pyramid {

// An absolute tile of the enclosing pyramid: the root of a region file.
struct RegionRoot {
    int level = 0, tx = 0, ty = 0;
    auto operator<=>(const RegionRoot&) const = default;
};

struct RegionEntry {
    std::string file; // as the index spells it: relative to the index's directory
    RegionRoot root;
};

// An index as it stands on disk.
struct RegionIndex {
    PyramidKind kind = PyramidKind::Residual;
    std::string main;                 // relative to the index's directory
    std::vector<RegionEntry> regions; // sorted by root (level, tx, ty)
};

inline constexpr const char* kRegionIndexFormat = "libpyramid region set";
inline constexpr int kRegionIndexVersion = 1;
inline constexpr const char* kRegionIndexSuffix = ".regions.json";

// Whether absolute tile (level, tx, ty) lies in the region rooted at `root` (at or below it).
bool regionHolds(const RegionRoot& root, int level, int tx, int ty);
// The region file's own coordinates of absolute tile (level, tx, ty), which it holds: its level
// below the root, its position within the root's subtree.
RegionRoot regionRelativeTile(const RegionRoot& root, int level, int tx, int ty);

// "(6,12,40)": a tile in messages.
std::string tileText(const RegionRoot& root);

// "DIR/DEM.dat" -> "DIR/DEM.dat.regions.json".
std::string regionIndexPath(const std::string& mainFile);
// The region file of `mainFile` rooted at `root`: "DIR/DEM.dat", (6, 12, 40) -> "DIR/DEM-L6-12-40.dat"
// (the main file's stem and extension).
std::string regionFilePath(const std::string& mainFile, const RegionRoot& root);
// The inverse of regionFilePath, by the name alone: "DIR/DEM-L6-12-40.dat" -> "DIR/DEM.dat",
// (6, 12, 40); nullopt for a path the rule gives no main file for (a root off its level or
// outside 1..30, numbers spelt otherwise than regionFilePath spells them, an empty stem).
// Whether the main file exists is not asked.
struct RegionFileName {
    std::string mainFile;
    RegionRoot root;
};
std::optional<RegionFileName> parseRegionFilePath(const std::string& file);

// Parses an index (its regions in any order). Throws Error("PATH: ...") for text that is not
// such an index: bad JSON, another format or version, an unknown kind, an empty file name, a
// root that is not three whole numbers (level 1..30, tx and ty inside the level).
RegionIndex parseRegionIndex(const std::string& text, const std::string& path);
std::string formatRegionIndex(const RegionIndex& index); // pretty JSON and a final newline
RegionIndex readRegionIndex(const std::string& path);
// Writes `index` to `path` atomically (a temporary renamed into place: formats/atomic_file.hpp),
// its regions sorted by root. Throws Error for an index parseRegionIndex would refuse.
void writeRegionIndex(const std::string& path, RegionIndex index);
// The index of a main file and its regions, named by the rule above (regionFilePath), the
// paths relative to the main file's directory: what writeRegionIndex(regionIndexPath(mainFile),
// ...) records for a set a preprocessor wrote.
RegionIndex makeRegionIndex(const std::string& mainFile, PyramidKind kind, const std::vector<RegionRoot>& roots);

// The files named after an output `path` that exist beside it, an earlier run's: its region
// index, the region files the index lists (by the naming rule: regionFilePath), its
// georeference sidecar. A run that writes `path` replaces them all: the ones it does not write
// again go in the same commit (StagingDirectory::commit), so that no reader takes an earlier
// build's regions or placement for the new one's.
std::vector<std::string> filesNamedAfter(const std::string& path);

// The files a path names, resolved but not yet checked.
struct PyramidSet {
    std::string index;                // the index's path; empty for a file alone
    PyramidKind kind = PyramidKind::Residual;
    std::string main;                 // the main file's path
    std::vector<std::string> regions; // the region files' paths, in the index's order
    std::vector<RegionRoot> roots;    // their roots, as the index says
    // What messages call the set: the index, or the file alone.
    const std::string& name() const { return index.empty() ? main : index; }
};

// Which files `path` names: (a) an index: the set it lists; (b) a pyramid file: the set of its
// index beside it (regionIndexPath) when there is one, else the file alone (of the kind it
// holds: its kind is detected); (c) a directory: the set of the one *.regions.json in it.
// Throws Error naming the path: missing, a directory with several indexes or none, a bad index.
// The files themselves are opened by pyramidSetProblems only (a file alone: its kind detected).
PyramidSet resolvePyramidSet(const std::string& path);

// The problems that break the rules of a set, one line each naming the file and the problem
// (empty: a good set). For a set with an index: every listed file exists and holds a pyramid
// of the index's kind; the main file has rootLevel 0; every region has minLevel 0 (residual),
// the main file's tile size, its scale (residual) or its channels, border and DXT flag (ortho),
// and the root the index gives; its parent tile lies in the main file or in another region of
// the set; no two regions share a root. A file alone has none of these rules: it is only opened.
std::vector<std::string> pyramidSetProblems(const PyramidSet& set);

// The index `path` names (a): itself; (b) the index beside it, or "" when there is none; (c) the
// one in the directory. A missing path names no index (unless it ends in .json): its reader
// says it is missing. Throws as resolvePyramidSet for a directory with several indexes or none.
std::string findRegionIndex(const std::string& path);

// resolvePyramidSet, then the first of pyramidSetProblems thrown as an Error.
PyramidSet openPyramidSet(const std::string& path);

// The pyramids under a directory, its subdirectories too (what a build's output directory holds:
// a planet's faces, an ortho build's three outputs, sets and files side by side): every region
// set index (*.regions.json) names a set, and every other *.dat file that no index lists is a
// file alone. Each list in path order; files of other names are not looked at. Throws Error
// naming the directory when it cannot be listed. (A bad index is listed as a set: its problems
// are the set's.)
struct PyramidsUnder {
    std::vector<std::string> sets;  // the indexes
    std::vector<std::string> files; // files alone
    size_t count() const { return sets.size() + files.size(); }
};
PyramidsUnder pyramidsUnder(const std::string& directory);

} // namespace pyramid
