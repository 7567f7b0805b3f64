// The C API's files (pyramid.h, "Files"): a residual or ortho file opened from a source, its
// header and offset table, its tiles decoded or as stored.
#include "libpyramid/capi/pyramid.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "formats/byte_source.hpp"
#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/capi/capi_sized.hpp"
#include "libpyramid/capi/capi_sources.hpp"
#include "libpyramid/capi/capi_status.hpp"
#include "libpyramid/capi/capi_tiles.hpp"

struct pyramid_file {
    pyramid::PyramidKind kind;
    std::unique_ptr<pyramid::ResidualFileReader> residual;
    std::unique_ptr<pyramid::OrthoFileReader> ortho;
};

namespace {

using namespace pyramid::capi;

bool inside(const pyramid_file* f, int level, int tx, int ty) {
    return f->kind == pyramid::PyramidKind::Residual ? f->residual->header().contains(level, tx, ty)
                                                      : f->ortho->header().contains(level, tx, ty);
}

// What the header and offset table say of tile (level, tx, ty), which must be inside the file.
pyramid_tile_info tileInfo(const pyramid_file* f, int level, int tx, int ty) {
    pyramid_tile_info t{};
    t.struct_size = sizeof t;
    pyramid::TileTable::Range r;
    uint64_t dataStart = 0;
    if (f->kind == pyramid::PyramidKind::Residual) {
        t.side = f->residual->header().tileSamples(level);
        t.channels = 1;
        t.decoded_bytes = static_cast<size_t>(t.side) * static_cast<size_t>(t.side) * sizeof(int16_t);
        r = f->residual->tileRange(level, tx, ty);
        dataStart = f->residual->table().dataStart();
    } else {
        const pyramid::OrthoHeader& h = f->ortho->header();
        t.side = h.tilePixels();
        t.channels = h.channels;
        t.decoded_bytes = static_cast<size_t>(t.side) * static_cast<size_t>(t.side) * static_cast<size_t>(t.channels);
        r = f->ortho->tileRange(level, tx, ty);
        dataStart = f->ortho->table().dataStart();
    }
    t.exists = r.size() > 0 ? 1 : 0;
    t.stored_bytes = static_cast<size_t>(r.size());
    t.offset = t.exists ? dataStart + r.begin : 0;
    return t;
}

pyramid_status absent(int level, int tx, int ty, size_t* written) {
    if (written) {
        *written = 0;
    }
    return failWith(PYRAMID_ERROR_NOT_FOUND,
                    "tile " + pyramid::tileCoordinates(level, tx, ty) + " is not stored (empty byte range)");
}

// pyramid_read_tile (decoded samples) and pyramid_read_tile_bytes (the stored blob): the size
// needed comes from the header, the existence from the offset table, so a size query or a
// buffer too small reads nothing.
pyramid_status readTileInto(const pyramid_file* file, int level, int tx, int ty, void* buffer, size_t size,
                            size_t* written, const char* function, bool stored) {
    if (!file) {
        return failWith(PYRAMID_ERROR_ARGUMENT, std::string(function) + ": null file");
    }
    if (!inside(file, level, tx, ty)) {
        if (written) {
            *written = 0;
        }
        return outside(level, tx, ty);
    }
    return guarded([&] {
        const pyramid_tile_info t = tileInfo(file, level, tx, ty);
        if (!t.exists) {
            return absent(level, tx, ty, written);
        }
        const size_t bytes = stored ? t.stored_bytes : t.decoded_bytes;
        if (written) {
            *written = bytes;
        }
        if (!buffer) {
            return PYRAMID_OK;
        }
        if (size < bytes) {
            return tooSmall(size, bytes);
        }
        const bool residual = file->kind == pyramid::PyramidKind::Residual;
        if (stored) {
            const std::vector<uint8_t> b =
                residual ? file->residual->readTileBytes(level, tx, ty) : file->ortho->readTileBytes(level, tx, ty);
            return copyOut(b.data(), b.size(), buffer, size, written);
        }
        if (residual) {
            const std::vector<int16_t> r = file->residual->readTile(level, tx, ty);
            return copyOut(r.data(), r.size() * sizeof(int16_t), buffer, size, written);
        }
        const std::vector<uint8_t> p = file->ortho->readTile(level, tx, ty);
        return copyOut(p.data(), p.size(), buffer, size, written);
    });
}

} // namespace

