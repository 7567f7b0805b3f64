#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>

#include "formats/error.hpp"
#include "formats/residual_set.hpp"
#include "formats/sparse_set.hpp"
#include "libpyramid/encode/residual/residual_parts.hpp"
#include "libpyramid/encode/residual/residual_reach.hpp"
#include "libpyramid/encode/residual/residual_region_plan.hpp"
#include "libpyramid/encode/residual/residual_tile.hpp"
#include "libpyramid/encode/residual/root_fill.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/ordered_writer.hpp"
#include "libpyramid/support/parallel.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

void ResidualEncodeOptions::validate() const {
    if (!autoScale && (!std::isfinite(scale) || scale <= 0.0)) {
        failOption("scale", "must be a positive number, not " + numberText(scale));
    }
    workerThreads(threads); // refuses a count out of range
    tiles.validate();
}

namespace {

// Subtrees encoded at once, in the memory estimate of cutLevel (a constant, not the thread
// count: the cut decides the tile order in the file, which must not depend on the threads).
constexpr int64_t kSubtreesInFlight = 4;

// The cut-off level C: levels 0..C are encoded from a grid of every 2^(M-C)-th finest sample
// held in memory, the deeper ones subtree by subtree from level-(C+1) footprints read on
// demand. C minimises the samples held at once: the grid (counted twice: its heights and the
// level-C reconstructions) plus kSubtreesInFlight footprints; C = M (everything in memory) is a
// candidate too, and wins for small pyramids. Subtree roots need a quadrant parent: C >= minLevel.
int cutLevel(int minLevel, int maxLevel, int tileSize, int64_t N) {
    int best = maxLevel;
    double bestSamples = static_cast<double>(N + 1) * static_cast<double>(N + 1);
    for (int c = maxLevel - 1; c >= minLevel; --c) {
        const double grid = static_cast<double>((N >> (maxLevel - c)) + 1);
        const double footprint = static_cast<double>((static_cast<int64_t>(tileSize + 4) << (maxLevel - c - 1)) + 1);
        const double samples = 2.0 * grid * grid + static_cast<double>(kSubtreesInFlight) * footprint * footprint;
        if (samples < bestSamples) {
            best = c;
            bestSamples = samples;
        }
    }
    return best;
}

// The smallest 1, 2 or 5 x 10^k that is >= x.
double niceCeil(double x) {
    if (!(x > 0.0)) {
        return 0.0;
    }
    const double p = std::pow(10.0, std::floor(std::log10(x)));
    for (double m : {1.0, 2.0, 5.0, 10.0}) {
        if (m * p >= x * (1.0 - 1e-12)) {
            return m * p;
        }
    }
    return 10.0 * p;
}

// x rounded up to 3 significant digits, as messages print it ("0.239", "1.25e+04").
std::string roundUp3(double x) {
    const double p = std::pow(10.0, std::floor(std::log10(x)) - 2.0);
    return numberText(std::ceil(x / p - 1e-9) * p);
}

using Overflow = ResidualOverflow;

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

    void put(const EncodedTile& t) const {
        if (log) {
            if (t.emptySubtree) {
                log->addEmptySubtree(t.level, t.tx, t.ty);
            } else {
                log->add(t.level, t.tx, t.ty, t.blob);
            }
        } else if (part && t.emptySubtree) {
            part->add(stream, t.level, t.tx, t.ty, {}, *partEmpty);
        } else if (part) {
            part->add(stream, t.level, t.tx, t.ty, packLevelStats(t.stats), t.blob);
        } else if (region) {
            const RegionRoot r = regionRelativeTile(*region, t.level, t.tx, t.ty);
            writer->writeTileBytes(r.level, r.tx, r.ty, t.blob);
        } else {
            writer->writeTileBytes(t.level, t.tx, t.ty, t.blob);
        }
    }
};

