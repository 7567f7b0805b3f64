// The C API over the C++ library: every entry point catches everything, maps it to a status
// and keeps the message for pyramid_last_error().
#include "libpyramid/capi/pyramid.h"

#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/capi/last_error.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/height_query.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"
#include "libpyramid/runtime/colour_producer.hpp"

struct pyramid_file {
    pyramid::PyramidKind kind;
    std::unique_ptr<pyramid::ResidualFileReader> residual;
    std::unique_ptr<pyramid::OrthoFileReader> ortho;
};

struct pyramid_elevation {
    std::unique_ptr<pyramid::ElevationProducer> producer;
};

struct pyramid_ortho {
    std::shared_ptr<pyramid::OrthoProducer> tiles;
    std::unique_ptr<pyramid::ColourProducer> residuals; // when colour residuals
};

namespace {

thread_local std::string lastError;

pyramid_status failWith(pyramid_status status, const std::string& message) {
    lastError = message;
    return status;
}

// Runs `body`, turning exceptions into statuses: Error is a file problem unless `body` already
// decided otherwise by returning a status.
template <class Body>
pyramid_status guarded(Body body) {
    try {
        return body();
    } catch (const pyramid::Error& e) {
        return failWith(PYRAMID_ERROR_FILE, e.what());
    } catch (const std::bad_alloc&) {
        return failWith(PYRAMID_ERROR_MEMORY, "out of memory");
    } catch (const std::exception& e) {
        return failWith(PYRAMID_ERROR_INTERNAL, e.what());
    } catch (...) {
        return failWith(PYRAMID_ERROR_INTERNAL, "unknown error");
    }
}

pyramid_status copyOut(const void* data, size_t bytes, void* buffer, size_t size, size_t* written) {
    if (written) {
        *written = bytes;
    }
    if (!buffer) {
        return PYRAMID_OK;
    }
    if (size < bytes) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "buffer of " + std::to_string(size) + " bytes, " +
                                                    std::to_string(bytes) + " needed");
    }
    std::memcpy(buffer, data, bytes);
    return PYRAMID_OK;
}

bool inside(const pyramid_file* f, int level, int tx, int ty) {
    return f->kind == pyramid::PyramidKind::Residual ? f->residual->header().contains(level, tx, ty)
                                                      : f->ortho->header().contains(level, tx, ty);
}

pyramid_status outside(int level, int tx, int ty) {
    return failWith(PYRAMID_ERROR_ARGUMENT, "no tile (" + std::to_string(level) + "," + std::to_string(tx) + "," +
                                                std::to_string(ty) + ") in this pyramid");
}

// The region paths of an *_open_regions call; false when the array or one of its paths is null.
bool regionList(const char* const* paths, size_t count, std::vector<std::string>& out) {
    if (count > 0 && !paths) {
        return false;
    }
    for (size_t k = 0; k < count; ++k) {
        if (!paths[k]) {
            return false;
        }
        out.emplace_back(paths[k]);
    }
    return true;
}

} // namespace

extern "C" {

int pyramid_version_number(void) { return PYRAMID_VERSION_NUMBER; }

const char* pyramid_version_string(void) {
    static const std::string text = std::to_string(PYRAMID_VERSION_MAJOR) + "." + std::to_string(PYRAMID_VERSION_MINOR) +
                                    "." + std::to_string(PYRAMID_VERSION_PATCH);
    return text.c_str();
}

const char* pyramid_last_error(void) { return lastError.c_str(); }

const char* pyramid_status_name(pyramid_status status) {
    switch (status) {
    case PYRAMID_OK:
        return "ok";
    case PYRAMID_ERROR_ARGUMENT:
        return "argument";
    case PYRAMID_ERROR_FILE:
        return "file";
    case PYRAMID_ERROR_MEMORY:
        return "memory";
    case PYRAMID_ERROR_INTERNAL:
        return "internal";
    case PYRAMID_ERROR_CANCELLED:
        return "cancelled";
    }
    return "unknown";
}

pyramid_status pyramid_open(const char* path, pyramid_file** file) {
    if (!path || !file) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_open: null argument");
    }
    *file = nullptr;
    return guarded([&] {
        auto f = std::make_unique<pyramid_file>();
        // The reader that recognises the file is the one kept: the offset table is read once.
        pyramid::OpenedPyramid opened = pyramid::openPyramid(path);
        f->kind = opened.kind;
        f->residual = std::move(opened.residual);
        f->ortho = std::move(opened.ortho);
        *file = f.release();
        return PYRAMID_OK;
    });
}

void pyramid_close(pyramid_file* file) { delete file; }

pyramid_status pyramid_get_info(const pyramid_file* file, pyramid_info* info) {
    if (!file || !info) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_get_info: null argument");
    }
    std::memset(info, 0, sizeof *info);
    if (file->kind == pyramid::PyramidKind::Residual) {
        const auto& h = file->residual->header();
        info->kind = PYRAMID_KIND_RESIDUAL;
        info->min_level = h.minLevel;
        info->max_level = h.maxLevel;
        info->tile_size = h.tileSize;
        info->root_level = h.rootLevel;
        info->root_tx = h.rootTx;
        info->root_ty = h.rootTy;
        info->scale = h.scale;
        info->channels = 1;
        info->border = 2;
        info->tile_count = h.tileCount();
    } else {
        const auto& h = file->ortho->header();
        info->kind = PYRAMID_KIND_ORTHO;
        info->max_level = h.maxLevel;
        info->tile_size = h.tileSize;
        info->root_level = h.rootLevel;
        info->root_tx = h.rootTx;
        info->root_ty = h.rootTy;
        info->channels = h.channels;
        info->border = h.border();
        info->dxt = h.dxt() ? 1 : 0;
        info->tile_count = h.tileCount();
    }
    return PYRAMID_OK;
}

