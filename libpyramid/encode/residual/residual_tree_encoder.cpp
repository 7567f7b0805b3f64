// The residual tree encoder's top (residual_tree_encoder.hpp): where its tiles go, and levels
// 0..C encoded level by level from the in-memory grid, each level's tiles in parallel.
#include "libpyramid/encode/residual/residual_tree_encoder.hpp"

#include <algorithm>
#include <cstdint>

#include "libpyramid/encode/residual/residual_parts.hpp"
#include "libpyramid/encode/residual/residual_reach.hpp"
#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

using Overflow = ResidualOverflow;

} // namespace

void TileSink::put(const EncodedTile& t) const {
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

int64_t ResidualTreeEncoder::tiles() const {
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

std::optional<Overflow> ResidualTreeEncoder::run(const TileSink& sink, std::vector<LevelStats>& stats,
                                                 int64_t& nodataFilled) {
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

// Whether the tile is recorded: every tile, or the region's.
bool ResidualTreeEncoder::holds(int l, int tx, int ty) const { return !region_ || regionHolds(*region_, l, tx, ty); }

// Whether the tile is encoded: the region's tiles and their ancestors (whose reconstructions
// they are predicted from).
bool ResidualTreeEncoder::needed(int l, int tx, int ty) const {
    return holds(l, tx, ty) ||
           (l < region_->level && regionHolds(RegionRoot{l, tx, ty}, region_->level, region_->tx, region_->ty));
}

// The finest samples tile (l, tx, ty) (l >= minLevel) owns, the map's far edges included,
// within the region's when there is one.
SampleBox ResidualTreeEncoder::owned(int l, int tx, int ty) const {
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

// Whether subtree (l, tx, ty) (l > C) is encoded from its samples and its parent's
// reconstruction. A subtree no valid height can reach (a face beyond a small map) is all
// residual 0, exactly what encoding its all-nodata samples gives, without sampling it or
// its parent. With the reconstruction hook every tile is encoded, as the hook wants each one.
bool ResidualTreeEncoder::encodesSamples(int l, int tx, int ty) const {
    return options_.reconstruction || tileReached(plan_, sampler_, l, tx, ty);
}

// Whether the reconstruction of level-C tile (tx, ty) is a parent the range's subtrees need.
bool ResidualTreeEncoder::parentOfSubtrees(int tx, int ty) const {
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

void ResidualTreeEncoder::write(const TileSink& sink, const EncodedTile& t, std::vector<LevelStats>& stats) {
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

} // namespace pyramid
