// One ortho pyramid encoded from its true tiles (ortho_build.hpp): the options checked against
// the input, the walks (one, or two with colour residuals beside TIFF or DXT tiles), the writer
// that writes each item while later ones are encoded, and the outputs, a region's file or a
// share's records; whether the walk is pruned into sparse sets.
#include "libpyramid/encode/ortho/ortho_build.hpp"

#include <algorithm>
#include <atomic>
#include <future>
#include <limits>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/part_file.hpp"
#include "libpyramid/encode/ortho/ortho_item_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_kept_subtrees.hpp"
#include "libpyramid/encode/ortho/ortho_output.hpp"
#include "libpyramid/encode/ortho/ortho_outputs.hpp"
#include "libpyramid/encode/ortho/ortho_region.hpp"
#include "libpyramid/encode/ortho/ortho_tile_encoder.hpp"
#include "libpyramid/support/ordered_writer.hpp"
#include "libpyramid/support/text.hpp"
#include "libpyramid/support/work_share.hpp"

namespace pyramid {

namespace {

// The checks that need the input's channels and the tile size.
void checkAgainstInput(const OrthoEncodeOptions& o, const OrthoLevels& levels) {
    const int channels = levels.channels();
    if ((o.compression == TilePolicy::Jpeg || o.compression == TilePolicy::JpegYCbCr) && o.writeTiff && channels != 1 &&
        channels != 3) {
        failOption("compression", "JPEG tiles hold 1 or 3 channels, the input has " + std::to_string(channels));
    }
    if (o.residualCompression == TilePolicy::Jpeg && o.writeResiduals && channels != 1 && channels != 3) {
        failOption("residualCompression", "JPEG tiles hold 1 or 3 channels, the input has " + std::to_string(channels));
    }
    if (o.writeDxt && (levels.tileSize() + 2 * o.border) % 4 != 0) {
        failOption("tileSize", "DXT tiles need tile size + 2 x border to be a multiple of 4");
    }
}

// The outputs' headers and names, as part files record them.
nlohmann::json orthoOutputsJson(const OrthoLevels& levels, const OrthoEncodeOptions& o) {
    nlohmann::json list = nlohmann::json::array();
    const std::string file = o.name + ".dat";
    const uint32_t flags = o.border == 0 ? OrthoHeader::kFlagNoBorder : 0u;
    const auto add = [&](int slot, const std::string& name, int channels, uint32_t f) {
        list.push_back({{"slot", slot},
                        {"name", name},
                        {"max_level", levels.maxLevel()},
                        {"tile_size", levels.tileSize()},
                        {"channels", channels},
                        {"flags", f}});
    };
    if (o.writeTiff) {
        add(0, file, levels.channels(), flags);
    }
    if (o.writeDxt) {
        add(1, "dxt/" + file, std::max(3, levels.channels()), flags | OrthoHeader::kFlagDxt);
    }
    if (o.writeResiduals) {
        add(2, "residuals/" + file, levels.channels(), 0u);
    }
    return list;
}

} // namespace

OrthoReport encodeOrthoLevels(const OrthoLevels& levels, const std::string& directory, StagingDirectory* staging,
                              const OrthoEncodeOptions& o,
                              const std::vector<std::pair<std::string, std::string>>& companions,
                              std::chrono::steady_clock::time_point start) {
    checkAgainstInput(o, levels);
    OrthoReport report;
    report.input = levels.inputPath();
    report.directory = directory;
    report.sampling = levels.sampling();
    report.inputWidth = levels.inputWidth();
    report.inputHeight = levels.inputHeight();
    report.channels = levels.channels();
    report.tileSize = levels.tileSize();
    report.maxLevel = levels.maxLevel();
    report.border = o.border;
    report.threads = levels.threads();
    report.jpegErrorMeasured = o.measureJpegError;
    std::optional<OrthoRegionPlan> region;
    if (o.region) {
        region = planOrthoRegion(levels, o);
        report.region = region->root;
        report.maxLevel = levels.maxLevel() - region->root.level;
    }
    // Colour residuals predict each tile from its parent's rebuilt colours: parents first
    // (WalkOrder::CoarseFirst). Without them, tiles are independent, and the input is read once
    // (WalkOrder::SinglePass). With them and TIFF or DXT tiles, the build takes two walks of
    // the SinglePass order (doc/ortho-encoding.md): the first encodes every tile's TIFF and DXT
    // tiles, and levels 0..C whole; the second, the subtrees' residuals, against the
    // reconstruction of level C the first left. The subtrees of the first walk need no parent,
    // so they start on an input still being decoded; the TIFF and DXT files are those of a
    // build without residuals. Either way the input is sampled twice, as a CoarseFirst walk
    // does (once for levels 0..C, once for the subtrees), unless the first walk's subtrees are
    // kept for the second (KeptSubtrees).
    const bool twoWalks = !region && o.writeResiduals && (o.writeTiff || o.writeDxt) &&
                          levels.subtreeItems(OrthoLevels::WalkOrder::SinglePass) > 0;
    const auto order = region                            ? region->order
                       : o.writeResiduals && !twoWalks ? OrthoLevels::WalkOrder::CoarseFirst
                                                       : OrthoLevels::WalkOrder::SinglePass;
    const OrthoShare* share = o.share;
    // A face the input does not fill is walked pruned, into sparse sets (doc/format.md 1.5,
    // "Sparse sets"): blank subtrees are neither walked nor written. A plane, a region, and a
    // face the input reaches all over are walked whole, into the files of --layout dense.
    // An input of several resolutions is always walked pruned: its tiles stop where its parts' do.
    if (levels.severalLevels() && (region || o.layout == PyramidLayout::Dense)) {
        failOption(region ? "region" : "layout",
                   std::string(region ? "a region build" : "--layout dense") +
                       " needs every tile down to the finest level, and the input's parts have several resolutions "
                       "(the tiles stop where each part's resolution does): build it with --layout sparse");
    }
    const bool pruned = o.layout == PyramidLayout::Sparse && !region &&
                        (levels.severalLevels() || (levels.isFace() && !levels.reachesEveryTopTile()));
    const int64_t items = levels.subtreeItems(order, pruned);
    // A SinglePass walk gives the top levels after its subtrees: the share of the last one records them.
    const bool topLast = order == OrthoLevels::WalkOrder::SinglePass && items > 0;
    const int64_t units = std::max<int64_t>(1, items);
    ShareRange range{0, items, true};
    if (share) {
        range = shareRange(share->index, share->count, o.pyramid, o.pyramids, units);
        if (items == 0) {
            range.begin = range.end = 0; // the one unit is the top levels
        } else if (topLast) {
            range.top = range.begin < range.end && range.end == units; // the share of the last subtree
        }
    }
    const int topLevel = levels.topLevels(order);
    const int64_t topTiles = ((int64_t{1} << (2 * (topLevel + 1))) - 1) / 3;
    const int64_t subtreeTiles = ((int64_t{1} << (2 * (levels.maxLevel() - topLevel))) - 1) / 3;
    const int64_t total = region ? region->tiles
                          : share ? (range.top ? topTiles : 0) + (range.end - range.begin) * subtreeTiles
                                  : levels.tileCount();
    report.tiles = total; // a sparse output's: the tiles its files hold (below)
    if (share && !range.active()) {
        return report; // nothing of this pyramid is this share's
    }
    // Progress is given in tiles, of the work: two walks encode the subtrees' tiles twice, so
    // each of the `steps` tiles encoded moves it by total / steps of a tile; a pruned walk's
    // empty subtree moves it by the tiles it stands for (EncodedOrthoTile::covers).
    const int64_t steps = total + (twoWalks ? (range.end - range.begin) * subtreeTiles : 0);
    int64_t stepsDone = 0;
    std::unique_ptr<OrthoOutputs> outputs;
    if (!share) {
        outputs = std::make_unique<OrthoOutputs>(levels, directory, *staging, o, report,
                                                 region ? &region->root : nullptr, pruned);
    }
    const uint64_t recordsStart = share ? share->out->file().position() : 0;
    const nlohmann::json slots = orthoOutputsJson(levels, o);
    // A sparse build's parts carry each output's empty tile (hex, by slot) for the merge.
    nlohmann::json emptyTilesJson = nlohmann::json::array();
    if (share && pruned) {
        const EncodedOrthoTile blank = blankTileBytes(levels, o);
        for (const SharedBytes& b : {blank.tiff, blank.dxt, blank.residual}) {
            emptyTilesJson.push_back(hexText(bytesOf(b)));
        }
    }
    // The outputs of each walk's subtrees (levels 0..C always get every output).
    OrthoEncodeOptions pictures = o;
    pictures.writeResiduals = false;
    OrthoEncodeOptions residualsOnly = o;
    residualsOnly.writeTiff = residualsOnly.writeDxt = false;
    OrthoItemEncoder encoder(levels, o, twoWalks ? pictures : o);
    if (region && !region->parentRecon.empty()) {
        const RegionRoot& r = region->root;
        encoder.seed(r.level - 1, r.tx >> 1, r.ty >> 1, region->parentRecon);
    }
    std::vector<OrthoLevelTotals> totals(static_cast<size_t>(levels.maxLevel()) + 1);
    int64_t done = 0;

    // A share records the outputs `made` of a tile in each output's stream (pyramid x 3 +
    // slot), the tile's statistics with the first of them; an empty subtree of an output
    // (EncodedOrthoTile::picturesEmptyBelow, residualEmptyBelow) is a record of no bytes, and an
    // output a tile does not carry (a blank subtree's colour residual) has no record.
    const auto record = [&](const EncodedOrthoTile& e, OutputSet made, bool stats) {
        PartFileWriter& file = share->out->file();
        bool first = stats;
        for (const nlohmann::json& slot : slots) {
            const int k = slot["slot"].get<int>();
            if (!(k == 0 ? made.tiff : k == 1 ? made.dxt : made.residual)) {
                continue;
            }
            const SharedBytes& bytes = k == 0 ? e.tiff : k == 1 ? e.dxt : e.residual;
            const bool empty = k < 2 ? e.picturesEmptyBelow : e.residualEmptyBelow;
            if (!bytes && !empty) {
                continue;
            }
            const std::vector<uint8_t>& blob = bytesOf(bytes);
            file.add(static_cast<uint32_t>(o.pyramid * 3 + k), e.level, e.tx, e.ty,
                     first ? packOrthoTileStats(e.stats) : std::vector<uint8_t>{}, blob);
            first = false;
        }
    };
    const auto put = [&](const EncodedOrthoTile& e, OutputSet made, bool stats = true) {
        if (share) {
            record(e, made, stats);
        } else {
            outputs->write(e, made);
        }
    };
    // Two walks: the residual tiles of levels 0..C, held from the first walk until the
    // second's are written, so that the residual file (and a split build's streams) has the
    // top levels last, as the TIFF and DXT files: at most the compressed residuals of levels
    // 0..C, which the SinglePass walk bounds (OrthoLevels).
    std::vector<EncodedOrthoTile> heldTop;
    std::vector<bool> heldStats; // a held tile that carried no TIFF or DXT output: its statistics go with it
    // What the writer writes of each tile of the first walk (or the only one), and of the second.
    const OutputSet residualsOut{false, false, true};
    const OutputSet firstOut = twoWalks ? OutputSet{o.writeTiff, o.writeDxt, false} : OutputSet::of(o);
    // The walk's items are written (content hashes, file writes: serial, in the walk's order),
    // each as soon as it and the items before it are encoded, by the thread that hands over the
    // item written next, while the walk's other threads sample and encode the next ones.
    // Window: OrthoLevels::itemWindow items, admitted once encoded, so that memory grows by that
    // many encoded items at most, besides the one each thread works on. Items from `secondWalk`
    // on are the second walk's. Declared after everything its writes use (its destructor stops
    // it).
    std::atomic<int64_t> secondWalk{std::numeric_limits<int64_t>::max()};
    // The TIFF and DXT files, complete once the writing reaches the second walk (before `writer`:
    // a write starts it, and it is awaited before `outputs` goes).
    std::future<void> picturesFinished;
    OrderedWriter<EncodedItem> writer(levels.itemWindow(), [&](int64_t index, EncodedItem& item) {
        const bool second = index >= secondWalk.load(std::memory_order_acquire);
        if (second && outputs && !picturesFinished.valid()) {
            picturesFinished = std::async(std::launch::async, [&outputs] { outputs->finishPictures(); });
        }
        for (EncodedOrthoTile& e : item) {
            if (region && !region->holds(e.level, e.tx, e.ty)) {
                continue; // an ancestor of the root, encoded for its reconstruction
            }
            if (share && !range.top && e.top) {
                continue; // another share's
            }
            if (o.colourReconstruction && e.recon) {
                o.colourReconstruction(e.level, e.tx, e.ty, *e.recon);
            }
            if (second) {
                e.stats.tiles = 0; // counted with its TIFF or DXT tile
                put(e, residualsOut);
            } else {
                put(e, firstOut);
                if (twoWalks && e.top) {
                    EncodedOrthoTile& held = heldTop.emplace_back();
                    held.level = e.level;
                    held.tx = e.tx;
                    held.ty = e.ty;
                    held.residual = std::move(e.residual); // its statistics go with its other outputs
                    held.residualEmptyBelow = e.residualEmptyBelow;
                    const bool carried = e.tiff || e.dxt || e.picturesEmptyBelow;
                    heldStats.push_back(!carried);
                    if (!carried) {
                        held.stats = e.stats;
                    }
                }
            }
            totals[static_cast<size_t>(e.level)].add(e.stats);
            stepsDone += e.covers;
            const auto now = static_cast<int64_t>(static_cast<long double>(stepsDone) * total / steps);
            if (now > done) {
                done = std::min(now, total);
                if (o.progress) {
                    o.progress(done, total);
                }
            }
            if (o.cancelled && o.cancelled()) {
                throw Cancelled(report.input + ": cancelled");
            }
        }
    });
    int64_t walked = 0; // the walks' items so far
    // A whole build's second walk encodes the first walk's subtrees again when they fit in
    // keptSubtreeBytes (ortho_kept_subtrees.hpp), instead of sampling the input again.
    KeptSubtrees kept(levels, order, twoWalks && !share ? items : 0, o.keptSubtreeBytes);
    bool keeping = kept.active(); // the first walk
    const auto encodeWalk = [&](const OrthoLevels::Range* walkRange) {
        const int64_t first = walked;
        std::atomic<bool> stopped{false};
        // Hands an item over to the writer: false when the run has stopped (a write failed).
        const auto hand = [&](int64_t i, EncodedItem&& item) {
            const int64_t index = first + i;
            if (!writer.admit(index)) {
                stopped = true;
                return false;
            }
            writer.deliver(index, std::move(item));
            return true;
        };
        // Only the tiles the region needs are encoded.
        const auto keep = [&](TileBatch& item) {
            if (region) {
                for (const TrueTile& t : item) {
                    if (t.level == region->root.level && t.tx == region->root.tx && t.ty == region->root.ty) {
                        region->checkParent(t); // before any of the region's tiles is encoded
                    }
                }
                std::erase_if(item, [&](const TrueTile& t) { return !region->needed(t.level, t.tx, t.ty); });
            }
        };
        OrthoLevels::Sink sink;
        sink.subtree = [&](int64_t i, TileBatch& item) {
            keep(item);
            EncodedItem e = encoder.encodeSubtree(item);
            if (keeping) {
                kept.keep(i, std::move(item));
            }
            return hand(i, std::move(e));
        };
        sink.level = [&](int64_t i, TileBatch& item) {
            keep(item);
            return hand(i, encoder.encodeLevel(item));
        };
        sink.failed = [&](int64_t i) { writer.stopAt(first + i); }; // items after it are not awaited
        // No walk after this one samples the input: the only walk, or the first when the second
        // encodes the subtrees it keeps.
        sink.lastRead = !region && (keeping || !twoWalks);
        if (kept.active() && !keeping) {
            walked += kept.encode(encoder, levels.threads(), hand, sink.failed);
        } else {
            walked += levels.walk(sink, order, walkRange, pruned);
        }
        if (stopped) {
            writer.finish(first); // a write failed: rethrows its error
        }
    };
    if (region) {
        encodeWalk(&region->range);
    } else if (twoWalks) {
        // Levels 0..C in every share: the second walk's subtrees need their reconstruction.
        const OrthoLevels::Range first{range.begin, range.end, true};
        encodeWalk(share ? &first : nullptr);
        encoder.setSubtreeOutputs(residualsOnly);
        keeping = false;
        secondWalk.store(walked, std::memory_order_release);
        const OrthoLevels::Range second{range.begin, range.end, false};
        encodeWalk(&second);
    } else {
        const OrthoLevels::Range walkRange{range.begin, range.end, range.top};
        encodeWalk(share ? &walkRange : nullptr);
    }
    writer.finish(walked);
    for (size_t i = 0; i < heldTop.size(); ++i) {
        put(heldTop[i], residualsOut, heldStats[i]);
    }

    if (share) {
        nlohmann::json companionJson = nlohmann::json::object();
        for (const auto& [name, text] : companions) {
            companionJson[name] = text;
        }
        share->out->addPyramid({{"pyramid", o.pyramid},
                                {"pyramids", o.pyramids},
                                {"name", o.name + ".dat"},
                                {"header", {{"outputs", slots}}},
                                {"units", items == 0 ? 0 : units}, // no subtree: the top levels alone
                                {"begin", range.begin},
                                {"end", range.end},
                                {"top", range.top},
                                {"top_last", topLast},
                                {"records", {recordsStart, share->out->file().position()}},
                                {"tiles", total},
                                {"max_file_bytes", o.maxFileBytes},
                                {"sparse", pruned},
                                {"left_out", pruned && levels.severalLevels()},
                                {"empty_tiles", emptyTilesJson},
                                {"companions", companionJson}});
    } else {
        if (picturesFinished.valid()) {
            picturesFinished.get(); // rethrows its error
        }
        const int64_t held = outputs->commit(report);
        if (pruned) {
            report.tiles = held;
        }
        for (const auto& [name, text] : companions) {
            AtomicFile file(staging->path(name));
            file.writeAt(0, text.data(), text.size());
            file.commit();
        }
    }
    const size_t first = region ? static_cast<size_t>(region->root.level) : 0; // a region's levels count from its root
    for (size_t l = first; l < totals.size(); ++l) {
        report.levels.push_back(totals[l].report(static_cast<int>(l - first)));
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace pyramid