pyramid_status pyramid_tile_side(const pyramid_file* file, int level, int* side) {
    if (!file || !side) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_tile_side: null argument");
    }
    if (!inside(file, level, 0, 0)) {
        return outside(level, 0, 0);
    }
    *side = file->kind == pyramid::PyramidKind::Residual ? file->residual->header().tileSamples(level)
                                                          : file->ortho->header().tilePixels();
    return PYRAMID_OK;
}

pyramid_status pyramid_read_tile(const pyramid_file* file, int level, int tx, int ty, void* buffer, size_t size,
                                 size_t* written) {
    if (!file) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_read_tile: null file");
    }
    if (!inside(file, level, tx, ty)) {
        return outside(level, tx, ty);
    }
    return guarded([&] {
        if (file->kind == pyramid::PyramidKind::Residual) {
            const std::vector<int16_t> r = file->residual->readTile(level, tx, ty);
            return copyOut(r.data(), r.size() * sizeof(int16_t), buffer, size, written);
        }
        const std::vector<uint8_t> p = file->ortho->readTile(level, tx, ty);
        return copyOut(p.data(), p.size(), buffer, size, written);
    });
}

pyramid_status pyramid_read_tile_bytes(const pyramid_file* file, int level, int tx, int ty, void* buffer,
                                       size_t size, size_t* written) {
    if (!file) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_read_tile_bytes: null file");
    }
    if (!inside(file, level, tx, ty)) {
        return outside(level, tx, ty);
    }
    return guarded([&] {
        const std::vector<uint8_t> b = file->kind == pyramid::PyramidKind::Residual
                                           ? file->residual->readTileBytes(level, tx, ty)
                                           : file->ortho->readTileBytes(level, tx, ty);
        return copyOut(b.data(), b.size(), buffer, size, written);
    });
}

pyramid_status pyramid_elevation_open(const char* residual_path, int tile_size, int grid_size, size_t cache_tiles,
                                      pyramid_elevation** producer) {
    return pyramid_elevation_open_regions(residual_path, nullptr, 0, tile_size, grid_size, cache_tiles, producer);
}

pyramid_status pyramid_elevation_open_regions(const char* residual_path, const char* const* region_paths,
                                              size_t region_count, int tile_size, int grid_size, size_t cache_tiles,
                                              pyramid_elevation** producer) {
    std::vector<std::string> regions;
    if (!residual_path || !producer || !regionList(region_paths, region_count, regions)) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_elevation_open: null argument");
    }
    *producer = nullptr;
    return guarded([&] {
        // The header alone: the producer below reads the offset table, once.
        const pyramid::ResidualHeader h = pyramid::ResidualFileReader::readHeader(residual_path);
        const int n = tile_size == 0 ? h.tileSize : tile_size;
        int delta = 0;
        try {
            delta = pyramid::elevationDelta(h, n);
        } catch (const pyramid::Error& e) {
            return failWith(PYRAMID_ERROR_ARGUMENT, std::string(residual_path) + ": " + e.what());
        }
        pyramid::ResidualProducerOptions ro;
        ro.delta = delta;
        auto residuals = std::make_shared<pyramid::ResidualProducer>(residual_path, regions, ro);
        pyramid::ElevationProducerOptions eo;
        eo.tileSize = n;
        eo.gridSize = grid_size;
        eo.cacheCapacity = cache_tiles == 0 ? 1 : cache_tiles;
        auto p = std::make_unique<pyramid_elevation>();
        try {
            p->producer = std::make_unique<pyramid::ElevationProducer>(residuals, eo);
        } catch (const pyramid::Error& e) {
            return failWith(PYRAMID_ERROR_ARGUMENT, std::string(residual_path) + ": " + e.what());
        }
        *producer = p.release();
        return PYRAMID_OK;
    });
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
    if (level < 0 || level > 30 || tx < 0 || ty < 0 || tx >= (1 << level) || ty >= (1 << level)) {
        return outside(level, tx, ty);
    }
    return guarded([&] {
        const auto tile = producer->producer->tile(level, tx, ty);
        std::memcpy(zf, tile->zf.data(), tile->zf.size() * sizeof(float));
        if (zc) {
            std::memcpy(zc, tile->zc.data(), tile->zc.size() * sizeof(float));
        }
        if (zm) {
            std::memcpy(zm, tile->zm.data(), tile->zm.size() * sizeof(float));
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

pyramid_status pyramid_ortho_open(const char* path, int colour_residuals, size_t cache_tiles, pyramid_ortho** producer) {
    return pyramid_ortho_open_regions(path, nullptr, 0, colour_residuals, cache_tiles, producer);
}

pyramid_status pyramid_ortho_open_regions(const char* path, const char* const* region_paths, size_t region_count,
                                          int colour_residuals, size_t cache_tiles, pyramid_ortho** producer) {
    std::vector<std::string> regions;
    if (!path || !producer || !regionList(region_paths, region_count, regions)) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_ortho_open: null argument");
    }
    *producer = nullptr;
    return guarded([&] {
        auto p = std::make_unique<pyramid_ortho>();
        p->tiles = std::make_shared<pyramid::OrthoProducer>(path, regions);
        if (colour_residuals) {
            p->residuals = std::make_unique<pyramid::ColourProducer>(p->tiles, cache_tiles == 0 ? 1 : cache_tiles);
        }
        *producer = p.release();
        return PYRAMID_OK;
    });
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
    if (level < 0 || level > 30 || tx < 0 || ty < 0 || tx >= (1 << level) || ty >= (1 << level)) {
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

namespace pyramid::capi {

void setLastError(const std::string& message) { lastError = message; }

} // namespace pyramid::capi
