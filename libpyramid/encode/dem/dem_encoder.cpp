#include "libpyramid/encode/dem/dem_encoder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_sampling.hpp"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"

namespace pyramid {

namespace {

// The most tiles one file may get. With the default 192-tiles and 24-sample root that allows
// maxLevel 16: 1572864 intervals per side, the Earth's circumference at 25 m.
constexpr int64_t kMaxTiles = int64_t{1} << 28;

int log2Exact(int v) {
    int k = 0;
    while ((1 << k) < v) {
        ++k;
    }
    return (1 << k) == v ? k : -1;
}

} // namespace

ResidualHeader planDemPyramid(const RasterInfo& input, const DemEncodeOptions& o, const std::string& where) {
    if (o.tileSize < 2 || o.tileSize > 8192 || o.tileSize % 2 != 0) {
        fail("--tile-size", std::to_string(o.tileSize) + " is not an even number from 2 to 8192");
    }
    if (o.rootTileSize < 1 || o.rootTileSize > o.tileSize || o.tileSize % o.rootTileSize != 0 ||
        log2Exact(o.tileSize / o.rootTileSize) < 0) {
        fail("--root-tile-size", std::to_string(o.rootTileSize) + " must be the tile size (" +
                                     std::to_string(o.tileSize) + ") divided by a power of two");
    }
    const int minLevel = log2Exact(o.tileSize / o.rootTileSize);
    const int64_t longest = std::max(input.width, input.height);
    int maxLevel = o.maxLevel;
    if (maxLevel < 0) {
        maxLevel = minLevel;
        while ((static_cast<int64_t>(o.rootTileSize) << maxLevel) + 1 < longest) {
            ++maxLevel;
        }
    }
    if (maxLevel < minLevel || maxLevel > 24) {
        fail("--max-level", std::to_string(maxLevel) + " is outside " + std::to_string(minLevel) +
                                "..24 (the file needs at least minLevel = log2(tile size / root tile size) levels)");
    }
    ResidualHeader h;
    h.minLevel = minLevel;
    h.maxLevel = maxLevel;
    h.tileSize = o.tileSize;
    h.scale = static_cast<float>(o.scale);
    // Every tile needs at least a shared blob's offsets and a hash in memory: a bound that keeps
    // a mistyped --max-level from exhausting memory (8193 x 8193 samples make 5461 tiles).
    if (h.tileCount() > kMaxTiles) {
        fail(o.maxLevel < 0 ? where : std::string("--max-level"),
             "maxLevel " + std::to_string(maxLevel) + " makes " + std::to_string(h.tileCount()) + " tiles, more than " +
                 std::to_string(kMaxTiles) + " in one file");
    }
    return h;
}

std::optional<double> checkBandAndNodata(const RasterInfo& input, const DemEncodeOptions& options,
                                         const std::string& where) {
    if (options.band < 0 || options.band >= input.channels) {
        fail("--band", std::to_string(options.band + 1) + " is not a band of " + where + " (it has " +
                           std::to_string(input.channels) + ")");
    }
    if (options.nodata || options.ignoreDeclaredNodata) {
        return options.nodata;
    }
    return input.nodata;
}

DemReport encodeDem(const std::string& input, const std::string& output, const DemEncodeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    if (!options.autoScale && (!std::isfinite(options.scale) || options.scale <= 0.0)) {
        fail("--scale", "must be a positive number, not " + numberText(options.scale));
    }
    auto source = RasterSource::open(input, options.cacheMegabytes);
    DemReport report;
    report.input = input;
    report.output = output;
    report.inputInfo = source->info();
    report.band = options.band;
    const std::optional<double> nodata = checkBandAndNodata(source->info(), options, input);
    ResidualPyramidJob job;
    job.header = planDemPyramid(source->info(), options, input);
    job.input = input;
    const int64_t N = static_cast<int64_t>(job.header.tileSize >> job.header.minLevel) << job.header.maxLevel;
    report.nodata = nodata;
    const DemGeometry geometry = makeDemGeometry(source->info().width, source->info().height, N, options.stretch, input);
    report.sampling = geometry.describe();
    const DemSampler sampler(*source, geometry, options.band, nodata);
    job.heights = &sampler;
    encodeResidualPyramid(job, output, options, report);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

nlohmann::json demInputJson(const std::string& path, const RasterInfo& info, int band, std::optional<double> nodata) {
    nlohmann::json nodataJson = nullptr;
    if (nodata) {
        nodataJson = std::isnan(*nodata) ? nlohmann::json("nan") : nlohmann::json(*nodata);
    }
    return {{"path", path},
            {"width", info.width},
            {"height", info.height},
            {"channels", info.channels},
            {"type", sampleTypeName(info.type)},
            {"format", info.formatName},
            {"band", band + 1},
            {"nodata", nodataJson}};
}

nlohmann::json toJson(const DemReport& r) {
    nlohmann::json levels = nlohmann::json::array();
    for (const DemLevelReport& l : r.levels) {
        levels.push_back({{"level", l.level},
                          {"tiles", l.tiles},
                          {"samples", l.samples},
                          {"max_error", l.maxError},
                          {"rms_error", l.rmsError},
                          {"max_abs_residual", l.maxAbsResidual}});
    }
    return {{"input", demInputJson(r.input, r.inputInfo, r.band, r.nodata)},
            {"output", r.output},
            {"sampling", r.sampling},
            {"header", {{"min_level", r.header.minLevel},
                        {"max_level", r.header.maxLevel},
                        {"tile_size", r.header.tileSize},
                        {"scale", r.header.scale}}},
            {"scales_tried", r.scalesTried},
            {"tiles", r.tiles},
            {"shared_tiles", r.sharedTiles},
            {"bytes", r.bytes},
            {"bits_per_sample", r.finestSamples ? 8.0 * static_cast<double>(r.bytes) / static_cast<double>(r.finestSamples) : 0.0},
            {"finest_samples", r.finestSamples},
            {"nodata_filled", r.nodataFilled},
            {"levels", levels},
            {"threads", r.threads},
            {"seconds", r.seconds}};
}

} // namespace pyramid
