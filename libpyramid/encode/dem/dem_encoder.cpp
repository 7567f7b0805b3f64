#include "libpyramid/encode/dem/dem_encoder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_sampling.hpp"
#include "libpyramid/encode/residual/residual_parts.hpp"
#include "libpyramid/encode/tile_size_rule.hpp"
#include "libpyramid/input/height_samples.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

// The most tiles one file may get. With the default 192-tiles and 24-sample root that allows
// maxLevel 16: 1572864 intervals per side, the Earth's circumference at 25 m.

int log2Exact(int v) {
    int k = 0;
    while ((1 << k) < v) {
        ++k;
    }
    return (1 << k) == v ? k : -1;
}

// Encodes `raster` (read from `inputs`, for the report) into `output`.
DemReport encodeDemFrom(const RasterSource& raster, const std::vector<std::string>& inputs, const std::string& output,
                        const DemEncodeOptions& options, std::chrono::steady_clock::time_point start);

} // namespace

void DemEncodeOptions::validate() const {
    ResidualEncodeOptions::validate();
    requireCacheBudget(cacheMegabytes);
    if (fitTiles && (maxLevel || dstMaxLevel)) {
        failOption(maxLevel ? "maxLevel" : "dstMaxLevel",
                   "is chosen with the tiles by tileSize auto (fitTiles): give one or the other");
    }
    if (fitTiles) {
        return; // tileSize and rootTileSize are the fit's (always valid)
    }
    requireEncodableTileSize(tileSize);
    if (rootTileSize < 1 || rootTileSize > tileSize || tileSize % rootTileSize != 0 ||
        log2Exact(tileSize / rootTileSize) < 0) {
        failOption("rootTileSize", std::to_string(rootTileSize) + " must be the tile size (" +
                                       std::to_string(tileSize) + ") divided by a power of two");
    }
    if (rootTileSize % 2 != 0) {
        // The producers rebuild every level with tiles of its own size, which must be even.
        failOption("rootTileSize", std::to_string(rootTileSize) + " is odd: every level's tiles need an even size (" +
                                       std::to_string(2 * rootTileSize) + " with one level less covers the same grid)");
    }
    if (maxLevel && dstMaxLevel) {
        failOption("dstMaxLevel", "and maxLevel name the same level: give one of them");
    }
    if (dstMaxLevel && *dstMaxLevel < 0) {
        failOption("dstMaxLevel", std::to_string(*dstMaxLevel) + " is outside 0.." + std::to_string(24 - minLevel()) +
                                      " (maxLevel = minLevel " + std::to_string(minLevel()) +
                                      " + dstMaxLevel, at most 24)");
    }
    if (dstMaxLevel && minLevel() + *dstMaxLevel > 24) {
        failOption("dstMaxLevel", std::to_string(*dstMaxLevel) + " makes maxLevel = minLevel " +
                                      std::to_string(minLevel()) + " + " + std::to_string(*dstMaxLevel) +
                                      ", beyond 24");
    }
}

int DemEncodeOptions::minLevel() const { return log2Exact(tileSize / rootTileSize); }

