#include "libpyramid/verify/dem_verify.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <optional>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/dem/dem_sampling.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/input/input_list.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/map_sources.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

bool DemVerifyReport::ok() const {
    return std::all_of(levels.begin(), levels.end(), [](const DemVerifyLevel& l) { return l.beyondBound == 0 && l.nonFinite == 0; });
}


namespace {

// A whole pyramid: a file (not a region file on its own) or a region set.
struct WholePyramid {
    PyramidSet set;
    ResidualHeader header; // the main file's, with the set's deepest level as maxLevel
};

// The whole pyramid `file` names: a residual file alone, or the region set it, its index or its
// directory names.
WholePyramid wholePyramid(const std::string& file) {
    WholePyramid w;
    if (findRegionIndex(file).empty()) {
        w.set.main = file;
        w.header = ResidualFileReader::open(file)->header();
        if (w.header.rootLevel != 0) {
            fail(file, "a region file cannot be verified on its own against a whole-map source");
        }
        return w;
    }
    w.set = openPyramidSet(file);
    if (w.set.kind != PyramidKind::Residual) {
        fail(w.set.name(), "holds an ortho pyramid, not a residual one");
    }
    w.header = ResidualFileReader::readHeader(w.set.main);
    w.header.maxLevel = setMaxLevel(w.set);
    return w;
}

// The tiles of each level that are compared (x + y * side), each level's found from the level
// above: every tile of the levels the main file holds (nullopt: all of them, less those where the
// source has no heights of that level: compareLevels asks); below, the tiles under which the source
// may have heights of their level (HeightSource::mayHaveHeightsAt). A sparse set
// (formats/sparse_set.hpp) stores nothing where the source has no heights, and where a coarse input
// alone is, nothing below that input's level: both give the upsampled heights there, which are
// not the source's at deeper levels, so they are not compared. A tile with heights that no file
// holds is compared (with the continuation of the files above it, which fails where data was
// left out).
// Whether the source may have heights of level l under tile (tx, ty) of n intervals (the samples
// it owns), on a finest grid of R << M intervals.
bool tileHasHeights(const HeightSource& sampler, int l, int M, int64_t R, int n, int tx, int ty) {
    const int64_t stride = int64_t{1} << (M - l);
    const int64_t x0 = static_cast<int64_t>(tx) * n * stride, y0 = static_cast<int64_t>(ty) * n * stride;
    const int64_t last = R << M;
    return sampler.mayHaveHeightsAt(l, x0, y0, std::min(last, x0 + n * stride), std::min(last, y0 + n * stride));
}

std::vector<std::optional<std::vector<int64_t>>> comparedTiles(const WholePyramid& whole,
                                                               const std::vector<FileLevelProducer>& producers,
                                                               const HeightSource& sampler) {
    const ResidualHeader& h = whole.header;
    const int M = h.maxLevel;
    const int mainLast = ResidualFileReader::readHeader(whole.set.main).maxLevel;
    const int64_t R = h.tileSize >> h.minLevel;
    std::vector<std::optional<std::vector<int64_t>>> levels;
    for (int l = 0; l <= M; ++l) {
        if (l <= mainLast || l <= h.minLevel) {
            levels.emplace_back(std::nullopt);
            continue;
        }
        const int side = 1 << (l - producers[static_cast<size_t>(l)].delta);
        const int above = 1 << (l - 1 - producers[static_cast<size_t>(l) - 1].delta);
        const int n = producers[static_cast<size_t>(l)].n;
        const auto wanted = [&](int tx, int ty) { return tileHasHeights(sampler, l, M, R, n, tx, ty); };
        std::vector<int64_t> tiles;
        const auto visit = [&](int64_t parent) {
            const int px = static_cast<int>(parent % above), py = static_cast<int>(parent / above);
            for (int c = 0; c < 4; ++c) {
                const int tx = 2 * px + (c & 1), ty = 2 * py + (c >> 1);
                if (wanted(tx, ty)) {
                    tiles.push_back(tx + static_cast<int64_t>(ty) * side);
                }
            }
        };
        if (levels.back()) {
            for (const int64_t parent : *levels.back()) {
                visit(parent);
            }
        } else {
            for (int64_t parent = 0; parent < static_cast<int64_t>(above) * above; ++parent) {
                visit(parent);
            }
        }
        std::sort(tiles.begin(), tiles.end());
        levels.emplace_back(std::move(tiles));
    }
    return levels;
}

// Every level of `file` (of header `h`) rebuilt and compared with the finest-grid heights
// `sampler` gives, subsampled to each level.
DemVerifyReport compareLevels(const std::string& file, const WholePyramid& whole, const std::string& sourceName,
                              const HeightSource& sampler, int threadOption,
                              const std::function<void(int64_t, int64_t)>& progress) {
    const ResidualHeader& h = whole.header;
    const int M = h.maxLevel;
    const int64_t R = h.tileSize >> h.minLevel;
    const int threads = workerThreads(threadOption);
    DemVerifyReport report;
    report.file = file;
    report.source = sourceName;
    report.scale = h.scale;
    report.bound = h.scale / 2.0;
    std::vector<FileLevelProducer> producers;
    for (int l = 0; l <= M; ++l) {
        producers.push_back(makeSetLevelProducer(whole.set, l));
    }
    const std::vector<std::optional<std::vector<int64_t>>> toCompare = comparedTiles(whole, producers, sampler);
    int64_t total = 0;
    for (int l = 0; l <= M; ++l) {
        const int64_t side = int64_t{1} << (l - producers[static_cast<size_t>(l)].delta);
        const auto& list = toCompare[static_cast<size_t>(l)];
        total += list ? static_cast<int64_t>(list->size()) : side * side;
    }
    int64_t done = 0;
    std::mutex progressMutex;
    for (int l = 0; l <= M; ++l) {
        const FileLevelProducer& lp = producers[static_cast<size_t>(l)];
        const int side = 1 << (l - lp.delta);
        const auto& list = toCompare[static_cast<size_t>(l)];
        const int64_t count = list ? static_cast<int64_t>(list->size()) : static_cast<int64_t>(side) * side;
        const int64_t Nl = R << l;
        struct TileResult {
            int64_t samples = 0, beyond = 0, nonFinite = 0;
            double maxError = 0.0, sumSquares = 0.0;
        };
        std::vector<TileResult> results(static_cast<size_t>(count));
        parallelFor(count, threads, [&](int64_t at) {
            const int64_t k = list ? (*list)[static_cast<size_t>(at)] : at;
            const int tx = static_cast<int>(k % side), ty = static_cast<int>(k / side);
            if (!list && !tileHasHeights(sampler, l, M, R, lp.n, tx, ty)) {
                return; // no heights of this level here (nor compared in the count)
            }
            const auto tile = lp.fileTile(l, tx, ty);
            const int S = lp.n + 5;
            // The samples this tile owns: [t*n, t*n + n), plus the map's last row and column.
            SourceGrid grid;
            grid.stride = int64_t{1} << (M - l);
            const int64_t px0 = static_cast<int64_t>(tx) * lp.n, py0 = static_cast<int64_t>(ty) * lp.n;
            grid.nx = std::min<int64_t>(lp.n, Nl - px0) + (px0 + lp.n >= Nl ? 1 : 0);
            grid.ny = std::min<int64_t>(lp.n, Nl - py0) + (py0 + lp.n >= Nl ? 1 : 0);
            grid.x0 = px0 * grid.stride;
            grid.y0 = py0 * grid.stride;
            sampler.sample(grid);
            TileResult& r = results[static_cast<size_t>(at)];
            for (int64_t j = 0; j < grid.ny; ++j) {
                for (int64_t i = 0; i < grid.nx; ++i) {
                    const size_t g = static_cast<size_t>(i + j * grid.nx);
                    if (grid.valid[g] != 1) {
                        continue;
                    }
                    const double src = grid.height[g];
                    const double z = tile->zf[static_cast<size_t>((i + 2) + (j + 2) * S)];
                    r.samples += 1;
                    if (!std::isfinite(z) || !std::isfinite(src)) {
                        r.nonFinite += 1;
                        continue;
                    }
                    const double e = std::fabs(z - src);
                    // scale/2, plus the float32 roundings of the reconstruction and the source.
                    const double allowed = report.bound + std::ldexp(std::max(std::fabs(z), std::fabs(src)), -22);
                    r.maxError = std::max(r.maxError, e);
                    r.sumSquares += e * e;
                    r.beyond += e > allowed;
                }
            }
            if (progress) {
                const std::lock_guard<std::mutex> lock(progressMutex);
                progress(++done, total);
            }
        });
        DemVerifyLevel level;
        level.level = l;
        level.tiles = count;
        double sum = 0.0;
        for (const TileResult& r : results) {
            level.samples += r.samples;
            level.maxError = std::max(level.maxError, r.maxError);
            level.beyondBound += r.beyond;
            level.nonFinite += r.nonFinite;
            sum += r.sumSquares;
        }
        const int64_t compared = level.samples - level.nonFinite;
        level.rmsError = compared ? std::sqrt(sum / static_cast<double>(compared)) : 0.0;
        report.levels.push_back(level);
    }
    return report;
}

} // namespace

