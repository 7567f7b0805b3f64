#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/staging_directory.hpp"
#include "libpyramid/encode/dem/sphere_root_fill.hpp"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/sphere/map_sources.hpp"
#include "libpyramid/support/parallel.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

void FaceHeights::sample(SourceGrid& grid) const {
    grid.height.resize(static_cast<size_t>(grid.nx * grid.ny));
    grid.valid.resize(grid.height.size());
    sampler_.sample(grid.x0, grid.y0, grid.stride, grid.nx, grid.ny, grid.height.data(), grid.valid.data());
}

bool FaceHeights::mayHaveHeights(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    return sampler_.mayHaveValues(x0, y0, x1, y1);
}

double columnsNeedingLevel(int64_t rootIntervals, int level) {
    return level <= 0 ? 0.0 : 4.0 * static_cast<double>(rootIntervals << (level - 1));
}

bool FaceHeights::mayHaveHeightsAt(int level, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    if (rootIntervals_ == 0 || level == 0) {
        return mayHaveHeights(x0, y0, x1, y1);
    }
    return sampler_.mayHaveValuesFinerThan(columnsNeedingLevel(rootIntervals_, level), x0, y0, x1, y1);
}

SphericalDemReport encodeSphericalDem(const std::string& input, const std::string& directory,
                                      const SphericalDemOptions& options) {
    return encodeSphericalDem(std::vector<std::string>{input}, directory, options);
}