class Encoder {
public:
    // With `region`, only the region's tiles are recorded (the range then holds the subtrees
    // that reach it); with `regionParent` as well (the reconstruction of the root's parent, a
    // root below level C), the region is encoded from it alone, without the top levels.
    Encoder(const ResidualPlan& plan, const HeightSource& sampler, SourceGrid& grid, const ResidualEncodeOptions& options,
            int threads, const std::string& input, const ShareRange& range, const RegionRoot* region = nullptr,
            const std::vector<float>* regionParent = nullptr, bool sparse = false)
        : plan_(plan), sampler_(sampler), grid_(grid), options_(options), threads_(threads), input_(input), range_(range),
          region_(region), regionParent_(regionParent), sparse_(sparse) {}

    // The tiles the range records.
    int64_t tiles() const {
        if (region_) {
            const int d = plan_.M - region_->level;
            return ((int64_t{1} << (2 * (d + 1))) - 1) / 3;
        }
        if (plan_.C == plan_.M) {
            return range_.top ? plan_.header.tileCount() : 0;
        }
        int64_t top = 0;
        for (int l = 0; l <= plan_.C; ++l) {
            top += static_cast<int64_t>(plan_.tilesPerSide(l)) * plan_.tilesPerSide(l);
        }
        const int d = plan_.M - plan_.C - 1;
        const int64_t subtree = ((int64_t{1} << (2 * (d + 1))) - 1) / 3;
        return (range_.top ? top : 0) + (range_.end - range_.begin) * subtree;
    }

    // Encodes the range's tiles at plan_.scale into `sink`; returns the first overflow, if any.
    std::optional<Overflow> run(const TileSink& sink, std::vector<LevelStats>& stats, int64_t& nodataFilled) {
        stats.assign(static_cast<size_t>(plan_.M) + 1, LevelStats{});
        total_ = tiles();
        done_ = 0;
        if (regionParent_) {
            return runRegion(sink, stats, nodataFilled);
        }
        std::vector<std::vector<float>> previous;
        // A sparse output's tiles no valid height reaches (row by row per level): the highest of
        // them is given as an empty subtree, the ones below it not at all.
        std::vector<uint8_t> unreachedAbove;
        for (int l = 0; l <= plan_.C; ++l) {
            const int side = plan_.tilesPerSide(l);
            const int64_t count = static_cast<int64_t>(side) * side;
            std::vector<EncodedTile> tiles(static_cast<size_t>(count));
            std::vector<uint8_t> unreached(sparse_ ? static_cast<size_t>(count) : 0, 0);
            parallelFor(count, threads_, [&](int64_t m) {
                const auto [tx, ty] = mortonDecode(static_cast<uint64_t>(m));
                const std::vector<float>* parent = nullptr;
                const int pside = l > 0 ? plan_.tilesPerSide(l - 1) : 1;
                const size_t parentAt = l <= plan_.minLevel ? 0 : static_cast<size_t>((ty / 2) * pside + tx / 2);
                if (l > 0) {
                    parent = &previous[parentAt];
                }
                EncodedTile& t = tiles[static_cast<size_t>(m)];
                t.level = l;
                t.tx = static_cast<int>(tx);
                t.ty = static_cast<int>(ty);
                if (sparse_ && l >= std::max(1, plan_.minLevel)) {
                    const size_t at = static_cast<size_t>(ty * side + tx);
                    if (l > plan_.minLevel && unreachedAbove[parentAt]) {
                        t.skipped = true;
                        unreached[at] = 1;
                        return;
                    }
                    if (!tileReached(plan_, sampler_, l, t.tx, t.ty)) {
                        t.emptySubtree = true;
                        unreached[at] = 1;
                        return;
                    }
                }
                t = encodeResidualTile(plan_, l, static_cast<int>(tx), static_cast<int>(ty), parent, grid_);
                if (l == plan_.C && plan_.C < plan_.M && !options_.reconstruction &&
                    !parentOfSubtrees(static_cast<int>(tx), static_cast<int>(ty))) {
                    // Level C's reconstructions are held through every subtree: only the parents
                    // of subtrees encoded from their samples.
                    t.recon.clear();
                    t.recon.shrink_to_fit();
                }
            });
            std::vector<std::vector<float>> current(static_cast<size_t>(count));
            int64_t overflow = 0;
            for (EncodedTile& t : tiles) {
                if (t.skipped) {
                    continue;
                }
                if (range_.top && holds(t.level, t.tx, t.ty)) {
                    write(sink, t, stats);
                }
                overflow = std::max(overflow, t.stats.overflowResidual);
                current[static_cast<size_t>(t.ty * side + t.tx)] = std::move(t.recon);
            }
            if (overflow) {
                return Overflow{plan_.scale, overflow, l, -1};
            }
            previous = std::move(current);
            unreachedAbove = std::move(unreached);
        }
        if (plan_.C == plan_.M) {
            if (!range_.top) {
                return std::nullopt;
            }
            const SampleBox box = region_ ? owned(region_->level, region_->tx, region_->ty)
                                          : SampleBox{0, 0, plan_.N + 1, plan_.N + 1};
            for (int64_t y = box.y0; y < box.y1; ++y) {
                const uint8_t* valid = grid_.valid.data() + grid_.index(box.x0, y);
                nodataFilled += (box.x1 - box.x0) - std::count(valid, valid + (box.x1 - box.x0), uint8_t{1});
            }
            return std::nullopt;
        }
        // The subtrees read their own footprints: the grid's memory goes back before theirs is
        // taken (the caller samples it again for another attempt).
        grid_ = SourceGrid{};
        unreachedC_ = std::move(unreachedAbove);
        return runSubtrees(sink, stats, previous, nodataFilled);
    }

private:
    struct Subtree {
        std::vector<EncodedTile> tiles;
        int64_t filled = 0;
    };