DemVerifyReport verifyDem(const std::string& file, const std::string& sourcePath, const DemVerifyOptions& options) {
    wholePyramid(file);
    // The source as the preprocessor read it: a file, or the files a VRT, directory or glob
    // names, joined or resampled as preprocessDem does (sphere/planar_mosaic.hpp).
    const auto source = openPlanarMosaic(expandInputs({sourcePath}).paths, 256, false, options.target);
    DemVerifyReport report = verifyDem(file, *source, options);
    report.source = sourcePath;
    return report;
}

DemVerifyReport verifyDem(const std::string& file, const RasterSource& source, const DemVerifyOptions& options) {
    const WholePyramid whole = wholePyramid(file);
    const ResidualHeader& h = whole.header;
    DemEncodeOptions read; // the band and nodata, chosen as the encoder chooses them
    read.band = options.band;
    read.nodata = options.nodata;
    read.ignoreDeclaredNodata = options.ignoreDeclaredNodata;
    const std::optional<double> nodata = checkBandAndNodata(source.info(), read, source.path());
    const int64_t N = static_cast<int64_t>(h.tileSize >> h.minLevel) << h.maxLevel;
    const DemGeometry geometry = makeDemGeometry(source.info().width, source.info().height, N, options.stretch, source.path());
    const DemSampler sampler(source, geometry, options.band, nodata, h.tileSize >> h.minLevel);
    return compareLevels(file, whole, source.path(), sampler, options.threads, options.progress);
}

