// Tiles for the file writer tests (tests/formats_*_test.cpp): every tile of a pyramid's levels in
// a shuffled order (writers must accept any order), residuals spanning the whole int16 range and
// smooth pixels, each different for every tile.
#pragma once
#include <cstdint>
#include <vector>

#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"

namespace pyramid::test {

struct TileId {
    int level, tx, ty;
};

// Every tile of levels [0, maxLevel] of `h`, shuffled deterministically by `seed`.
std::vector<TileId> residualTiles(const ResidualHeader& h, unsigned seed);
std::vector<TileId> orthoTiles(const OrthoHeader& h, unsigned seed);

// Residuals spanning the whole int16 range, different for every tile.
std::vector<int16_t> residualsFor(const ResidualHeader& h, const TileId& t);

// A smooth gradient, different for every tile (lossy codecs are only bounded on such content).
std::vector<uint8_t> smoothPixels(int size, int channels, const TileId& t);

} // namespace pyramid::test
