// The C API's elevation and normal producers (pyramid.h): the residual file (or set) opened as an
// elevation producer, its tiles and heights at points, and the normals of its tiles.
#include "libpyramid/capi/pyramid.h"

#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/capi/capi_open.hpp"
#include "libpyramid/capi/capi_sized.hpp"
#include "libpyramid/capi/capi_status.hpp"
#include "libpyramid/capi/capi_tiles.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/height_query.hpp"
#include "libpyramid/runtime/normal_producer.hpp"

struct pyramid_elevation {
    std::shared_ptr<pyramid::ElevationProducer> producer; // shared with its normal producers
};

struct pyramid_normal {
    std::unique_ptr<pyramid::NormalProducer> producer;
};

namespace {

using namespace pyramid::capi;

pyramid_status openElevationSources(const char* function, const pyramid_source* mainSource,
                                    const pyramid_source* const* regions, size_t regionCount,
                                    const pyramid_elevation_options* options, pyramid_elevation** producer) {
    const auto build = [](const pyramid_elevation_options& o, const ByteSourcePtr& mainBytes,
                          const std::vector<ByteSourcePtr>& regionBytes, std::unique_ptr<pyramid_elevation>& made) {
        const std::string& name = mainBytes->name();
        // The header alone: the producer below reads the offset table, once.
        const pyramid::ResidualHeader h = pyramid::ResidualFileReader::readHeader(*mainBytes);
        const int n = o.tile_size == 0 ? h.tileSize : o.tile_size;
        int delta = 0;
        // The tiling's errors name the file (the source's name) themselves.
        try {
            delta = pyramid::elevationDelta(h, n, name);
        } catch (const pyramid::Error& e) {
            return failWith(PYRAMID_ERROR_ARGUMENT, e.what());
        }
        pyramid::ResidualProducerOptions ro;
        ro.delta = delta;
        ro.scale = o.scale == 0.0f ? 1.0f : o.scale;
        auto residuals = std::make_shared<pyramid::ResidualProducer>(mainBytes, regionBytes, ro);
        pyramid::ElevationProducerOptions eo;
        eo.tileSize = n;
        eo.gridSize = o.grid_size;
        eo.cacheCapacity = o.cache_tiles == 0 ? 1 : o.cache_tiles;
        made = std::make_unique<pyramid_elevation>();
        try {
            made->producer = std::make_shared<pyramid::ElevationProducer>(residuals, eo);
        } catch (const pyramid::Error& e) {
            return failWith(PYRAMID_ERROR_ARGUMENT, e.what());
        }
        return PYRAMID_OK;
    };
    return openSources(mainSource, regions, regionCount, options, function, producer, build);
}

pyramid_status openElevationRegions(const char* function, const char* path, const char* const* regionPaths,
                                    size_t regionCount, int tileSize, int gridSize, size_t cacheTiles,
                                    pyramid_elevation** producer) {
    return openRegionPaths(path, regionPaths, regionCount, function, producer,
                           [&](const pyramid_source* main, const pyramid_source* const* regions, size_t count) {
                               pyramid_elevation_options options{};
                               options.struct_size = sizeof options;
                               options.tile_size = tileSize;
                               options.grid_size = gridSize;
                               options.cache_tiles = cacheTiles;
                               return openElevationSources(function, main, regions, count, &options, producer);
                           });
}

} // namespace

