// One attempt of the residual pyramid encoder (encodeResidualPyramid) at one scale: the tiles of
// levels 0..C encoded from the in-memory grid (residual_tree_encoder.cpp), then the subtrees below
// level C, each from its own footprint of finest samples, in Z order (residual_subtrees.cpp);
// all of them, a share's or a region's, into a TileSink.
#pragma once
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "formats/part_file.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "formats/sparse_set.hpp"
#include "libpyramid/encode/residual/height_source.hpp"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"
#include "libpyramid/encode/residual/residual_reach.hpp"
#include "libpyramid/encode/residual/residual_tile.hpp"
#include "libpyramid/support/work_share.hpp"

namespace pyramid {

// Subtrees encoded at once, in the memory estimate of cutLevel (a constant, not the thread
// count: the cut decides the tile order in the file, which must not depend on the threads).
inline constexpr int64_t kSubtreesInFlight = 4;

// Where an encoder's tiles go: a pyramid writer, a region file's (the tiles at the region's own
// coordinates), or a share's part file (with each tile's statistics, for the merge's report).
struct TileSink {
    ResidualFileWriter* writer = nullptr;
    PartFileWriter* part = nullptr;
    uint32_t stream = 0;
    const RegionRoot* region = nullptr;
    SparseTileLog* log = nullptr; // a sparse output: stored tiles and empty subtrees, logged
    // A sparse build's part: an empty subtree is a record of this blob without statistics.
    const std::vector<uint8_t>* partEmpty = nullptr;

    void put(const EncodedTile& t) const;
};

class ResidualTreeEncoder {
public:
    // With `region`, only the region's tiles are recorded (the range then holds the subtrees
    // that reach it); with `regionParent` as well (the reconstruction of the root's parent, a
    // root below level C), the region is encoded from it alone, without the top levels.
    ResidualTreeEncoder(const ResidualPlan& plan, const HeightSource& sampler, SourceGrid& grid,
                        const ResidualEncodeOptions& options, int threads, const std::string& input,
                        const ShareRange& range, const RegionRoot* region = nullptr,
                        const std::vector<float>* regionParent = nullptr, bool sparse = false)
        : plan_(plan), sampler_(sampler), grid_(grid), options_(options), threads_(threads), input_(input), range_(range),
          region_(region), regionParent_(regionParent), sparse_(sparse) {}

    // The tiles the range records.
    int64_t tiles() const;

    // Encodes the range's tiles at plan_.scale into `sink`; returns the first overflow, if any.
    std::optional<ResidualOverflow> run(const TileSink& sink, std::vector<LevelStats>& stats, int64_t& nodataFilled);

private:
    struct Subtree {
        std::vector<EncodedTile> tiles;
        int64_t filled = 0;
    };

    // Levels 0..C and what every tile asks (residual_tree_encoder.cpp).
    bool holds(int l, int tx, int ty) const;
    bool needed(int l, int tx, int ty) const;
    SampleBox owned(int l, int tx, int ty) const;
    bool encodesSamples(int l, int tx, int ty) const;
    bool parentOfSubtrees(int tx, int ty) const;
    void write(const TileSink& sink, const EncodedTile& t, std::vector<LevelStats>& stats);

    // The subtrees below level C (residual_subtrees.cpp).
    SampleBox footprintBox(int l, int tx, int ty) const;
    void encodeSubtree(int l, int tx, int ty, const std::vector<float>& parent, const SourceGrid& footprint,
                       std::vector<EncodedTile>& out);
    void sampleReachable(SourceGrid& footprint) const;
    void emptySubtree(int l, int tx, int ty, std::vector<EncodedTile>& out);
    Subtree encodeRooted(int l, int tx, int ty, const std::vector<float>& parent, SourceGrid& footprint);
    std::optional<ResidualOverflow> runRegion(const TileSink& sink, std::vector<LevelStats>& stats,
                                              int64_t& nodataFilled);
    std::optional<ResidualOverflow> runSubtrees(const TileSink& sink, std::vector<LevelStats>& stats,
                                                const std::vector<std::vector<float>>& levelC, int64_t& nodataFilled);

    const ResidualPlan& plan_;
    const HeightSource& sampler_;
    SourceGrid& grid_; // released once levels 0..C are encoded, when subtrees follow
    const ResidualEncodeOptions& options_;
    int threads_;
    const std::string& input_;
    ShareRange range_;
    const RegionRoot* region_;
    const std::vector<float>* regionParent_;
    bool sparse_ = false;
    std::vector<uint8_t> unreachedC_; // a sparse output's level-C tiles under or at an empty subtree
    int64_t total_ = 0;
    int64_t done_ = 0;
    std::once_flag zeroBlobOnce_;
    std::vector<uint8_t> zeroBlob_;
};

} // namespace pyramid