extern "C" {

pyramid_status pyramid_open(const char* path, pyramid_file** file) {
    if (!path || !file) {
        if (file) {
            *file = nullptr;
        }
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_open: null argument");
    }
    const pyramid_source source = pathSource(path);
    return pyramid_open_source(&source, file);
}

pyramid_status pyramid_open_source(const pyramid_source* source, pyramid_file** file) {
    if (!file) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_open_source: null argument");
    }
    *file = nullptr;
    return guarded([&] {
        SourceSet sources;
        std::shared_ptr<const pyramid::ByteSource> bytes;
        if (!sources.make(source, "pyramid_open_source", bytes)) {
            return PYRAMID_ERROR_ARGUMENT;
        }
        auto f = std::make_unique<pyramid_file>();
        // The reader that recognises the file is the one kept: the offset table is read once.
        pyramid::OpenedPyramid opened = pyramid::openPyramid(std::move(bytes));
        f->kind = opened.kind;
        f->residual = std::move(opened.residual);
        f->ortho = std::move(opened.ortho);
        sources.arm();
        *file = f.release();
        return PYRAMID_OK;
    });
}

void pyramid_close(pyramid_file* file) { delete file; }

pyramid_status pyramid_get_file_info(const pyramid_file* file, pyramid_file_info* info) {
    if (!file || !info) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_get_file_info: null argument");
    }
    return guarded([&] {
        pyramid_file_info full{};
        full.struct_size = sizeof full;
        const pyramid::TileTable* table = nullptr;
        if (file->kind == pyramid::PyramidKind::Residual) {
            const auto& h = file->residual->header();
            full.kind = PYRAMID_KIND_RESIDUAL;
            full.min_level = h.minLevel;
            full.max_level = h.maxLevel;
            full.tile_size = h.tileSize;
            full.root_level = h.rootLevel;
            full.root_tx = h.rootTx;
            full.root_ty = h.rootTy;
            full.scale = h.scale;
            full.channels = 1;
            full.border = 2;
            full.tile_count = h.tileCount();
            table = &file->residual->table();
        } else {
            const auto& h = file->ortho->header();
            full.kind = PYRAMID_KIND_ORTHO;
            full.max_level = h.maxLevel;
            full.tile_size = h.tileSize;
            full.root_level = h.rootLevel;
            full.root_tx = h.rootTx;
            full.root_ty = h.rootTy;
            full.channels = h.channels;
            full.border = h.border();
            full.dxt = h.dxt() ? 1 : 0;
            full.tile_count = h.tileCount();
            table = &file->ortho->table();
        }
        full.source_size = table->fileSize();
        full.data_offset = table->dataStart();
        // The counts walk the whole table: only for callers whose struct holds them.
        if (info->struct_size >= offsetof(pyramid_file_info, stored_tiles) + sizeof full.stored_tiles) {
            full.stored_tiles = table->storedTiles();
        }
        if (info->struct_size >= offsetof(pyramid_file_info, distinct_tiles) + sizeof full.distinct_tiles) {
            full.distinct_tiles = table->distinctRanges();
        }
        return writeSized(full, info, "pyramid_get_file_info") ? PYRAMID_OK : PYRAMID_ERROR_ARGUMENT;
    });
}

pyramid_status pyramid_get_info(const pyramid_file* file, pyramid_info* info) {
    if (!file || !info) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_get_info: null argument");
    }
    // The members pyramid_file_info shares with pyramid_info, before the table's counts.
    pyramid_file_info full{};
    full.struct_size = offsetof(pyramid_file_info, source_size);
    const pyramid_status status = pyramid_get_file_info(file, &full);
    if (status != PYRAMID_OK) {
        return status;
    }
    std::memset(info, 0, sizeof *info);
    info->kind = full.kind;
    info->max_level = full.max_level;
    info->tile_size = full.tile_size;
    info->root_level = full.root_level;
    info->root_tx = full.root_tx;
    info->root_ty = full.root_ty;
    info->min_level = full.min_level;
    info->scale = full.scale;
    info->channels = full.channels;
    info->border = full.border;
    info->dxt = full.dxt;
    info->tile_count = full.tile_count;
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

pyramid_status pyramid_tile_stat(const pyramid_file* file, int level, int tx, int ty, pyramid_tile_info* info) {
    if (!file || !info) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_tile_stat: null argument");
    }
    return guarded([&] {
        pyramid_tile_info full{};
        full.struct_size = sizeof full;
        const bool in = inside(file, level, tx, ty);
        if (in) {
            full = tileInfo(file, level, tx, ty);
        }
        if (!writeSized(full, info, "pyramid_tile_stat")) {
            return PYRAMID_ERROR_ARGUMENT;
        }
        return in ? PYRAMID_OK : outside(level, tx, ty);
    });
}

pyramid_status pyramid_read_tile(const pyramid_file* file, int level, int tx, int ty, void* buffer, size_t size,
                                 size_t* written) {
    return readTileInto(file, level, tx, ty, buffer, size, written, "pyramid_read_tile", false);
}

pyramid_status pyramid_read_tile_bytes(const pyramid_file* file, int level, int tx, int ty, void* buffer,
                                       size_t size, size_t* written) {
    return readTileInto(file, level, tx, ty, buffer, size, written, "pyramid_read_tile_bytes", true);
}

} // extern "C"
