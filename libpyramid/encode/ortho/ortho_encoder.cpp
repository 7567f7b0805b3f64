#include "libpyramid/encode/ortho/ortho_encoder.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"
#include "formats/atomic_file.hpp"
#include "formats/part_file.hpp"
#include "libpyramid/support/work_share.hpp"
#include "formats/staging_directory.hpp"
#include "formats/ortho_set.hpp"
#include "libpyramid/encode/ortho/ortho_output.hpp"
#include "libpyramid/encode/ortho/ortho_region.hpp"
#include "libpyramid/encode/ortho/ortho_tile_encoder.hpp"
#include "libpyramid/support/ordered_writer.hpp"
#include "libpyramid/support/parallel.hpp"

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

// Which outputs of a tile an encoded tile carries.
struct OutputSet {
    bool tiff = false, dxt = false, residual = false;

    static OutputSet of(const OrthoEncodeOptions& o) { return {o.writeTiff, o.writeDxt, o.writeResiduals}; }
};

// The files being written, in the staging directory (the caller commits it).
class OrthoOutputs {
public:
    // Names the outputs' final paths in `directory` in report.outputs.
    // With `region`, each output is that region's file (its tiles given at absolute coordinates).
    OrthoOutputs(const OrthoLevels& levels, const std::string& directory, StagingDirectory& staging,
                 const OrthoEncodeOptions& o, OrthoReport& report, const RegionRoot* region = nullptr)
        : staging_(staging), maxFileBytes_(o.maxFileBytes), region_(region) {
        OrthoHeader base;
        base.maxLevel = levels.maxLevel();
        base.tileSize = levels.tileSize();
        base.channels = levels.channels();
        base.flags = o.border == 0 ? OrthoHeader::kFlagNoBorder : 0u;
        const std::filesystem::path dir(directory);
        const std::string file = o.name + ".dat";
        auto output = [&](const std::string& whole, const OrthoHeader& h) {
            const std::string relative = region ? regionFilePath(whole, *region) : whole;
            names_.push_back(relative);
            report.outputs.push_back((dir / relative).string());
            if (region) {
                // Staged as the tiles come, never committed: put in level order when complete.
                const OrthoHeader r = orthoRegionHeader(h, *region, h.maxLevel);
                r.validate(relative);
                return std::make_unique<OrthoFileWriter>(staging.path(relative) + ".staged", r);
            }
            return std::make_unique<OrthoFileWriter>(staging.path(relative), h);
        };
        if (o.writeTiff) {
            tiff_ = output(file, base);
        }
        if (o.writeDxt) {
            OrthoHeader h = base;
            h.channels = std::max(3, base.channels);
            h.flags |= OrthoHeader::kFlagDxt;
            dxt_ = output("dxt/" + file, h);
        }
        if (o.writeResiduals) {
            OrthoHeader h = base;
            h.flags = 0; // colour residuals always carry their 2-pixel border
            residual_ = output("residuals/" + file, h);
        }
    }

    // Writes the outputs of `e` in `made` (which it carries).
    void write(const EncodedOrthoTile& e, OutputSet made) {
        RegionRoot t{e.level, e.tx, e.ty};
        if (region_) {
            t = regionRelativeTile(*region_, e.level, e.tx, e.ty);
        }
        if (tiff_ && made.tiff) {
            writeOne(*tiff_, firstWith_[0], t, e.tiff, e.uniform);
        }
        if (dxt_ && made.dxt) {
            writeOne(*dxt_, firstWith_[1], t, e.dxt, e.uniform);
        }
        if (residual_ && made.residual) {
            writeOne(*residual_, firstWith_[2], t, e.residual, e.uniform);
        }
    }

    // Completes the TIFF and DXT files (their tables written, their bytes on disk) but for the
    // rename, once every tile of theirs is written: in the two walks, while the second walk
    // encodes the residual tiles, rather than after it (a file system commits its journal at
    // the first fsync: tens of milliseconds). Not for a region's files, which are put in order
    // when complete, nor for region sets, which are split from the files as they are read.
    void finishPictures() {
        if (!region_ && maxFileBytes_ == 0) {
            for (auto* w : {&tiff_, &dxt_}) {
                if (*w) {
                    (*w)->finish();
                }
            }
        }
    }

