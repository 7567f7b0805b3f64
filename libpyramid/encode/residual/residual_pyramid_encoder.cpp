#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>

#include "formats/error.hpp"
#include "formats/residual_set.hpp"
#include "formats/sparse_set.hpp"
#include "libpyramid/encode/residual/residual_parts.hpp"
#include "libpyramid/encode/residual/residual_reach.hpp"
#include "libpyramid/encode/residual/residual_region_plan.hpp"
#include "libpyramid/encode/residual/residual_tile.hpp"
#include "libpyramid/encode/residual/residual_tree_encoder.hpp"
#include "libpyramid/encode/residual/root_fill.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
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
        region = planRegion(plan, options, *job.heights);
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
    // Context-coded tiles take the parent mode where smaller once their file is final.
    const std::optional<int> parentModes =
        plan.coding.codec == ResidualCodec::Context ? std::optional<int>(threads) : std::nullopt;
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
            out = std::make_unique<ResidualOutput>(output, region->header, 0, true, parentModes);
            sink.writer = &out->writer();
            sink.region = &region->root;
        } else if (sparse) {
            out = std::make_unique<ResidualOutput>(
                output, plan.header, options.maxFileBytes,
                ResidualOutput::Sparse{zeroResidualBlob(plan.T + 5, plan.coding), parentModes});
            sink.log = out->log();
        } else {
            out = std::make_unique<ResidualOutput>(output, plan.header, options.maxFileBytes, false, parentModes);
            sink.writer = &out->writer();
        }
        if (gridNeeded && grid.height.empty()) {
            grid = sampleLevelGrid(plan, job, options, threads); // released by the attempt before
        }
        ResidualTreeEncoder encoder(plan, *job.heights, grid, options, threads, job.input, range,
                                    region ? &region->root : nullptr,
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
                                    {"parent_modes", parentModes.has_value()},
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