extern "C" {

pyramid_status pyramid_elevation_open(const char* residual_path, int tile_size, int grid_size, size_t cache_tiles,
                                      pyramid_elevation** producer) {
    const char* function = "pyramid_elevation_open";
    return openPath(residual_path, function, producer, [&](const char* main, const char* const* regions, size_t count) {
        return openElevationRegions(function, main, regions, count, tile_size, grid_size, cache_tiles, producer);
    });
}

pyramid_status pyramid_elevation_open_regions(const char* residual_path, const char* const* region_paths,
                                              size_t region_count, int tile_size, int grid_size, size_t cache_tiles,
                                              pyramid_elevation** producer) {
    return openElevationRegions("pyramid_elevation_open_regions", residual_path, region_paths, region_count,
                                tile_size, grid_size, cache_tiles, producer);
}

pyramid_status pyramid_elevation_open_sources(const pyramid_source* main_source, const pyramid_source* const* regions,
                                              size_t region_count, const pyramid_elevation_options* options,
                                              pyramid_elevation** producer) {
    return openElevationSources("pyramid_elevation_open_sources", main_source, regions, region_count, options,
                                producer);
}

void pyramid_elevation_close(pyramid_elevation* producer) { delete producer; }

int pyramid_elevation_side(const pyramid_elevation* producer) {
    return producer ? producer->producer->tileSize() + 5 : 0;
}

pyramid_status pyramid_elevation_tile(pyramid_elevation* producer, int level, int tx, int ty, float* zf, float* zc,
                                      float* zm, size_t count) {
    if (!producer || !zf) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_elevation_tile: null argument");
    }
    const size_t side = static_cast<size_t>(producer->producer->tileSize()) + 5;
    if (count < side * side) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "arrays of " + std::to_string(count) + " floats, " +
                                                    std::to_string(side * side) + " needed");
    }
    if (!pyramid::isQuadtreeTile(level, tx, ty)) {
        return outside(level, tx, ty);
    }
    return guarded([&] {
        const auto tile = producer->producer->tile(level, tx, ty);
        std::memcpy(zf, tile->zf.data(), tile->zf.size() * sizeof(float));
        if (zc) {
            std::memcpy(zc, tile->zc.data(), tile->zc.size() * sizeof(float));
        }
        if (zm) {
            std::memcpy(zm, tile->zm().data(), tile->zm().size() * sizeof(float));
        }
        return PYRAMID_OK;
    });
}

pyramid_status pyramid_elevation_height(pyramid_elevation* producer, int level, double u, double v, double* height) {
    if (!producer || !height) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_elevation_height: null argument");
    }
    if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0) || level < -1 || level > producer->producer->maxLevel()) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "point (" + std::to_string(u) + ", " + std::to_string(v) +
                                                    ") at level " + std::to_string(level) + " is outside the pyramid");
    }
    return guarded([&] {
        *height = pyramid::heightAt(*producer->producer, u, v, level).height;
        return PYRAMID_OK;
    });
}

pyramid_status pyramid_normal_open(pyramid_elevation* elevations, const pyramid_normal_options* options,
                                   pyramid_normal** producer) {
    if (producer) {
        *producer = nullptr; // whenever the open fails, as every open
    }
    if (!elevations || !options || !producer) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_normal_open: null argument");
    }
    pyramid_normal_options o{};
    if (!readSized(options, o, "pyramid_normal_open: options")) {
        return PYRAMID_ERROR_ARGUMENT;
    }
    if (o.deformation != PYRAMID_DEFORM_PLANE && o.deformation != PYRAMID_DEFORM_SPHERE) {
        return failWith(PYRAMID_ERROR_ARGUMENT,
                        "pyramid_normal_open: deformation " + std::to_string(o.deformation) + " is not plane or sphere");
    }
    return guarded([&] {
        pyramid::NormalProducerOptions no;
        no.deformation = o.deformation == PYRAMID_DEFORM_SPHERE ? pyramid::Deformation::Sphere : pyramid::Deformation::Plane;
        no.size = o.size;
        no.cacheCapacity = o.cache_tiles == 0 ? 1 : o.cache_tiles;
        auto p = std::make_unique<pyramid_normal>();
        try {
            p->producer = std::make_unique<pyramid::NormalProducer>(elevations->producer, no);
        } catch (const pyramid::Error& e) {
            return failWith(PYRAMID_ERROR_ARGUMENT, std::string("pyramid_normal_open: ") + e.what());
        }
        *producer = p.release();
        return PYRAMID_OK;
    });
}

void pyramid_normal_close(pyramid_normal* producer) { delete producer; }

int pyramid_normal_side(const pyramid_normal* producer) { return producer ? producer->producer->tileSize() + 1 : 0; }

pyramid_status pyramid_normal_tile(pyramid_normal* producer, int level, int tx, int ty, float* normals, size_t count) {
    if (!producer || !normals) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_normal_tile: null argument");
    }
    const size_t side = static_cast<size_t>(producer->producer->tileSize()) + 1;
    if (count < 4 * side * side) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "an array of " + std::to_string(count) + " floats, " +
                                                    std::to_string(4 * side * side) + " needed");
    }
    if (!pyramid::isQuadtreeTile(level, tx, ty)) {
        return outside(level, tx, ty);
    }
    return guarded([&] {
        const auto tile = producer->producer->tile(level, tx, ty);
        std::memcpy(normals, tile->normals.data(), tile->normals.size() * sizeof(float));
        return PYRAMID_OK;
    });
}

} // extern "C"
