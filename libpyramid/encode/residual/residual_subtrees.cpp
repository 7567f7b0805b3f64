// The residual tree encoder's subtrees below level C (residual_tree_encoder.hpp): each sampled
// from its own footprint where heights can be, encoded depth first, handed out to the threads and
// written in Z order; a region's alone from its parent's reconstruction.
#include "libpyramid/encode/residual/residual_tree_encoder.hpp"

#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "libpyramid/encode/residual/residual_reach.hpp"
#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/ordered_writer.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

using Overflow = ResidualOverflow;

} // namespace

// The finest samples subtree (l, tx, ty) is encoded from: its root tile with 2 border samples
// of level l beyond each edge; clamped to the map unless edges are folded.
SampleBox ResidualTreeEncoder::footprintBox(int l, int tx, int ty) const {
    return pyramid::footprintBox(plan_, l, tx, ty);
}

void ResidualTreeEncoder::encodeSubtree(int l, int tx, int ty, const std::vector<float>& parent,
                                        const SourceGrid& footprint, std::vector<EncodedTile>& out) {
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
void ResidualTreeEncoder::sampleReachable(SourceGrid& footprint) const {
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
void ResidualTreeEncoder::emptySubtree(int l, int tx, int ty, std::vector<EncodedTile>& out) {
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
ResidualTreeEncoder::Subtree ResidualTreeEncoder::encodeRooted(int l, int tx, int ty, const std::vector<float>& parent,
                                                               SourceGrid& footprint) {
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
std::optional<Overflow> ResidualTreeEncoder::runRegion(const TileSink& sink, std::vector<LevelStats>& stats,
                                                       int64_t& nodataFilled) {
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
std::optional<Overflow> ResidualTreeEncoder::runSubtrees(const TileSink& sink, std::vector<LevelStats>& stats,
                                                         const std::vector<std::vector<float>>& levelC,
                                                         int64_t& nodataFilled) {
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

} // namespace pyramid
