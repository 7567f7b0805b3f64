// The parent mode's pass (doc/format.md 1.8, version 3): a finished residual file's
// context-coded tiles rewritten in the parent mode where that is smaller. The mode predicts a
// tile from its parent's shadow (formats/residual_shadow.hpp), a property of the tiles above it
// in the same file: it is chosen once the file that holds a tile is final, whatever split the
// pyramid into a set or merged it from parts, so that each file decodes alone.
#pragma once
#include <memory>
#include <string>

#include "formats/residual_file.hpp"

namespace pyramid {

// Writes `input`'s pyramid into `output` (the same path or another; put in place atomically by
// the returned writer's commit(): it is finished, not committed). Every tile that is
// context-coded, stored once (its bytes shared with no other tile) and smaller in the parent mode
// takes it; every other tile keeps its bytes. The residuals are the same, the tiles in the
// input's order, no tile grows, and the bytes do not depend on `threads` (0: all cores). Depth
// first below the top levels, each thread holding one shadow per level.
std::unique_ptr<ResidualFileWriter> rewriteInParentMode(const std::string& input, const std::string& output,
                                                        int threads);

} // namespace pyramid