ResidualHeader planDemPyramid(const RasterInfo& input, const DemEncodeOptions& options, const std::string& where,
                              DemTileFit* fit) {
    options.validate();
    DemEncodeOptions o = options;
    if (options.fitTiles) {
        const DemTileFit chosen = fitDemTiles(input.width, input.height, options.stretch, where);
        o.tileSize = chosen.tileSize;
        o.rootTileSize = chosen.rootTileSize;
        o.maxLevel = chosen.maxLevel;
        if (fit) {
            *fit = chosen;
        }
    }
    const int minLevel = o.minLevel();
    const int64_t longest = std::max(input.width, input.height);
    const std::optional<int> asked = o.dstMaxLevel ? std::optional<int>(minLevel + *o.dstMaxLevel) : o.maxLevel;
    // A level the caller gave (not the default, nor the fit's) is named in the errors.
    const bool given = asked && !options.fitTiles;
    int maxLevel = asked.value_or(-1);
    if (!asked) {
        maxLevel = minLevel;
        while ((static_cast<int64_t>(o.rootTileSize) << maxLevel) + 1 < longest) {
            ++maxLevel;
        }
    }
    if (maxLevel < minLevel || maxLevel > 24) {
        failOption("maxLevel", std::to_string(maxLevel) + " is outside " + std::to_string(minLevel) +
                                   "..24 (the file needs at least minLevel = log2(tile size / root tile size) levels)");
    }
    ResidualHeader h;
    h.minLevel = minLevel;
    h.maxLevel = maxLevel;
    h.tileSize = o.tileSize;
    h.scale = static_cast<float>(o.scale);
    // Every tile needs at least a shared blob's offsets and a hash in memory: a bound that keeps
    // a mistyped maxLevel from exhausting memory (8193 x 8193 samples make 5461 tiles). A sparse
    // layout stores only the tiles the data reaches: the encoder bounds a pyramid the data fills
    // (residual_pyramid_encoder.hpp, kMaxDenseTiles).
    if (o.layout == PyramidLayout::Dense && h.tileCount() > kMaxDenseTiles) {
        const std::string what = "maxLevel " + std::to_string(maxLevel) + " makes " + std::to_string(h.tileCount()) +
                                 " tiles, more than " + std::to_string(kMaxDenseTiles) + " in one file";
        if (given) {
            failOption(o.dstMaxLevel ? "dstMaxLevel" : "maxLevel", what);
        }
        fail(where, what);
    }
    return h;
}

std::optional<double> checkBandAndNodata(const RasterInfo& input, const DemEncodeOptions& options,
                                         const std::string& where) {
    if (options.band < 0 || options.band >= input.channels) {
        failOption("band", std::to_string(options.band + 1) + " is not a band of " + where + " (it has " +
                           std::to_string(input.channels) + ")");
    }
    if (options.nodata || options.ignoreDeclaredNodata) {
        // Reading keeps the file's own nodata value as stored and converts every other sample: a
        // value chosen here would be compared with converted heights, and the file's with none.
        if (!sameNodata(options.nodata, input.nodata) && heightsConverted(input, options.band)) {
            failOption("nodata", where + "'s heights are read converted (a scale, an offset or another unit), and only "
                                         "the file's own nodata value is kept as stored: declare the value in the file instead");
        }
        return options.nodata;
    }
    return input.nodata;
}

DemReport encodeDem(const std::string& input, const std::string& output, const DemEncodeOptions& options) {
    return encodeDem(std::vector<std::string>{input}, output, options);
}

DemReport encodeDem(const std::vector<std::string>& inputs, const std::string& output, const DemEncodeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    options.validate();
    const auto source = openPlanarMosaic(inputs, options.cacheMegabytes, false, options.target);
    return encodeDemFrom(*source, inputs, output, options, start);
}

DemReport encodeDem(const RasterSource& source, const std::string& output, const DemEncodeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    options.validate();
    return encodeDemFrom(source, {source.path()}, output, options, start);
}

