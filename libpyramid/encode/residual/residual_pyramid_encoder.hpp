// The residual pyramid encoder behind preprocessDem and preprocessSphericalDem, independent of
// where the heights come from (doc/dem-encoding.md): a finest grid of N + 1 samples per side
// whose heights a HeightSource provides, encoded closed loop into one residual file.
//
// Tile borders reach 2 samples beyond the finest grid's edges. A planar map has nothing there:
// the edge samples repeat (GridEdges::Clamped). A cube face has its neighbours there: the
// HeightSource is asked for those positions too, with negative coordinates or beyond N
// (GridEdges::Folded), and answers with the neighbour face's samples.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/region_request.hpp"
#include "libpyramid/encode/residual/height_source.hpp"
#include "libpyramid/encode/residual/residual_output.hpp"

namespace pyramid {

enum class GridEdges { Clamped, Folded };

// The most tiles a pyramid written whole (one file, or a --max-file-bytes set) may have: each holds
// offsets and a hash in memory. A sparse output holds only the tiles its heights reach.
inline constexpr int64_t kMaxDenseTiles = int64_t{1} << 28;

class PartOutput;

// An attempt's int16 overflow: the largest |residual| beyond int16 where the encoding stops, at
// which scale and level. position -1: in the in-memory top levels; else the end of the group of 4
// subtrees it was found in (the encoding stops at the end of the first such group).
struct ResidualOverflow {
    double scale = 0.0;
    int64_t residual = 0;
    int level = 0;
    int64_t position = -1;
};

// One process's share of a build split across processes (residual_parts.hpp): part `index` of
// `count`, whose tiles go to `out` instead of the outputs.
struct ResidualShare {
    int index = 0;
    int count = 1;
    PartOutput* out = nullptr;
    // When the parts run together (the ranks of an MPI run): called by every part once per
    // attempt of each pyramid, in the same order, with the part's own overflow (none when it
    // encodes nothing of the pyramid); returns the build's, the first by position, which every
    // part then acts on alike (a larger automatic scale, or the error). Without it a part can
    // only fail on an overflow in its subtrees: the other parts' scale would not follow.
    std::function<std::optional<ResidualOverflow>(const std::optional<ResidualOverflow>&)> agree;
};

// How residuals are quantized and the encoding is run: the options every residual pyramid
// takes, whatever its heights' source (the DEM front ends' options extend them).
struct ResidualEncodeOptions {
    double scale = 1.0;             // quantization step (height units per residual unit)
    bool autoScale = false;         // choose the smallest 1-2-5 x 10^k scale without int16 overflow
    int threads = 0;                // 0: all cores
    // How tiles are coded: the original tools' Deflate TIFF tiles by default (fast), the
    // smallest TIFF tiles the original runtime reads, or libpyramid's context coding.
    ResidualTileCoding tiles;
    // 0: one file (its tile data at most 4 GiB). Otherwise a region set of files of at most
    // this many bytes each, and its index (formats/residual_set.hpp, doc/format.md 1.6).
    uint64_t maxFileBytes = 0;
    // Sparse (the default): a pyramid the heights reach only part of is written as the files that
    // hold that part (formats/sparse_set.hpp). Not for a share or a region build, which write
    // every tile of theirs.
    PyramidLayout layout = PyramidLayout::Sparse;
    // Set in each process of a split build: encode only this share, into its part file.
    const ResidualShare* share = nullptr;
    // Set: encode only this region, into one region file (neither a share nor a set of files).
    std::optional<RegionRequest> region;
    // Called from one thread at a time with (tiles done, total tiles).
    std::function<void(int64_t, int64_t)> progress;
    // Asked after every tile, from one thread at a time: true stops the encoding, which throws
    // Cancelled (formats/error.hpp) and leaves no file behind.
    std::function<bool()> cancelled;
    // Called from one thread at a time with each tile's reconstruction ((n+5)^2 float32, row 0 =
    // bottom), exactly what a producer rebuilds from the file: for tests and inspection.
    std::function<void(int level, int tx, int ty, const std::vector<float>&)> reconstruction;

    // Throws OptionError unless the scale is positive and finite (or automatic) and threads >= 0.
    void validate() const;
};

struct ResidualLevelReport {
    int level = 0;
    int64_t tiles = 0;
    int64_t samples = 0;     // valid source samples compared
    double maxError = 0.0;   // max |reconstruction - source|
    double rmsError = 0.0;
    int maxAbsResidual = 0;
};

// What the encoder measured of the pyramid it wrote.
struct ResidualPyramidReport {
    ResidualHeader header;
    int64_t tiles = 0;
    int64_t sharedTiles = 0;
    uint64_t bytes = 0;       // file size (of a set: of all its files)
    // A region set's files (main first, with their sizes); empty for one file.
    std::vector<std::pair<std::string, uint64_t>> files;
    int64_t finestSamples = 0;
    int64_t nodataFilled = 0; // finest-grid samples without a source height, filled
    std::vector<ResidualLevelReport> levels;
    std::vector<double> scalesTried; // automatic scale
    int threads = 0;
};

struct GivenRootFill; // root_fill.hpp

struct ResidualPyramidJob {
    ResidualHeader header;           // minLevel, maxLevel and tileSize; the scale comes from the options
    const HeightSource* heights = nullptr;
    GridEdges edges = GridEdges::Clamped;
    // Root values solved with other pyramids' (a planet's faces, root_fill.hpp), asked for only
    // when the root has nodata; none: the root's nodata is solved from this pyramid's own
    // samples, and a pyramid without any valid sample is an error.
    std::function<const GivenRootFill&()> rootFill;
    std::string input;               // names the input in messages
    // The files that go with the pyramid (its georeference sidecar), put in place together with
    // it (residual_output.hpp).
    std::vector<CompanionFile> companions;
    // This pyramid among the build's (a cube face among six), for a split build's shares.
    int pyramid = 0;
    int pyramids = 1;
};

// Encodes the pyramid into `output` (written atomically; with options.share, the share's tiles
// into its part file instead, and nothing when it has none of the pyramid's; with
// options.region, the region's tiles into the region file `output`, without the companions, and
// the report then describes that file) with the options' scale (or the
// automatic one), threads, progress and reconstruction hook, and fills `report`. Throws Error
// on int16 overflow (naming the smallest scale that would fit) and when no sample is valid.
void encodeResidualPyramid(const ResidualPyramidJob& job, const std::string& output,
                           const ResidualEncodeOptions& options, ResidualPyramidReport& report);

} // namespace pyramid
