// The C API over the C++ library: every entry point catches everything, maps it to a status
// and keeps the message for pyramid_last_error().
#include "libpyramid/capi/pyramid.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "formats/byte_source.hpp"
#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/capi/capi_sized.hpp"
#include "libpyramid/capi/capi_status.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/normal_producer.hpp"
#include "libpyramid/runtime/height_query.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"

struct pyramid_file {
    pyramid::PyramidKind kind;
    std::unique_ptr<pyramid::ResidualFileReader> residual;
    std::unique_ptr<pyramid::OrthoFileReader> ortho;
};

struct pyramid_elevation {
    std::shared_ptr<pyramid::ElevationProducer> producer; // shared with its normal producers
};

struct pyramid_normal {
    std::unique_ptr<pyramid::NormalProducer> producer;
};

struct pyramid_ortho {
    std::shared_ptr<pyramid::OrthoProducer> tiles;
    std::unique_ptr<pyramid::ColourProducer> residuals; // when colour residuals
};

namespace {

thread_local std::string lastError;

using pyramid::capi::failWith;
using pyramid::capi::guarded;
using pyramid::capi::readSized;
using pyramid::capi::writeSized;

pyramid_status tooSmall(size_t size, size_t bytes);

pyramid_status copyOut(const void* data, size_t bytes, void* buffer, size_t size, size_t* written) {
    if (written) {
        *written = bytes;
    }
    if (!buffer) {
        return PYRAMID_OK;
    }
    if (size < bytes) {
        return tooSmall(size, bytes);
    }
    std::memcpy(buffer, data, bytes);
    return PYRAMID_OK;
}

bool inside(const pyramid_file* f, int level, int tx, int ty) {
    return f->kind == pyramid::PyramidKind::Residual ? f->residual->header().contains(level, tx, ty)
                                                      : f->ortho->header().contains(level, tx, ty);
}

pyramid_status outside(int level, int tx, int ty) {
    return failWith(PYRAMID_ERROR_NOT_FOUND, "no tile " + pyramid::tileCoordinates(level, tx, ty) + " in this pyramid");
}

// ---- Sources --------------------------------------------------------------------------------

// A caller's I/O callbacks. release() is called by the destructor only once the open that made
// the source succeeded (arm()): a failed open leaves the callbacks to the caller.
class IoSource final : public pyramid::ByteSource {
public:
    IoSource(std::string name, const pyramid_io& io) : ByteSource(std::move(name)), io_(io) {}
    ~IoSource() override {
        if (armed_.load(std::memory_order_acquire) && io_.release) {
            io_.release(io_.user);
        }
    }
    void arm() { armed_.store(true, std::memory_order_release); }

    uint64_t size() const override { return io_.size; }

    void readAt(uint64_t offset, void* out, size_t size) const override {
        pyramid::checkRange(*this, io_.size, offset, size);
        if (size == 0) {
            return;
        }
        size_t got = 0;
        const int status = io_.read(io_.user, offset, out, size, &got);
        if (status != 0) {
            pyramid::fail(name(), "read of " + std::to_string(size) + " bytes at offset " + std::to_string(offset) +
                                      " failed (the read callback returned " + std::to_string(status) + ")");
        }
        if (got != size) {
            pyramid::fail(name(), "read of " + std::to_string(size) + " bytes at offset " + std::to_string(offset) +
                                      " returned " + std::to_string(got) + " bytes");
        }
    }

private:
    pyramid_io io_;
    std::atomic<bool> armed_{false};
};

// The sources of one open call: made from the caller's descriptors, armed once the open succeeds.
struct SourceSet {
    std::vector<std::shared_ptr<IoSource>> io;

    void arm() {
        for (const auto& s : io) {
            s->arm();
        }
    }