    // Completes the files (each a region set with its index when maxFileBytes is set); their
    // sizes and shared tiles go to the report.
    void commit(OrthoReport& report) {
        size_t k = 0;
        for (auto* w : {&tiff_, &dxt_, &residual_}) {
            if (*w) {
                report.sharedTiles.push_back((*w)->sharedTiles());
                commitOne(std::move(*w), names_[k], report.outputs[k], report);
                ++k;
            }
        }
    }

private:
    // The tile that first took each uniform tile's shared bytes, by their address (the bytes held
    // here, so that the address stays theirs): a writer's tiles of bytes it was given once.
    using FirstWith = std::map<const std::vector<uint8_t>*, std::pair<SharedBytes, std::array<int, 3>>>;

    // Tile t's bytes: a uniform tile's bytes given before are not compared again, byte for byte,
    // with those the writer stored (a face that a small map barely touches has millions).
    static void writeOne(OrthoFileWriter& writer, FirstWith& firstWith, const RegionRoot& t, const SharedBytes& bytes,
                         bool uniform) {
        if (uniform && bytes) {
            const auto it = firstWith.find(bytes.get());
            if (it != firstWith.end()) {
                writer.writeTileSameAs(t.level, t.tx, t.ty, it->second.second);
                return;
            }
            firstWith.emplace(bytes.get(), std::make_pair(bytes, std::array<int, 3>{t.level, t.tx, t.ty}));
        }
        writer.writeTileBytes(t.level, t.tx, t.ty, bytesOf(bytes));
    }

    void commitOne(std::unique_ptr<OrthoFileWriter> writer, const std::string& name, const std::string& output,
                   OrthoReport& report) {
        if (region_) {
            // Level by level, row by row: the order the set splitter gives a region file, so that
            // a region built alone is byte for byte the file of a set (formats/set_splitter.hpp).
            const OrthoHeader& h = writer->header();
            auto ordered = std::make_unique<OrthoFileWriter>(staging_.path(name), h);
            for (int l = 0; l <= h.maxLevel; ++l) {
                const int side = 1 << l;
                for (int ty = 0; ty < side; ++ty) {
                    for (int tx = 0; tx < side; ++tx) {
                        ordered->writeTileBytes(l, tx, ty, writer->table().read(h.tileIndex(l, tx, ty)));
                    }
                }
            }
            writer = std::move(ordered);
            report.sharedTiles.back() = writer->sharedTiles();
        }
        placeOrthoOutput(std::move(writer), name, output, maxFileBytes_, staging_, report);
    }

    StagingDirectory& staging_;
    const uint64_t maxFileBytes_;
    const RegionRoot* region_;
    std::unique_ptr<OrthoFileWriter> tiff_, dxt_, residual_;
    FirstWith firstWith_[3]; // of tiff_, dxt_, residual_
    std::vector<std::string> names_; // each output's path relative to the directory and the staging directory
};

// One item of a walk (a subtree, or a level of levels 0..C) encoded, its tiles in the walk's order.
using EncodedItem = std::vector<EncodedOrthoTile>;