namespace {

// Checks the options that do not need the map; throws OptionError.
void checkSphericalDemOptions(const SphericalDemOptions& options) {
    const DemEncodeOptions& o = options.dem;
    o.validate();
    if (!std::isfinite(options.heightScale) || options.heightScale == 0.0) {
        failOption("heightScale", "must be a finite non-zero number, not " + numberText(options.heightScale));
    }
    if (options.fillHeight && !std::isfinite(*options.fillHeight)) {
        failOption("fillHeight", "must be a finite height, not " + numberText(*options.fillHeight));
    }
    checkFaceList(options.faces);
    if (o.region && options.faces.size() != 1) {
        failOption("faces", "a region build encodes one face: give a single face, not " +
                                std::to_string(options.faces.size()));
    }
    if (o.fitTiles) {
        // A face's grid is the cube's, not the map's: no tile size makes one the other.
        failOption("tileSize", "'auto' fits a planar input's grid; cube faces take a number (e.g. 192)");
    }
    if (o.rootTileSize < 2) {
        // The root tile's 2-interval borders fold onto the neighbouring faces: at most a face deep.
        failOption("rootTileSize", "cube faces need a root tile of at least 2 intervals, not " +
                                       std::to_string(o.rootTileSize));
    }
    (void)PlanetBody::parse(options.body);
}

SphericalDemReport encodeMap(const MapSources& sources, const std::vector<std::string>& inputs,
                             const std::string& directory, const SphericalDemOptions& options,
                             std::chrono::steady_clock::time_point start) {
    const DemEncodeOptions& o = options.dem;
    const PlanetBody body = PlanetBody::parse(options.body);
    SphericalDemReport report;
    MapPlacement placement;
    std::optional<double> nodata;
    const std::string input = sources.name;
    const GeodeticMap& map = *sources.map;
    placement = sources.placement;
    nodata = sources.nodata;
    report.input = input;
    report.inputs = inputs;
    report.directory = directory;
    report.inputInfo = sources.info;
    report.band = o.band;
    report.heightScale = options.heightScale;
    report.fillHeight = options.fillHeight;
    report.body = body.describe();
    report.extent = placement.extent;
    report.crs = placement.crs;
    report.nodata = nodata;

    // One face spans a quarter of the equator: at least width / 4 intervals match the map there.
    DemEncodeOptions faceOptions = o;
    faceOptions.stretch = false;
    faceOptions.reconstruction = nullptr;
    if (!faceOptions.maxLevel && !faceOptions.dstMaxLevel) {
        int level = 0;
        const auto rootTile = static_cast<int64_t>(faceOptions.rootTileSize);
        while (level < 24 && placement.columnsAround > columnsNeedingLevel(rootTile, level + 1)) {
            ++level;
        }
        faceOptions.maxLevel = std::max(level, o.minLevel());
    }
    const ResidualHeader header = planDemPyramid(sources.info, faceOptions, input);
    const int64_t N = static_cast<int64_t>(header.tileSize >> header.minLevel) << header.maxLevel;
    report.threads = workerThreads(o.threads);

    // A split build's part writes its share of every face into its part file, and no face.
    std::unique_ptr<StagingDirectory> staging;
    if (!o.share) {
        staging = std::make_unique<StagingDirectory>(directory);
    }
    // The faces' root nodata is one surface: solved for all six whatever options.faces holds, so
    // that each face's bytes are those of a whole planet's build; once, when a face first has
    // nodata at its root (never for a region encoded from its parent's tiles).
    const int64_t R = static_cast<int64_t>(header.tileSize >> header.minLevel);
    std::optional<std::array<GivenRootFill, kCubeFaceCount>> rootFills;
    const int64_t faceTiles = header.tileCount();
    const int64_t totalTiles = faceTiles * static_cast<int64_t>(options.faces.size());
    int64_t finished = 0; // tiles of the faces already done
    int64_t shown = 0;    // progress never goes back, even when --scale auto starts a face over
    for (const int face : options.faces) {
        const FaceSampler sampler(map, body, face, FaceGrid{N, FaceGridKind::Vertices}, options.heightScale);
        const FaceHeights heights(sampler, R);
        ResidualPyramidJob job;
        job.header = header;
        job.heights = &heights;
        job.edges = GridEdges::Folded;
        job.rootFill = [&, face]() -> const GivenRootFill& {
            if (!rootFills) {
                rootFills = solveSphereRootFill(map, body, options.heightScale, N, R, options.fillHeight,
                                                workerThreads(o.threads));
            }
            return (*rootFills)[static_cast<size_t>(face - 1)];
        };
        job.input = input;
        job.pyramid = static_cast<int>(report.faces.size());
        job.pyramids = static_cast<int>(options.faces.size());
        DemEncodeOptions run = faceOptions;
        if (o.progress) {
            run.progress = [&](int64_t done, int64_t total) {
                if (finished + done > shown) {
                    shown = finished + done;
                    o.progress(shown, o.region ? total : totalTiles); // a region: its one face's tiles
                }
            };
        }
        if (options.reconstruction) {
            run.reconstruction = [&, face](int level, int tx, int ty, const std::vector<float>& z) {
                options.reconstruction(face, level, tx, ty, z);
            };
        }
        const auto faceStart = std::chrono::steady_clock::now();
        SphericalDemFaceReport fr;
        fr.face = face;
        // A region build writes the face's region file, named as its set would name it.
        const std::string faceName = faceFileName(options.name, face);
        const std::string name = o.region ? regionFilePath(faceName, o.region->root) : faceName;
        fr.dem.input = input;
        fr.dem.output = (std::filesystem::path(directory) / name).string();
        fr.dem.inputInfo = sources.info;
        fr.dem.band = o.band;
        fr.dem.coding = o.tiles;
        fr.dem.nodata = nodata;
        fr.dem.sampling = "face " + std::to_string(face) + " of the cube, " + std::to_string(N) +
                          " intervals across, sampled bilinearly on the " + body.name() +
                          " body; borders from the neighbouring faces";
        encodeResidualPyramid(job, staging ? staging->path(name) : fr.dem.output, run, fr.dem);
        fr.dem.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - faceStart).count();
        for (int l = 0; l <= header.maxLevel; ++l) {
            const int64_t n = static_cast<int64_t>(header.tileSize >> header.minLevel) << l;
            fr.gsd.push_back(faceGroundSampleDistance(body, face, FaceGrid{n, FaceGridKind::Vertices}));
        }
        report.faces.push_back(std::move(fr));
        finished += faceTiles;
    }
    if (staging) {
        staging->commit();
        for (SphericalDemFaceReport& f : report.faces) {
            if (f.dem.files.empty()) { // a set's bytes are its files', added up when it was written
                f.dem.bytes = std::filesystem::file_size(f.dem.output);
            }
        }
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace

SphericalDemReport encodeSphericalDem(const std::vector<std::string>& inputs, const std::string& directory,
                                      const SphericalDemOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    checkSphericalDemOptions(options);
    const DemEncodeOptions& o = options.dem;
    const PlanetBody body = PlanetBody::parse(options.body);
    const MapSources sources = openMapSources(inputs, options.extent, body, o.cacheMegabytes, SampleRead::Float,
                                              o.band, o.band + 1, [&](const RasterInfo& info, const std::string& name) {
                                                  return checkBandAndNodata(info, o, name);
                                              });
    sources.tell(options.warning);
    SphericalDemReport report = encodeMap(sources, inputs, directory, options, start);
    report.warnings = sources.warnings;
    return report;
}

SphericalDemReport encodeSphericalDem(const MapSources& sources, const std::string& directory,
                                      const SphericalDemOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    checkSphericalDemOptions(options);
    if (!sources.map || sources.map->channels() != 1) {
        fail(sources.name, "a planet's heights need a map of one channel");
    }
    return encodeMap(sources, {sources.name}, directory, options, start);
}

nlohmann::json toJson(const SphericalDemReport& r) {
    nlohmann::json faces = nlohmann::json::array();
    for (const SphericalDemFaceReport& f : r.faces) {
        nlohmann::json dem = toJson(f.dem);
        dem.erase("input"); // the same for every face: at the top
        nlohmann::json gsd = nlohmann::json::array();
        for (size_t l = 0; l < f.gsd.size(); ++l) {
            gsd.push_back({{"level", l}, {"min_metres", f.gsd[l].min}, {"max_metres", f.gsd[l].max}});
        }
        faces.push_back({{"face", f.face}, {"dem", dem}, {"ground_sample_distance", gsd}});
    }
    nlohmann::json input = demInputJson(r.input, r.inputInfo, r.band, r.nodata);
    input["height_scale"] = r.heightScale;
    input["files"] = r.inputs;
    return {{"input", input},
            {"directory", r.directory},
            {"extent", {{"west", r.extent.west}, {"south", r.extent.south}, {"east", r.extent.east},
                        {"north", r.extent.north}}},
            {"body", r.body},
            {"fill", r.fillHeight ? nlohmann::json(*r.fillHeight) : nlohmann::json("smooth")},
            {"crs", r.crs.empty() ? nlohmann::json() : nlohmann::json(r.crs)}, // null: not georeferenced
            {"faces", faces},
            {"warnings", r.warnings},
            {"threads", r.threads},
            {"seconds", r.seconds}};
}

} // namespace pyramid
