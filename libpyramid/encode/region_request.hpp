// A region build (doc/planet-scale.md, "One region at a time"), asked of any preprocessor: only
// the sub-pyramid rooted at absolute tile `root` of the pyramid the same build writes whole,
// as region files (doc/format.md 1.4) whose tiles are the whole pyramid's, byte for byte: the
// files `--max-file-bytes` writes for that subtree. Residuals (elevation or colour) are
// against the enclosing pyramid's reconstruction.
#pragma once
#include <string>

#include "formats/pyramid_set.hpp"

namespace pyramid {

// How a preprocessor lays its pyramid out in files (doc/format.md 1.5, "Sparse sets").
// Sparse: where the data reaches only part of the plane or face, the files hold that part alone
// (a main file of the top levels and region files nested where the data is, each no deeper than
// its data); a pyramid the data fills is one file (or a --max-file-bytes set), as Dense writes it.
// Dense: every tile of every level, in one file (or a --max-file-bytes set).
enum class PyramidLayout { Sparse, Dense };

struct RegionRequest {
    RegionRoot root;
    // An existing main file or set of the same build (empty: none): the residual pyramid whose
    // reconstruction the region's residuals are against. The root's parent tile is then read
    // from it through the runtime's producers, bit-exact with the encoder's, so that a root
    // below the in-memory top levels reads only its own input window. Without it the levels
    // above the root are encoded from the input first, as a whole build does.
    std::string parent;
};

} // namespace pyramid