// Encodes the walk's items (OrthoLevels::walk). A tile's colour residual is predicted from its
// parent's rebuilt colours: within a subtree, its own tiles'; above a subtree, and within levels
// 0..C, those of levels 0..C, kept here as the walk hands those levels out (before the subtrees
// that need them). The items of levels 0..C and the subtree items may be given different
// outputs (`top` and `subtrees`: a build in two walks, encodeLevels), which a later walk may
// change (setSubtreeOutputs).
class ItemEncoder {
public:
    ItemEncoder(const OrthoLevels& levels, const OrthoEncodeOptions& top, const OrthoEncodeOptions& subtrees)
        : levels_(levels), top_(levels, top), topResiduals_(top.writeResiduals),
          handOutRecon_(static_cast<bool>(top.colourReconstruction)), threads_(levels.threads()) {
        setSubtreeOutputs(subtrees);
    }
    // The outputs of the subtree items from now on (the options must outlive this object).
    void setSubtreeOutputs(const OrthoEncodeOptions& subtrees) {
        subtree_ = std::make_unique<OrthoTileEncoder>(levels_, subtrees);
        subtreeResiduals_ = subtrees.writeResiduals;
    }
    // The colour reconstruction of a tile this walk does not encode (a region's parent).
    void seed(int level, int tx, int ty, std::vector<uint8_t> recon) {
        shallowRecon_[{level, tx, ty}] = std::make_shared<const std::vector<uint8_t>>(std::move(recon));
    }

    // A whole level of 0..C, from the walk's calling thread: its tiles in parallel, independent
    // given the previous level's reconstruction.
    EncodedItem encodeLevel(const TileBatch& batch) {
        EncodedItem level(batch.size());
        parallelFor(static_cast<int64_t>(batch.size()), threads_, [&](int64_t i) {
            const TrueTile& t = batch[static_cast<size_t>(i)];
            const std::vector<uint8_t>* parent = t.level && topResiduals_ ? shallowRecon_.at(parentOf(t)).get() : nullptr;
            level[static_cast<size_t>(i)] = top_.encode(t, parent);
        });
        if (topResiduals_) {
            // The next levels and the subtrees predict from these rebuilt tiles while this one is
            // written. Moved rather than copied unless they are handed out too: a level's rebuilt
            // colours are held once (at planet scale, level C's are most of a gigabyte).
            for (EncodedOrthoTile& e : level) {
                SharedBytes& kept = shallowRecon_[{e.level, e.tx, e.ty}];
                kept = handOutRecon_ ? e.recon : std::move(e.recon);
            }
        }
        return level;
    }

    // A subtree, in pre-order (its parents before its children), on the calling thread; called
    // by several threads at once, never while a level is encoded.
    EncodedItem encodeSubtree(const TileBatch& item) const {
        std::map<TileKey, const std::vector<uint8_t>*> local;
        EncodedItem out;
        out.reserve(item.size());
        for (const TrueTile& t : item) {
            if (!subtreeResiduals_) {
                out.push_back(subtree_->encode(t, nullptr)); // no tile depends on its parent
                continue;
            }
            const auto key = parentOf(t);
            const auto it = local.find(key);
            const std::vector<uint8_t>* parent = it != local.end() ? it->second : shallowRecon_.at(key).get();
            out.push_back(subtree_->encode(t, parent));
            local[{t.level, t.tx, t.ty}] = out.back().recon.get();
        }
        if (!handOutRecon_) {
            for (EncodedOrthoTile& e : out) {
                e.recon.reset(); // not held while the item waits to be written
            }
        }
        return out;
    }

private:
    using TileKey = std::tuple<int, int, int>; // level, tx, ty
    static TileKey parentOf(const TrueTile& t) { return {t.level - 1, t.tx / 2, t.ty / 2}; }

    const OrthoLevels& levels_;
    const OrthoTileEncoder top_;
    const bool topResiduals_;
    const bool handOutRecon_; // OrthoEncodeOptions::colourReconstruction is set: the writer needs every tile's
    std::unique_ptr<OrthoTileEncoder> subtree_;
    bool subtreeResiduals_ = false;
    const int threads_;
    std::map<TileKey, SharedBytes> shallowRecon_; // levels 0..C
};

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

