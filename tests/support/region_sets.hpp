// Region sets made by hand for the tests (doc/format.md 1.5): a DEM encoded as one file and split
// here into a main file and region files, one nested in another; and the check that a set's
// problems name a file and what breaks it.
#pragma once
#include <string>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "tests/support/paths.hpp"

namespace pyramid::test {

// Copies the tiles of `single` into a new file at `path` with header `h`: tile (l, x, y) of the new
// file is tile (rootLevel + l, rootTx 2^l + x, rootTy 2^l + y) of the single file.
void copyResidual(const ResidualFileReader& single, const std::string& path, const ResidualHeader& h);

// `single`'s header for a region file rooted at `root`, holding `maxLevel` levels below it.
ResidualHeader regionHeader(const ResidualHeader& single, RegionRoot root, int maxLevel);

// A 257 x 257 DEM (tile size 8, minLevel 1, levels 0..6) encoded as DEM.dat in `single/`, and the
// same pyramid split in `set/`: the main file holds levels 0..2, the 16 tiles of level 3 root
// region files down to level 6, and region (5,5,9), nested in region (3,1,2), holds that
// subtree's levels 5..6 again: the deepest file serves them.
struct SplitDem {
    TempDir dir;
    std::string input = dir.file("dem.tif");
    std::string single = dir.file("single/DEM.dat");
    std::string setDir = dir.file("set");
    std::string main = dir.file("set/DEM.dat");
    std::string index = dir.file("set/DEM.dat.regions.json");
    std::string nested = dir.file("set/DEM-L5-5-9.dat");
    ResidualHeader header;
    std::vector<RegionRoot> roots;

    SplitDem();
};

// One of `problems` (pyramidSetProblems's) is "FILE: ..." with `words` in it.
void expectProblem(const std::vector<std::string>& problems, const std::string& file, const std::string& words);

} // namespace pyramid::test
