// The C API's ortho producer (pyramid.h): an ortho file (or set) opened for its tiles as they are
// stored, or rebuilt from colour residuals.
#include "libpyramid/capi/pyramid.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "formats/ortho_file.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "libpyramid/capi/capi_open.hpp"
#include "libpyramid/capi/capi_status.hpp"
#include "libpyramid/capi/capi_tiles.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"

struct pyramid_ortho {
    std::shared_ptr<pyramid::OrthoProducer> tiles;
    std::unique_ptr<pyramid::ColourProducer> residuals; // when colour residuals
};

namespace {

using namespace pyramid::capi;

pyramid_status openOrthoSources(const char* function, const pyramid_source* mainSource,
                                const pyramid_source* const* regions, size_t regionCount,
                                const pyramid_ortho_options* options, pyramid_ortho** producer) {
    const auto build = [function](const pyramid_ortho_options& o, const ByteSourcePtr& mainBytes,
                                  const std::vector<ByteSourcePtr>& regionBytes, std::unique_ptr<pyramid_ortho>& made) {
        if (o.colour_residuals != 0 && o.colour_residuals != 1) {
            return failWith(PYRAMID_ERROR_ARGUMENT, std::string(function) + ": colour_residuals " +
                                                        std::to_string(o.colour_residuals) + " is neither 0 nor 1");
        }
        made = std::make_unique<pyramid_ortho>();
        made->tiles = std::make_shared<pyramid::OrthoProducer>(mainBytes, regionBytes);
        if (o.colour_residuals == 1) {
            made->residuals =
                std::make_unique<pyramid::ColourProducer>(made->tiles, o.cache_tiles == 0 ? 1 : o.cache_tiles);
        }
        return PYRAMID_OK;
    };
    return openSources(mainSource, regions, regionCount, options, function, producer, build);
}

pyramid_status openOrthoRegions(const char* function, const char* path, const char* const* regionPaths,
                                size_t regionCount, int colourResiduals, size_t cacheTiles, pyramid_ortho** producer) {
    return openRegionPaths(path, regionPaths, regionCount, function, producer,
                           [&](const pyramid_source* main, const pyramid_source* const* regions, size_t count) {
                               pyramid_ortho_options options{};
                               options.struct_size = sizeof options;
                               options.colour_residuals = colourResiduals;
                               options.cache_tiles = cacheTiles;
                               return openOrthoSources(function, main, regions, count, &options, producer);
                           });
}

} // namespace

extern "C" {

pyramid_status pyramid_ortho_open(const char* path, int colour_residuals, size_t cache_tiles, pyramid_ortho** producer) {
    const char* function = "pyramid_ortho_open";
    return openPath(path, function, producer, [&](const char* main, const char* const* regions, size_t count) {
        return openOrthoRegions(function, main, regions, count, colour_residuals, cache_tiles, producer);
    });
}

pyramid_status pyramid_ortho_open_regions(const char* path, const char* const* region_paths, size_t region_count,
                                          int colour_residuals, size_t cache_tiles, pyramid_ortho** producer) {
    return openOrthoRegions("pyramid_ortho_open_regions", path, region_paths, region_count, colour_residuals,
                            cache_tiles, producer);
}

pyramid_status pyramid_ortho_open_sources(const pyramid_source* main_source, const pyramid_source* const* regions,
                                          size_t region_count, const pyramid_ortho_options* options,
                                          pyramid_ortho** producer) {
    return openOrthoSources("pyramid_ortho_open_sources", main_source, regions, region_count, options, producer);
}

void pyramid_ortho_close(pyramid_ortho* producer) { delete producer; }

pyramid_status pyramid_ortho_layout(const pyramid_ortho* producer, int* side, int* channels) {
    if (!producer || !side || !channels) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_ortho_layout: null argument");
    }
    const pyramid::OrthoHeader& h = producer->tiles->header();
    *side = h.tilePixels();
    *channels = h.channels;
    return PYRAMID_OK;
}

pyramid_status pyramid_ortho_tile(pyramid_ortho* producer, int level, int tx, int ty, unsigned char* pixels,
                                  size_t size) {
    if (!producer || !pixels) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_ortho_tile: null argument");
    }
    if (!pyramid::isQuadtreeTile(level, tx, ty)) {
        return outside(level, tx, ty);
    }
    return guarded([&] {
        if (producer->residuals) {
            const auto tile = producer->residuals->tile(level, tx, ty);
            return copyOut(tile->data(), tile->size(), pixels, size, nullptr);
        }
        if (!producer->tiles->hasTile(level, tx, ty)) {
            return outside(level, tx, ty);
        }
        const std::vector<uint8_t> tile = producer->tiles->tile(level, tx, ty);
        return copyOut(tile.data(), tile.size(), pixels, size, nullptr);
    });
}

} // extern "C"