// Writes the outputs and `companions` into `staging` (the caller commits it); the report names
// their final paths in `directory`. With o.share, the share's tiles go to its part file instead
// (and `staging` is null).
OrthoReport encodeLevels(const OrthoLevels& levels, const std::string& directory, StagingDirectory* staging,
                         const OrthoEncodeOptions& o, const std::vector<std::pair<std::string, std::string>>& companions,
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
    // does (once for levels 0..C, once for the subtrees).
    const bool twoWalks = !region && o.writeResiduals && (o.writeTiff || o.writeDxt) &&
                          levels.subtreeItems(OrthoLevels::WalkOrder::SinglePass) > 0;
    const auto order = region                            ? region->order
                       : o.writeResiduals && !twoWalks ? OrthoLevels::WalkOrder::CoarseFirst
                                                       : OrthoLevels::WalkOrder::SinglePass;
    const OrthoShare* share = o.share;
    const int64_t items = levels.subtreeItems(order);
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
    report.tiles = total;
    if (share && !range.active()) {
        return report; // nothing of this pyramid is this share's
    }
    // Progress is given in tiles, of the work: two walks encode the subtrees' tiles twice, so
    // each of the `steps` tiles encoded moves it by total / steps of a tile (an error
    // diffusion in integers: one tile at a time, `total` after the last step).
    const int64_t steps = total + (twoWalks ? (range.end - range.begin) * subtreeTiles : 0);
    int64_t stepCarry = 0;
    std::unique_ptr<OrthoOutputs> outputs;
    if (!share) {
        outputs = std::make_unique<OrthoOutputs>(levels, directory, *staging, o, report,
                                                 region ? &region->root : nullptr);
    }
    const uint64_t recordsStart = share ? share->out->file().position() : 0;
    const nlohmann::json slots = orthoOutputsJson(levels, o);
    // The outputs of each walk's subtrees (levels 0..C always get every output).
    OrthoEncodeOptions pictures = o;
    pictures.writeResiduals = false;
    OrthoEncodeOptions residualsOnly = o;
    residualsOnly.writeTiff = residualsOnly.writeDxt = false;
    ItemEncoder encoder(levels, o, twoWalks ? pictures : o);
    if (region && !region->parentRecon.empty()) {
        const RegionRoot& r = region->root;
        encoder.seed(r.level - 1, r.tx >> 1, r.ty >> 1, region->parentRecon);
    }
    std::vector<OrthoLevelTotals> totals(static_cast<size_t>(levels.maxLevel()) + 1);
    int64_t done = 0;

    // A share records the outputs `made` of a tile in each output's stream (pyramid x 3 +
    // slot), the tile's statistics with the first of them.
    const auto record = [&](const EncodedOrthoTile& e, OutputSet made, bool stats) {
        PartFileWriter& file = share->out->file();
        bool first = stats;
        for (const nlohmann::json& slot : slots) {
            const int k = slot["slot"].get<int>();
            if (!(k == 0 ? made.tiff : k == 1 ? made.dxt : made.residual)) {
                continue;
            }
            const std::vector<uint8_t>& blob = bytesOf(k == 0 ? e.tiff : k == 1 ? e.dxt : e.residual);
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
    // What the writer writes of each tile of the first walk (or the only one), and of the second.
    const OutputSet residualsOut{false, false, true};
    const OutputSet firstOut = twoWalks ? OutputSet{o.writeTiff, o.writeDxt, false} : OutputSet::of(o);
    // The walk's items are written (content hashes, file writes: serial, in the walk's order) by
    // the writer's thread, each as soon as it and the items before it are encoded, while the
    // walk's threads sample and encode the next ones, instead of stopping for the writes.
    // Window: OrthoLevels::itemWindow items, admitted once encoded, so that memory grows by that
    // many encoded items at most, besides the one each thread works on. Items from `secondWalk`
    // on are the second walk's. Declared after everything its writes use (its destructor stops
    // it).
    std::atomic<int64_t> secondWalk{std::numeric_limits<int64_t>::max()};
    // The TIFF and DXT files, complete once the writer reaches the second walk (before `writer`:
    // the writer's thread starts it, and it is awaited before `outputs` goes).
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
            if (share && !range.top && e.level <= topLevel) {
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
                if (twoWalks && e.level <= topLevel) {
                    EncodedOrthoTile& held = heldTop.emplace_back();
                    held.level = e.level;
                    held.tx = e.tx;
                    held.ty = e.ty;
                    held.residual = std::move(e.residual); // its statistics go with its other outputs
                }
            }
            totals[static_cast<size_t>(e.level)].add(e.stats);
            stepCarry += total;
            if (stepCarry >= steps) {
                stepCarry -= steps;
                if (o.progress) {
                    o.progress(++done, total);
                }
            }
            if (o.cancelled && o.cancelled()) {
                throw Cancelled(report.input + ": cancelled");
            }
        }
    });
    int64_t walked = 0; // the walks' items so far
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
            return hand(i, encoder.encodeSubtree(item));
        };
        sink.level = [&](int64_t i, TileBatch& item) {
            keep(item);
            return hand(i, encoder.encodeLevel(item));
        };
        sink.failed = [&](int64_t i) { writer.stopAt(first + i); }; // items after it are not awaited
        walked += levels.walk(sink, order, walkRange);
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
        secondWalk.store(walked, std::memory_order_release);
        const OrthoLevels::Range second{range.begin, range.end, false};
        encodeWalk(&second);
    } else {
        const OrthoLevels::Range walkRange{range.begin, range.end, range.top};
        encodeWalk(share ? &walkRange : nullptr);
    }
    writer.finish(walked);
    for (const EncodedOrthoTile& e : heldTop) {
        put(e, residualsOut, false);
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
                                {"units", units},
                                {"begin", range.begin},
                                {"end", range.end},
                                {"top", range.top},
                                {"top_last", topLast},
                                {"records", {recordsStart, share->out->file().position()}},
                                {"tiles", total},
                                {"max_file_bytes", o.maxFileBytes},
                                {"companions", companionJson}});
    } else {
        if (picturesFinished.valid()) {
            picturesFinished.get(); // rethrows its error
        }
        outputs->commit(report);
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

} // namespace