    // The byte source a descriptor names; false (with the message set) for a bad descriptor.
    // Throws Error when a file cannot be opened.
    bool make(const pyramid_source* in, const char* what, std::shared_ptr<const pyramid::ByteSource>& out) {
        if (!in) {
            failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": null source");
            return false;
        }
        pyramid_source d{};
        if (!readSized(in, d, what)) {
            return false;
        }
        // A C caller may store any int in the enum: read it as one (a value outside the enum is
        // no valid pyramid_source_kind in C++).
        int kind = 0;
        static_assert(sizeof kind == sizeof d.kind);
        std::memcpy(&kind, &d.kind, sizeof kind);
        switch (kind) {
        case PYRAMID_SOURCE_PATH:
            if (!d.path) {
                failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": a path source without a path");
                return false;
            }
            out = pyramid::openFileSource(d.path);
            return true;
        case PYRAMID_SOURCE_MEMORY:
            if (!d.data && d.size > 0) {
                failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": a memory source of " + std::to_string(d.size) +
                                                     " bytes without data");
                return false;
            }
            out = pyramid::memorySource(d.name ? d.name : "(memory)", d.data, d.size);
            return true;
        case PYRAMID_SOURCE_IO: {
            if (!d.io.read) {
                failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": an I/O source without a read callback");
                return false;
            }
            auto s = std::make_shared<IoSource>(d.name ? d.name : "(io)", d.io);
            io.push_back(s);
            out = std::move(s);
            return true;
        }
        }
        failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": unknown source kind " + std::to_string(kind));
        return false;
    }

    // The main source and the region sources of a producer.
    bool makeAll(const pyramid_source* main, const pyramid_source* const* regions, size_t count, const char* what,
                 std::shared_ptr<const pyramid::ByteSource>& mainOut,
                 std::vector<std::shared_ptr<const pyramid::ByteSource>>& regionsOut) {
        if (count > 0 && !regions) {
            failWith(PYRAMID_ERROR_ARGUMENT, std::string(what) + ": null region array");
            return false;
        }
        if (!make(main, what, mainOut)) {
            return false;
        }
        for (size_t k = 0; k < count; ++k) {
            std::shared_ptr<const pyramid::ByteSource> r;
            if (!make(regions[k], what, r)) {
                return false;
            }
            regionsOut.push_back(std::move(r));
        }
        return true;
    }
};