std::vector<DemVerifyReport> verifySphericalDem(const std::string& directory, const GeodeticMap& map,
                                                const SphericalDemVerifyOptions& options) {
    checkFaceList(options.faces);
    const PlanetBody body = PlanetBody::parse(options.body);
    std::vector<DemVerifyReport> reports;
    int64_t before = 0; // tiles of the faces already compared
    for (const int face : options.faces) {
        const std::string file = faceFilePath(directory, options.name, face);
        const WholePyramid whole = wholePyramid(file);
        const ResidualHeader& h = whole.header;
        const int64_t N = static_cast<int64_t>(h.tileSize >> h.minLevel) << h.maxLevel;
        const FaceSampler faceSampler(map, body, face, FaceGrid{N, FaceGridKind::Vertices}, options.heightScale);
        const FaceHeights heights(faceSampler, static_cast<int64_t>(h.tileSize >> h.minLevel));
        int64_t faceTiles = 0;
        std::function<void(int64_t, int64_t)> progress;
        if (options.progress) {
            // Faces of one build have one header: the total is this face's times their count.
            const auto faces = static_cast<int64_t>(options.faces.size());
            progress = [&, faces](int64_t done, int64_t total) {
                faceTiles = total;
                options.progress(before + done, std::max(total * faces, before + total));
            };
        }
        reports.push_back(compareLevels(file, whole, options.source, heights, options.threads, progress));
        before += faceTiles;
    }
    return reports;
}

std::vector<DemVerifyReport> verifySphericalDem(const std::string& directory, const std::vector<std::string>& inputs,
                                                const SphericalDemVerifyOptions& options) {
    checkFaceList(options.faces);
    const PlanetBody body = PlanetBody::parse(options.body);
    DemEncodeOptions read; // the band and nodata, chosen as the encoder chooses them
    read.band = options.band;
    read.nodata = options.nodata;
    read.ignoreDeclaredNodata = options.ignoreDeclaredNodata;
    const MapSources sources =
        openMapSources(inputs, options.extent, body, read.cacheMegabytes, SampleRead::Float, read.band, read.band + 1,
                       [&](const RasterInfo& info, const std::string& name) { return checkBandAndNodata(info, read, name); });
    SphericalDemVerifyOptions named = options;
    named.source = sources.name;
    return verifySphericalDem(directory, *sources.map, named);
}

nlohmann::json toJson(const DemVerifyReport& r) {
    nlohmann::json levels = nlohmann::json::array();
    for (const DemVerifyLevel& l : r.levels) {
        levels.push_back({{"level", l.level},
                          {"tiles", l.tiles},
                          {"samples", l.samples},
                          {"max_error", l.maxError},
                          {"rms_error", l.rmsError},
                          {"beyond_bound", l.beyondBound},
                          {"non_finite", l.nonFinite}});
    }
    return {{"file", r.file}, {"source", r.source}, {"scale", r.scale}, {"bound", r.bound},
            {"ok", r.ok()},   {"levels", levels}};
}

} // namespace pyramid