    // Whether the tile is recorded: every tile, or the region's.
    bool holds(int l, int tx, int ty) const { return !region_ || regionHolds(*region_, l, tx, ty); }
    // Whether the tile is encoded: the region's tiles and their ancestors (whose reconstructions
    // they are predicted from).
    bool needed(int l, int tx, int ty) const {
        return holds(l, tx, ty) ||
               (l < region_->level && regionHolds(RegionRoot{l, tx, ty}, region_->level, region_->tx, region_->ty));
    }

    // The finest samples tile (l, tx, ty) (l >= minLevel) owns, the map's far edges included,
    // within the region's when there is one.
    SampleBox owned(int l, int tx, int ty) const {
        const int d = plan_.M - l;
        const int64_t T = plan_.T;
        SampleBox b{static_cast<int64_t>(tx) * T << d, static_cast<int64_t>(ty) * T << d,
                    (static_cast<int64_t>(tx) + 1) * T << d, (static_cast<int64_t>(ty) + 1) * T << d};
        if (region_) {
            const int rd = plan_.M - region_->level;
            b.x0 = std::max(b.x0, static_cast<int64_t>(region_->tx) * T << rd);
            b.y0 = std::max(b.y0, static_cast<int64_t>(region_->ty) * T << rd);
            b.x1 = std::min(b.x1, (static_cast<int64_t>(region_->tx) + 1) * T << rd);
            b.y1 = std::min(b.y1, (static_cast<int64_t>(region_->ty) + 1) * T << rd);
        }
        b.x1 += b.x1 == plan_.N ? 1 : 0;
        b.y1 += b.y1 == plan_.N ? 1 : 0;
        return b;
    }

    // The finest samples subtree (l, tx, ty) is encoded from: its root tile with 2 border samples
    // of level l beyond each edge; clamped to the map unless edges are folded.
    SampleBox footprintBox(int l, int tx, int ty) const { return pyramid::footprintBox(plan_, l, tx, ty); }

    // Whether subtree (l, tx, ty) (l > C) is encoded from its samples and its parent's
    // reconstruction. A subtree no valid height can reach (a face beyond a small map) is all
    // residual 0, exactly what encoding its all-nodata samples gives, without sampling it or
    // its parent. With the reconstruction hook every tile is encoded, as the hook wants each one.
    bool encodesSamples(int l, int tx, int ty) const {
        return options_.reconstruction || tileReached(plan_, sampler_, l, tx, ty);
    }

