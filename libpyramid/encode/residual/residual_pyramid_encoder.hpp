// The residual pyramid encoder behind preprocessDem and preprocessSphericalDem, independent of
// where the heights come from (doc/dem-encoding.md): a finest grid of N + 1 samples per side
// whose heights a HeightSource provides, encoded closed loop into one residual file.
//
// Tile borders reach 2 samples beyond the finest grid's edges. A planar map has nothing there:
// the edge samples repeat (GridEdges::Clamped). A cube face has its neighbours there: the
// HeightSource is asked for those positions too, with negative coordinates or beyond N
// (GridEdges::Folded), and answers with the neighbour face's samples.
#pragma once
#include <optional>
#include <string>

#include "formats/residual_file.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/dem/dem_sampling.hpp"

namespace pyramid {

enum class GridEdges { Clamped, Folded };

struct ResidualPyramidJob {
    ResidualHeader header;           // minLevel, maxLevel and tileSize; the scale comes from the options
    const HeightSource* heights = nullptr;
    GridEdges edges = GridEdges::Clamped;
    // The height given to every sample of a pyramid that has no valid sample at all (a cube face
    // outside a partial --extent); none: such a pyramid is an error.
    std::optional<float> emptyFill;
    std::string input;               // names the input in messages
};

// Encodes the pyramid into `output` (written atomically) with options' scale (or --scale auto),
// threads, progress and reconstruction hook, and fills report's header, tiles, sharedTiles,
// bytes, finestSamples, nodataFilled, levels, scalesTried and threads. Throws Error on int16
// overflow (naming the smallest scale that would fit) and when no sample is valid.
void encodeResidualPyramid(const ResidualPyramidJob& job, const std::string& output, const DemEncodeOptions& options,
                           DemReport& report);

// A number as messages print it: up to 6 significant digits, no trailing zeros.
std::string numberText(double x);

} // namespace pyramid