// The checks that do not need the input, made before it is opened.
void OrthoEncodeOptions::validate() const {
    if (border != 0 && border != 2) {
        failOption("border", std::to_string(border) + " is not 0 or 2");
    }
    if (!writeTiff && !writeDxt && !writeResiduals) {
        failOption("outputs", "selects no output");
    }
    if (jpegQuality < 1 || jpegQuality > 100) {
        failOption("jpegQuality", std::to_string(jpegQuality) + " is not 1..100");
    }
    if (deflateLevel < 1 || deflateLevel > 12) {
        failOption("deflateLevel", std::to_string(deflateLevel) + " is not 1..12");
    }
    if (residualDeflateLevel < 0 || residualDeflateLevel > 12) {
        failOption("residualDeflateLevel", std::to_string(residualDeflateLevel) + " is not 0 (per tile) or 1..12");
    }
    if (dxtQuality < 0 || dxtQuality >= kDxtQualityLevels) {
        failOption("dxtQuality", std::to_string(dxtQuality) + " is not 0, 1, 2 or 3");
    }
    if (residualCompression != TilePolicy::Deflate && residualCompression != TilePolicy::Jpeg) {
        failOption("residualCompression", "must be deflate or jpeg");
    }
    if (name.empty() || name.find('/') != std::string::npos) {
        failOption("name", "'" + name + "' is not a plain file name");
    }
}

OrthoReport encodeOrtho(const std::string& input, const std::string& directory, const OrthoEncodeOptions& o) {
    return encodeOrtho(std::vector<std::string>{input}, directory, o);
}