    // Whether the reconstruction of level-C tile (tx, ty) is a parent the range's subtrees need.
    bool parentOfSubtrees(int tx, int ty) const {
        for (int c = 0; c < 4; ++c) {
            const uint32_t cx = 2 * static_cast<uint32_t>(tx) + static_cast<uint32_t>(c & 1);
            const uint32_t cy = 2 * static_cast<uint32_t>(ty) + static_cast<uint32_t>(c >> 1);
            const auto m = static_cast<int64_t>(mortonEncode(cx, cy));
            if (m >= range_.begin && m < range_.end &&
                encodesSamples(plan_.C + 1, static_cast<int>(cx), static_cast<int>(cy))) {
                return true;
            }
        }
        return false;
    }

    void write(const TileSink& sink, const EncodedTile& t, std::vector<LevelStats>& stats) {
        sink.put(t);
        if (options_.reconstruction) {
            options_.reconstruction(t.level, t.tx, t.ty, t.recon);
        }
        stats[static_cast<size_t>(t.level)].merge(t.stats);
        done_ += t.emptySubtree ? subtreeTiles(plan_.M, t.level) : 1;
        if (options_.progress) {
            options_.progress(done_, total_);
        }
        if (options_.cancelled && options_.cancelled()) {
            throw Cancelled(input_ + ": cancelled");
        }
    }

    void encodeSubtree(int l, int tx, int ty, const std::vector<float>& parent, const SourceGrid& footprint,
                       std::vector<EncodedTile>& out) {
        if (region_ && !needed(l, tx, ty)) {
            return;
        }
        EncodedTile tile = encodeResidualTile(plan_, l, tx, ty, &parent, footprint);
        // The children's parent; the tile keeps its reconstruction only for the hook, so that
        // memory stays per subtree.
        std::vector<float> recon;
        if (l < plan_.M) {
            recon = options_.reconstruction ? tile.recon : std::move(tile.recon);
        }
        if (!options_.reconstruction) {
            tile.recon.clear();
            tile.recon.shrink_to_fit();
        }
        if (holds(l, tx, ty)) {
            out.push_back(std::move(tile));
        }
        if (l < plan_.M) {
            for (int c = 0; c < 4; ++c) {
                const int cx = 2 * tx + (c & 1), cy = 2 * ty + (c >> 1);
                if (!encodesSamples(l + 1, cx, cy)) {
                    // All residual 0, as its all-nodata samples would give: not encoded.
                    emptySubtree(l + 1, cx, cy, out);
                } else {
                    encodeSubtree(l + 1, cx, cy, recon, footprint, out);
                }
            }
        }
    }

    // Samples `footprint` where valid heights can be: in one call when they can be anywhere (or
    // with the reconstruction hook); else block by block, the blocks no valid height reaches left
    // nodata (what sampling them gives), their rows not stored where no block of theirs is.
    void sampleReachable(SourceGrid& footprint) const {
        const int64_t across = (footprint.nx + kReachBlock - 1) / kReachBlock;
        const int64_t down = (footprint.ny + kReachBlock - 1) / kReachBlock;
        // One thread: this runs on a subtree's thread.
        const std::vector<uint8_t> reachable =
            reachableBlocks(footprint, sampler_, static_cast<bool>(options_.reconstruction), 1);
        const auto at = [&](int64_t i) { return footprint.x0 + i * footprint.stride; };
        const auto atY = [&](int64_t j) { return footprint.y0 + j * footprint.stride; };
        if (std::all_of(reachable.begin(), reachable.end(), [](uint8_t r) { return r != 0; })) {
            footprint.rows.clear();
            sampler_.sample(footprint);
            return;
        }
        allocateReachableRows(footprint, reachable, 0);
        SourceGrid block;
        block.stride = footprint.stride;
        for (int64_t by = 0; by < down; ++by) {
            for (int64_t bx = 0; bx < across; ++bx) {
                if (!reachable[static_cast<size_t>(by * across + bx)]) {
                    continue;
                }
                block.x0 = at(bx * kReachBlock);
                block.y0 = atY(by * kReachBlock);
                block.nx = std::min(footprint.nx, (bx + 1) * kReachBlock) - bx * kReachBlock;
                block.ny = std::min(footprint.ny, (by + 1) * kReachBlock) - by * kReachBlock;
                sampler_.sample(block);
                for (int64_t j = 0; j < block.ny; ++j) {
                    const size_t to = footprint.index(block.x0, block.y0 + j * block.stride);
                    const size_t from = static_cast<size_t>(j * block.nx);
                    std::copy_n(block.height.begin() + static_cast<std::ptrdiff_t>(from), block.nx,
                                footprint.height.begin() + static_cast<std::ptrdiff_t>(to));
                    std::copy_n(block.valid.begin() + static_cast<std::ptrdiff_t>(from), block.nx,
                                footprint.valid.begin() + static_cast<std::ptrdiff_t>(to));
                }
            }
        }
    }