pyramid_source pathSource(const char* path) {
    pyramid_source s{};
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_PATH;
    s.path = path;
    return s;
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

pyramid_status tooSmall(size_t size, size_t bytes) {
    return failWith(PYRAMID_ERROR_ARGUMENT,
                    "buffer of " + std::to_string(size) + " bytes, " + std::to_string(bytes) + " needed");
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


// The region paths of an *_open_regions call as path sources; false when the array or one of
// its paths is null.
bool regionList(const char* const* paths, size_t count, std::vector<pyramid_source>& sources,
                std::vector<const pyramid_source*>& pointers) {
    if (count > 0 && !paths) {
        return false;
    }
    for (size_t k = 0; k < count; ++k) {
        if (!paths[k]) {
            return false;
        }
        sources.push_back(pathSource(paths[k]));
    }
    for (const pyramid_source& s : sources) {
        pointers.push_back(&s);
    }
    return true;
}

// The files a path names (formats/pyramid_set.hpp): a pyramid file alone, or the main file and
// the regions of a set named by its main file (its index beside it), its index or its
// directory. files[0] is the main file; `regions` points into files[1..].
pyramid_status setFiles(const char* path, const char* function, std::vector<std::string>& files,
                        std::vector<const char*>& regions) {
    if (!path) {
        return failWith(PYRAMID_ERROR_ARGUMENT, std::string(function) + ": null argument");
    }
    return guarded([&] {
        if (pyramid::findRegionIndex(path).empty()) {
            files = {path}; // a file alone: its reader says what is wrong with it
            return PYRAMID_OK;
        }
        const pyramid::PyramidSet set = pyramid::openPyramidSet(path);
        files.push_back(set.main);
        files.insert(files.end(), set.regions.begin(), set.regions.end());
        for (size_t k = 1; k < files.size(); ++k) {
            regions.push_back(files[k].c_str());
        }
        return PYRAMID_OK;
    });
}

using ByteSourcePtr = std::shared_ptr<const pyramid::ByteSource>;

// The three ways a producer opens, one protocol for every kind of producer; `*producer` is null
// whenever the open fails.
//
// *_open(path): the files the path names (setFiles), opened as *_open_regions opens them.
template <class Producer, class OpenRegions>
pyramid_status openPath(const char* path, const char* function, Producer** producer, OpenRegions openRegions) {
    std::vector<std::string> files;
    std::vector<const char*> regions;
    if (const pyramid_status s = setFiles(path, function, files, regions); s != PYRAMID_OK) {
        if (producer) {
            *producer = nullptr;
        }
        return s;
    }
    return openRegions(files[0].c_str(), regions.data(), regions.size());
}

// *_open_regions(path, region paths): the paths as path sources, opened as *_open_sources opens
// them (`function` names the call in the message of a null argument).
template <class Producer, class OpenSources>
pyramid_status openRegionPaths(const char* path, const char* const* regionPaths, size_t regionCount,
                               const char* function, Producer** producer, OpenSources openSources) {
    std::vector<pyramid_source> regions;
    std::vector<const pyramid_source*> pointers;
    if (!path || !producer || !regionList(regionPaths, regionCount, regions, pointers)) {
        if (producer) {
            *producer = nullptr;
        }
        return failWith(PYRAMID_ERROR_ARGUMENT, std::string(function) + ": null argument");
    }
    const pyramid_source main = pathSource(path);
    return openSources(&main, pointers.data(), regionCount);
}

// *_open_sources(sources, options): the options read by their size and the sources made, then
// `build(options, main, regions, made)`; when it returns PYRAMID_OK the caller's I/O sources are
// armed (SourceSet) and `made` is handed over.
template <class Options, class Producer, class Build>
pyramid_status openSources(const pyramid_source* main, const pyramid_source* const* regions, size_t regionCount,
                           const Options* options, const char* function, Producer** producer, Build build) {
    if (!producer) {
        return failWith(PYRAMID_ERROR_ARGUMENT, std::string(function) + ": null argument");
    }
    *producer = nullptr;
    Options o{}; // a member the caller's struct lacks is zero
    if (!readSized(options, o, (std::string(function) + ": options").c_str())) {
        return PYRAMID_ERROR_ARGUMENT;
    }
    return guarded([&] {
        SourceSet sources;
        ByteSourcePtr mainBytes;
        std::vector<ByteSourcePtr> regionBytes;
        if (!sources.makeAll(main, regions, regionCount, function, mainBytes, regionBytes)) {
            return PYRAMID_ERROR_ARGUMENT;
        }
        std::unique_ptr<Producer> made;
        const pyramid_status s = build(o, mainBytes, regionBytes, made);
        if (s == PYRAMID_OK) {
            sources.arm();
            *producer = made.release();
        }
        return s;
    });
}

// Each producer's opens: *_open, *_open_regions and *_open_sources end in one function that
// takes the name of the call made, for its messages.

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

int pyramid_version_number(void) { return PYRAMID_VERSION_NUMBER; }

const char* pyramid_version_string(void) {
    static const std::string text = std::to_string(PYRAMID_VERSION_MAJOR) + "." + std::to_string(PYRAMID_VERSION_MINOR) +
                                    "." + std::to_string(PYRAMID_VERSION_PATCH);
    return text.c_str();
}

const char* pyramid_last_error(void) { return lastError.c_str(); }

const char* pyramid_status_name(pyramid_status status) {
    int value = 0; // any int a C caller passes, read as one (see make())
    static_assert(sizeof value == sizeof status);
    std::memcpy(&value, &status, sizeof value);
    switch (value) {
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
    case PYRAMID_ERROR_NOT_FOUND:
        return "not_found";
    case PYRAMID_ERROR_CANCELLED:
        return "cancelled";
    }
    return "unknown";
}

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

namespace pyramid::capi {

pyramid_status failWith(pyramid_status status, const std::string& message) {
    lastError = message;
    return status;
}

} // namespace pyramid::capi