namespace {

// A planar pyramid's outputs and its georeference sidecar, committed together (with o.share:
// the share's tiles, and the sidecar, into its part file).
OrthoReport encodePlanar(const OrthoLevels& levels, const std::string& directory, const OrthoEncodeOptions& o,
                         std::chrono::steady_clock::time_point start) {
    std::optional<PyramidGeoreference> georeference;
    std::vector<std::pair<std::string, std::string>> companions;
    if (const auto& g = levels.inputInfo().georeference; g && g->problem.empty() && !o.region) {
        // The finest level's pixels tile the root quad: the input's pixels, or its longer side's
        // square with the aspect kept (planar_pixels.hpp).
        const int w = levels.inputWidth(), h = levels.inputHeight(), longest = std::max(w, h);
        const std::array<double, 4> root{0.0, 0.0, static_cast<double>(o.levels.stretch ? w : longest),
                                         static_cast<double>(o.levels.stretch ? h : longest)};
        std::vector<int64_t> pixels;
        for (int l = 0; l <= levels.maxLevel(); ++l) {
            pixels.push_back(static_cast<int64_t>(levels.tileSize()) << l);
        }
        georeference = georeferencePyramid(*g, w, h, root, pixels, "pixel centres");
        companions.emplace_back(georeferenceSidecarPath(o.name + ".dat"),
                                georeferenceSidecarText(o.name + ".dat", *georeference));
    }
    std::unique_ptr<StagingDirectory> staging;
    if (!o.share) {
        staging = std::make_unique<StagingDirectory>(directory);
    }
    OrthoReport report = encodeLevels(levels, directory, staging.get(), o, companions, start);
    report.georeference = georeference;
    if (staging) {
        staging->commit(); // the outputs appear together, or none of them
    }
    return report;
}

} // namespace

OrthoReport encodeOrtho(const std::vector<std::string>& inputs, const std::string& directory, const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    o.validate();
    const OrthoLevels levels(inputs, o.levels);
    return encodePlanar(levels, directory, o, start);
}

OrthoReport encodeOrtho(const RasterSource& source, const std::string& directory, const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    o.validate();
    const OrthoLevels levels(source, o.levels);
    return encodePlanar(levels, directory, o, start);
}

OrthoReport encodeOrtho(const OrthoLevels& levels, const std::string& directory, StagingDirectory& staging,
                        const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    o.validate();
    return encodeLevels(levels, directory, o.share ? nullptr : &staging, o, {}, start);
}

OrthoReport encodeOrthoShare(const OrthoLevels& levels, const std::string& directory, const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    o.validate();
    if (!o.share) {
        failOption("share", "encodeOrthoShare needs a share");
    }
    return encodeLevels(levels, directory, nullptr, o, {}, start);
}

nlohmann::json toJson(const OrthoReport& r) {
    nlohmann::json levels = nlohmann::json::array();
    for (const OrthoLevelReport& l : r.levels) {
        // Not measured: null, never a 0 that would read as lossless.
        const nlohmann::json tiffMaxError =
            l.jpegTiles > 0 && !r.jpegErrorMeasured ? nlohmann::json() : nlohmann::json(l.tiffMaxError);
        levels.push_back({{"level", l.level},
                          {"tiles", l.tiles},
                          {"jpeg_tiles", l.jpegTiles},
                          {"tiff_max_error", tiffMaxError},
                          {"dxt_psnr_db", l.dxtPsnr},
                          {"residual_max_error", l.residualMaxError},
                          {"residual_rms_error", l.residualRmsError},
                          {"clamped_residuals", l.clampedResiduals}});
    }
    // The region sets' files, output after output, each main file first ([] without maxFileBytes).
    nlohmann::json files = nlohmann::json::array();
    for (const auto& set : r.files) {
        for (const auto& [name, bytes] : set) {
            files.push_back({{"file", name}, {"bytes", bytes}});
        }
    }
    return {{"input", {{"path", r.input}, {"width", r.inputWidth}, {"height", r.inputHeight}, {"channels", r.channels}}},
            {"directory", r.directory},
            {"outputs", r.outputs},
            {"bytes", r.bytes},
            {"files", files},
            {"shared_tiles", r.sharedTiles},
            {"sampling", r.sampling},
            {"tile_size", r.tileSize},
            {"max_level", r.maxLevel},
            {"region", r.region ? nlohmann::json::array({r.region->level, r.region->tx, r.region->ty}) : nlohmann::json()},
            {"border", r.border},
            {"tiles", r.tiles},
            {"levels", levels},
            {"georeference", r.georeference ? toJson(*r.georeference) : nlohmann::json()}, // null: not georeferenced
            {"threads", r.threads},
            {"seconds", r.seconds}};
}

} // namespace pyramid