    // The tiles of a subtree without valid heights, in encodeSubtree's order: residuals 0.
    void emptySubtree(int l, int tx, int ty, std::vector<EncodedTile>& out) {
        if (region_ && !needed(l, tx, ty)) {
            return;
        }
        if (sparse_) {
            EncodedTile marker;
            marker.level = l;
            marker.tx = tx;
            marker.ty = ty;
            marker.emptySubtree = true;
            out.push_back(std::move(marker));
            return;
        }
        std::call_once(zeroBlobOnce_, [this] { zeroBlob_ = zeroResidualBlob(plan_.T + 5, plan_.coding); });
        EncodedTile tile;
        tile.level = l;
        tile.tx = tx;
        tile.ty = ty;
        tile.blob = zeroBlob_;
        if (holds(l, tx, ty)) {
            out.push_back(std::move(tile));
        }
        if (l < plan_.M) {
            for (int c = 0; c < 4; ++c) {
                emptySubtree(l + 1, 2 * tx + (c & 1), 2 * ty + (c >> 1), out);
            }
        }
    }

    // The tiles of the subtree rooted at tile (l, tx, ty) (l > C), encoded from `parent`, the
    // reconstruction of its parent tile, and the finest samples of its footprint (the root tile
    // with its borders), sampled into `footprint`; with the owned samples that were filled.
    Subtree encodeRooted(int l, int tx, int ty, const std::vector<float>& parent, SourceGrid& footprint) {
        Subtree result;
        const SampleBox f = footprintBox(l, tx, ty);
        footprint.stride = 1;
        footprint.x0 = f.x0;
        footprint.y0 = f.y0;
        footprint.nx = f.x1 - f.x0;
        footprint.ny = f.y1 - f.y0;
        // Finest samples this subtree owns (of the region's, with one).
        const SampleBox box = owned(l, tx, ty);
        if (!encodesSamples(l, tx, ty)) {
            result.filled = (box.y1 - box.y0) * (box.x1 - box.x0);
            emptySubtree(l, tx, ty, result.tiles);
            return result;
        }
        sampleReachable(footprint);
        for (int64_t fy = box.y0; fy < box.y1; ++fy) {
            const uint8_t* valid = footprint.valid.data() + footprint.index(box.x0, fy);
            result.filled += std::count(valid, valid + (box.x1 - box.x0), uint8_t{0});
        }
        encodeSubtree(l, tx, ty, parent, footprint, result.tiles);
        return result;
    }

    // The region alone from its root's parent reconstruction: its subtree in one piece.
    std::optional<Overflow> runRegion(const TileSink& sink, std::vector<LevelStats>& stats, int64_t& nodataFilled) {
        SourceGrid footprint;
        Subtree subtree = encodeRooted(region_->level, region_->tx, region_->ty, *regionParent_, footprint);
        nodataFilled += subtree.filled;
        int64_t overflow = 0;
        int overflowLevel = 0;
        for (const EncodedTile& t : subtree.tiles) {
            write(sink, t, stats);
            if (t.stats.overflowResidual > overflow) {
                overflow = t.stats.overflowResidual;
                overflowLevel = t.level;
            }
        }
        if (overflow) {
            return Overflow{plan_.scale, overflow, overflowLevel, 0};
        }
        return std::nullopt;
    }