namespace {

DemReport encodeDemFrom(const RasterSource& raster, const std::vector<std::string>& inputs, const std::string& output,
                        const DemEncodeOptions& options, std::chrono::steady_clock::time_point start) {
    const RasterSource* source = &raster;
    const std::string& input = source->path();
    DemReport report;
    report.input = input;
    report.inputs = inputs;
    report.output = output;
    report.inputInfo = source->info();
    report.band = options.band;
    report.coding = options.tiles;
    const std::optional<double> nodata = checkBandAndNodata(source->info(), options, input);
    ResidualPyramidJob job;
    DemTileFit fit;
    job.header = planDemPyramid(source->info(), options, input, &fit);
    if (options.fitTiles) {
        report.tileFit = fit;
        if (options.tileFitChosen) {
            options.tileFitChosen(fit);
        }
    }
    job.input = input;
    const int64_t N = static_cast<int64_t>(job.header.tileSize >> job.header.minLevel) << job.header.maxLevel;
    report.nodata = nodata;
    const DemGeometry geometry = makeDemGeometry(source->info().width, source->info().height, N, options.stretch, input);
    report.sampling = geometry.describe();
    const DemSampler sampler(*source, geometry, options.band, nodata, job.header.tileSize >> job.header.minLevel);
    job.heights = &sampler;
    // The sidecar appears together with the pyramid.
    if (const auto& g = source->info().georeference; g && g->problem.empty()) {
        // Sample x of the finest grid is at input column x * lx / N, a pixel centre: +0.5 in
        // PixelIsArea coordinates.
        std::vector<int64_t> intervals;
        for (int l = 0; l <= job.header.maxLevel; ++l) {
            intervals.push_back(static_cast<int64_t>(job.header.tileSize >> job.header.minLevel) << l);
        }
        const std::array<double, 4> root{0.5, 0.5, static_cast<double>(geometry.lx) + 0.5,
                                         static_cast<double>(geometry.ly) + 0.5};
        report.georeference = georeferencePyramid(*g, geometry.width, geometry.height, root, intervals, "vertices");
        job.companions.push_back(
            CompanionFile{std::filesystem::path(georeferenceSidecarPath(output)).filename().string(),
                          georeferenceSidecarText(output, *report.georeference)});
    }
    encodeResidualPyramid(job, output, options, report);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace

nlohmann::json valueScalingJson(const RasterInfo& info, int band) {
    const auto b = static_cast<size_t>(band);
    if (b >= info.scaling.size() || info.scaling[b].identity()) {
        return nullptr;
    }
    return {{"scale", info.scaling[b].scale}, {"offset", info.scaling[b].offset}, {"from", "GDAL metadata"}};
}

nlohmann::json demInputJson(const std::string& path, const RasterInfo& info, int band, std::optional<double> nodata) {
    nlohmann::json nodataJson = nullptr;
    if (nodata) {
        nodataJson = std::isfinite(*nodata) ? nlohmann::json(*nodata) : nlohmann::json(nodataText(*nodata));
    }
    return {{"path", path},
            {"width", info.width},
            {"height", info.height},
            {"channels", info.channels},
            {"type", sampleTypeName(info.type)},
            {"format", info.formatName},
            {"band", band + 1},
            {"nodata", nodataJson},
            {"values", valueScalingJson(info, band)},
            {"heights", info.georeference ? heightUnitJson(*info.georeference) : nlohmann::json()}};
}

nlohmann::json toJson(const DemTileFit& f) {
    return {{"tile_size", f.tileSize},
            {"root_tile_size", f.rootTileSize},
            {"min_level", f.minLevel},
            {"max_level", f.maxLevel},
            {"finest_samples_per_side", f.intervals + 1},
            {"input_samples_per_side", f.inputIntervals + 1},
            {"exact", f.exact},
            {"resampling", f.resampling()},
            {"proland_readable", f.prolandReadable()},
            {"rule", f.describe()}};
}

nlohmann::json toJson(const DemReport& r) {
    const nlohmann::json levels = residualLevelsJson(r.levels);
    nlohmann::json input = demInputJson(r.input, r.inputInfo, r.band, r.nodata);
    input["files"] = r.inputs;
    nlohmann::json j = {{"input", input},
            {"output", r.output},
            {"sampling", r.sampling},
            {"header", {{"min_level", r.header.minLevel},
                        {"max_level", r.header.maxLevel},
                        {"tile_size", r.header.tileSize},
                        {"scale", r.header.scale}}},
            {"tile_fit", r.tileFit ? toJson(*r.tileFit) : nlohmann::json()}, // null: tiles as given
            {"scales_tried", r.scalesTried},
            {"tiles", r.tiles},
            {"shared_tiles", r.sharedTiles},
            {"bytes", r.bytes},
            {"files", residualFilesJson(r.files)},
            {"bits_per_sample", r.finestSamples ? 8.0 * static_cast<double>(r.bytes) / static_cast<double>(r.finestSamples) : 0.0},
            {"finest_samples", r.finestSamples},
            {"nodata_filled", r.nodataFilled},
            {"levels", levels},
            {"georeference", r.georeference ? toJson(*r.georeference) : nlohmann::json()}, // null: not georeferenced
            {"threads", r.threads},
            {"seconds", r.seconds}};
    j.update(residualCodingJson(r.coding));
    return j;
}

} // namespace pyramid