    // Subtrees go to the threads in Z order and are written in Z order by the ordered writer
    // while later ones are encoded. At most `window` subtrees' tiles are held at once.
    // Subtrees range_.begin to range_.end - 1; item i of the ordered writer is subtree begin + i.
    std::optional<Overflow> runSubtrees(const TileSink& sink, std::vector<LevelStats>& stats,
                                        const std::vector<std::vector<float>>& levelC, int64_t& nodataFilled) {
        const int top = plan_.C + 1;
        const int cside = plan_.tilesPerSide(plan_.C);
        const int64_t first = range_.begin;
        // A sparse output visits only the subtrees under reached level-C tiles (whole groups of 4
        // siblings): the others are under an empty subtree given above, their samples nodata.
        std::vector<int64_t> active;
        if (sparse_) {
            for (int64_t m = range_.begin; m < range_.end; ++m) {
                const auto [tx, ty] = mortonDecode(static_cast<uint64_t>(m));
                if (!unreachedC_[static_cast<size_t>((ty / 2) * cside + tx / 2)]) {
                    active.push_back(m);
                } else {
                    const SampleBox box = owned(top, static_cast<int>(tx), static_cast<int>(ty));
                    nodataFilled += (box.y1 - box.y0) * (box.x1 - box.x0);
                }
            }
        }
        const int64_t count = sparse_ ? static_cast<int64_t>(active.size()) : range_.end - range_.begin;
        const auto subtreeAt = [&](int64_t i) { return sparse_ ? active[static_cast<size_t>(i)] : first + i; };
        int64_t overflow = 0; // the writer's: the largest |residual| beyond int16 so far
        int overflowLevel = 0;
        int64_t overflowEnd = 0;
        OrderedWriter<Subtree> ordered(
            std::max<int64_t>(kSubtreesInFlight, 2 * threads_), [&](int64_t i, Subtree& subtree) {
                const int64_t m = subtreeAt(i);
                nodataFilled += subtree.filled;
                for (const EncodedTile& t : subtree.tiles) {
                    write(sink, t, stats);
                    if (t.stats.overflowResidual > overflow) {
                        overflow = t.stats.overflowResidual;
                        overflowLevel = t.level;
                    }
                }
                // An overflow ends the encoding at the end of its group of kSubtreesInFlight
                // subtrees (the overflow reported is the group's largest), whatever the threads
                // (and the parts: a share is whole groups).
                if (overflow && !overflowEnd && ((m + 1) % kSubtreesInFlight == 0 || i + 1 == count)) {
                    overflowEnd = m + 1;
                    ordered.stopAt(i + 1);
                }
            });
        std::vector<SourceGrid> footprints(static_cast<size_t>(threads_));
        parallelFor(count, threads_, [&](int64_t i) {
            if (!ordered.admit(i)) {
                return;
            }
            const int64_t m = subtreeAt(i);
            Subtree result;
            try {
                const auto [tx, ty] = mortonDecode(static_cast<uint64_t>(m));
                // Each thread reuses its footprint's buffers from subtree to subtree: no fresh
                // pages (faults, zeroing) per subtree.
                SourceGrid& footprint = footprints[static_cast<size_t>(omp_get_thread_num())];
                const std::vector<float>& parent = levelC[static_cast<size_t>((ty / 2) * cside + tx / 2)];
                result = encodeRooted(top, static_cast<int>(tx), static_cast<int>(ty), parent, footprint);
            } catch (...) {
                ordered.stopAt(i);
                throw;
            }
            ordered.deliver(i, std::move(result));
        });
        ordered.finish(count);
        if (overflow) {
            return Overflow{plan_.scale, overflow, overflowLevel, overflowEnd};
        }
        return std::nullopt;
    }

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

// The scale the next attempt takes after `overflow` with an automatic scale; the error otherwise
// (and for a part of a split build that cannot agree with the others on a new scale).
double nextScale(const Overflow& overflow, const ResidualEncodeOptions& options, const std::string& input, int attempt,
                 bool alone) {
    const double needed = overflow.scale * static_cast<double>(overflow.residual) / 32767.0;
    const std::string what = "residuals of " + input + " overflow int16 at scale " + numberText(overflow.scale) +
                             " (|residual| " + std::to_string(overflow.residual) + " at level " +
                             std::to_string(overflow.level) + ")";
    if (alone && options.autoScale) {
        failOption("scale", what + " in this part: a part cannot raise the scale alone; run every part again with --scale " +
                                numberText(niceCeil(std::max(needed, overflow.scale * 1.000001))));
    }
    if (!options.autoScale || attempt >= 12) {
        failOption("scale", what + ": use " + roundUp3(needed) + " or more (a largest error of " + roundUp3(needed / 2.0) +
                                ", half the scale), or auto");
    }
    return niceCeil(std::max(needed, overflow.scale * 1.000001));
}

} // namespace

void encodeResidualPyramid(const ResidualPyramidJob& job, const std::string& output,
                           const ResidualEncodeOptions& options, ResidualPyramidReport& report) {
    options.validate();
    ResidualPlan plan;
    plan.header = job.header;
    plan.M = plan.header.maxLevel;
    plan.minLevel = plan.header.minLevel;
    plan.T = plan.header.tileSize;
    plan.R = plan.T >> plan.minLevel;
    plan.N = plan.levelIntervals(plan.M);
    plan.C = cutLevel(plan.minLevel, plan.M, plan.T, plan.N);
    plan.folded = job.edges == GridEdges::Folded;
    plan.coding = options.tiles;
    const int threads = workerThreads(options.threads);
    report.threads = threads;
    const ResidualShare* share = options.share;
    const int64_t units = plan.C == plan.M ? 1
                                           : static_cast<int64_t>(plan.tilesPerSide(plan.C + 1)) * plan.tilesPerSide(plan.C + 1);
    std::optional<RegionBuild> region;
    if (options.region) {
        region = planRegion(plan, options);
    }
    const ShareRange range = share    ? shareRange(share->index, share->count, job.pyramid, job.pyramids, units)
                             : region ? region->range
                                      : ShareRange{0, units, true};
    report.header = region ? region->header : plan.header;
    if (!range.active()) {
        // Nothing of this pyramid is this part's: it only follows the build's attempts.
        for (int attempt = 0; share->agree; ++attempt) {
            const std::optional<Overflow> overflow = share->agree(std::nullopt);
            if (!overflow) {
                break;
            }
            nextScale(*overflow, options, job.input, attempt, false);
        }
        return;
    }

    // A region encoded from its parent's reconstruction reads only its own subtree's samples.
    // The grid is released once levels 0..C are encoded (Encoder::run): an attempt at another
    // scale samples it again.
    const bool gridNeeded = !region || !region->fromParent;
    // Sparse files where the heights leave part of the pyramid empty (formats/sparse_set.hpp).
    const bool sparse = options.layout == PyramidLayout::Sparse && !region && !options.reconstruction &&
                        !reachesEverywhere(plan, *job.heights, threads);
    if (!sparse && !region && plan.header.tileCount() > kMaxDenseTiles) {
        // Every tile of a dense file holds offsets and a hash in memory: a bound that keeps a
        // mistyped maxLevel from exhausting it.
        failOption("maxLevel", "maxLevel " + std::to_string(plan.M) + " makes " +
                                   std::to_string(plan.header.tileCount()) + " tiles, more than " +
                                   std::to_string(kMaxDenseTiles) + " in one file, and the heights reach all of them");
    }
    SourceGrid grid;
    if (gridNeeded) {
        grid = sampleLevelGrid(plan, job, options, threads);
    }

    double scale = options.scale;
    if (region && region->parentScale) {
        scale = *region->parentScale; // the build's (the parent's) scale, fixed
    } else if (options.autoScale) {
        double maxAbs = 0.0;
        for (size_t s = 0; s < grid.height.size(); ++s) {
            if (grid.valid[s]) {
                maxAbs = std::max(maxAbs, std::fabs(static_cast<double>(grid.height[s])));
            }
        }
        scale = std::max(niceCeil(maxAbs / 32767.0), 0.001);
    }
    const uint64_t partStart = share ? share->out->file().position() : 0;
    std::vector<uint8_t> partEmpty;
    for (int attempt = 0;; ++attempt) {
        plan.scale = static_cast<float>(scale);
        plan.header.scale = plan.scale;
        report.scalesTried.push_back(scale);
        std::vector<LevelStats> stats;
        int64_t nodataFilled = 0;
        std::unique_ptr<ResidualOutput> out;
        TileSink sink;
        if (share) {
            share->out->file().rewind(partStart);
            sink.part = &share->out->file();
            sink.stream = static_cast<uint32_t>(job.pyramid);
            if (sparse) {
                partEmpty = zeroResidualBlob(plan.T + 5, plan.coding);
                sink.partEmpty = &partEmpty;
            }
        } else if (region) {
            region->header.scale = plan.scale;
            out = std::make_unique<ResidualOutput>(output, region->header, 0, true);
            sink.writer = &out->writer();
            sink.region = &region->root;
        } else if (sparse) {
            out = std::make_unique<ResidualOutput>(output, plan.header, options.maxFileBytes,
                                                   ResidualOutput::Sparse{zeroResidualBlob(plan.T + 5, plan.coding)});
            sink.log = out->log();
        } else {
            out = std::make_unique<ResidualOutput>(output, plan.header, options.maxFileBytes);
            sink.writer = &out->writer();
        }
        if (gridNeeded && grid.height.empty()) {
            grid = sampleLevelGrid(plan, job, options, threads); // released by the attempt before
        }
        Encoder encoder(plan, *job.heights, grid, options, threads, job.input, range, region ? &region->root : nullptr,
                        region && region->fromParent ? &region->parentRecon : nullptr, sparse);
        std::optional<Overflow> overflow = encoder.run(sink, stats, nodataFilled);
        if (share && share->agree) {
            overflow = share->agree(overflow);
        }
        if (overflow && region && region->parentScale) {
            // The parent fixes the scale: a region cannot raise it alone.
            ResidualEncodeOptions fixed = options;
            fixed.autoScale = false;
            nextScale(*overflow, fixed, job.input, attempt, false);
        }
        if (overflow) {
            scale = nextScale(*overflow, options, job.input, attempt, share && !share->agree && overflow->position >= 0);
            continue;
        }
        report.header = plan.header;
        report.tiles = encoder.tiles();
        report.finestSamples = (plan.N + 1) * (plan.N + 1);
        report.nodataFilled = nodataFilled;
        report.levels = residualLevelReports(plan.header, stats);
        if (region) {
            // The region file's levels, counted from its root, and its finest samples.
            const int L = region->root.level;
            report.header = region->header;
            const int64_t n = (static_cast<int64_t>(plan.T) << (plan.M - L)) + 1;
            report.finestSamples = n * n;
            report.levels = residualLevelReports(
                region->header, std::vector<LevelStats>(stats.begin() + L, stats.end()));
        }
        if (share) {
            nlohmann::json companions = nlohmann::json::object();
            for (const CompanionFile& c : job.companions) {
                companions[c.name] = c.text;
            }
            share->out->addPyramid({{"pyramid", job.pyramid},
                                    {"pyramids", job.pyramids},
                                    {"name", std::filesystem::path(output).filename().string()},
                                    {"header", residualHeaderJson(plan.header)},
                                    {"units", units},
                                    {"begin", range.begin},
                                    {"end", range.end},
                                    {"top", range.top},
                                    {"records", {partStart, share->out->file().position()}},
                                    {"tiles", report.tiles},
                                    {"nodata_filled", nodataFilled},
                                    {"finest_samples", report.finestSamples},
                                    {"scales_tried", report.scalesTried},
                                    {"max_file_bytes", options.maxFileBytes},
                                    {"sparse", sparse},
                                    {"empty_tile", sparse ? hexText(partEmpty) : std::string()},
                                    {"companions", companions}});
            report.bytes = share->out->file().position() - partStart;
        } else {
            // A region file goes without the pyramid's companions (they describe the whole pyramid,
            // beside its main file).
            out->place(region ? std::vector<CompanionFile>{} : job.companions, report);
        }
        break;
    }
}

} // namespace pyramid
