/* The C API tests' sources and comparisons (strict C99, header-only): I/O callbacks over memory
 * that count their reads, bytes and releases and fail on request; path, memory and callback
 * source descriptors (a file read into memory: c_load_file.h); and checks that two files or two
 * producers give the same tiles. Used by c_api_test.c, c_api_io_test.c and c_api_structs_test.c. */
#ifndef PYRAMID_TESTS_SUPPORT_C_API_IO_H
#define PYRAMID_TESTS_SUPPORT_C_API_IO_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libpyramid/capi/pyramid.h"
#include "tests/support/c_check.h"
#include "tests/support/c_load_file.h"

/* Callbacks over a block of memory that count what they are asked, and fail on request. */
typedef struct counting_io {
    const unsigned char* data;
    size_t size;
    long reads;
    unsigned long long bytes;
    long fail_at;  /* the read (counted from 1) that fails; 0: none */
    int fail_short; /* the failing read returns fewer bytes instead of an error */
    long released;
} counting_io;

static inline int counting_read(void* user, uint64_t offset, void* buffer, size_t size, size_t* bytes_read) {
    counting_io* io = (counting_io*)user;
    ++io->reads;
    io->bytes += size;
    if (io->fail_at != 0 && io->reads >= io->fail_at) {
        if (!io->fail_short) {
            return -5;
        }
        size = size / 2;
    }
    if (offset > io->size || size > io->size - offset) {
        return -1;
    }
    memcpy(buffer, io->data + offset, size);
    *bytes_read = size;
    return 0;
}

static inline void counting_release(void* user) { ++((counting_io*)user)->released; }

static inline void counting_init(counting_io* io, const unsigned char* data, size_t size) {
    memset(io, 0, sizeof *io);
    io->data = data;
    io->size = size;
}

static inline pyramid_source path_source(const char* path) {
    pyramid_source s;
    memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_PATH;
    s.path = path;
    return s;
}

static inline pyramid_source memory_source(const void* data, size_t size) {
    pyramid_source s;
    memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_MEMORY;
    s.name = "DEM in memory";
    s.data = data;
    s.size = size;
    return s;
}

static inline pyramid_source io_source(counting_io* io, const char* name) {
    pyramid_source s;
    memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_IO;
    s.name = name;
    s.io.read = counting_read;
    s.io.release = counting_release;
    s.io.user = io;
    s.io.size = io->size;
    return s;
}

/* Every tile of `reference` (decoded and as stored) equals the same tile of `other`. */
static inline void check_same_tiles(pyramid_file* reference, pyramid_file* other) {
    pyramid_info info;
    int level, tx, ty;
    size_t a_size = 0, b_size = 0;
    unsigned char* a;
    unsigned char* b;
    long compared = 0, differ = 0;
    CHECK(pyramid_get_info(reference, &info) == PYRAMID_OK);
    a = (unsigned char*)malloc(1 << 20);
    b = (unsigned char*)malloc(1 << 20);
    for (level = 0; level <= info.max_level; ++level) {
        const int side = info.kind == PYRAMID_KIND_RESIDUAL && level < info.min_level
                             ? 1
                             : 1 << (info.kind == PYRAMID_KIND_RESIDUAL ? level - info.min_level : level);
        for (ty = 0; ty < side; ++ty) {
            for (tx = 0; tx < side; ++tx) {
                CHECK(pyramid_read_tile(reference, level, tx, ty, a, 1 << 20, &a_size) == PYRAMID_OK);
                CHECK(pyramid_read_tile(other, level, tx, ty, b, 1 << 20, &b_size) == PYRAMID_OK);
                differ += a_size != b_size || memcmp(a, b, a_size) != 0;
                CHECK(pyramid_read_tile_bytes(reference, level, tx, ty, a, 1 << 20, &a_size) == PYRAMID_OK);
                CHECK(pyramid_read_tile_bytes(other, level, tx, ty, b, 1 << 20, &b_size) == PYRAMID_OK);
                differ += a_size != b_size || memcmp(a, b, a_size) != 0;
                compared += 2;
            }
        }
    }
    CHECK(compared == 2 * info.tile_count);
    CHECK(differ == 0);
    free(a);
    free(b);
}

/* The elevation tiles of levels 0..3 of two producers are identical (zf, zc and zm). */
static inline void check_same_elevations(pyramid_elevation* reference, pyramid_elevation* other) {
    const int side = pyramid_elevation_side(reference);
    const size_t n = (size_t)side * (size_t)side;
    float* a = (float*)malloc(3 * n * sizeof(float));
    float* b = (float*)malloc(3 * n * sizeof(float));
    int level, tx, ty;
    long differ = 0;
    CHECK(pyramid_elevation_side(other) == side);
    for (level = 0; level <= 3; ++level) {
        for (ty = 0; ty < 1 << level; ++ty) {
            for (tx = 0; tx < 1 << level; ++tx) {
                CHECK(pyramid_elevation_tile(reference, level, tx, ty, a, a + n, a + 2 * n, n) == PYRAMID_OK);
                CHECK(pyramid_elevation_tile(other, level, tx, ty, b, b + n, b + 2 * n, n) == PYRAMID_OK);
                differ += memcmp(a, b, 3 * n * sizeof(float)) != 0;
            }
        }
    }
    CHECK(differ == 0);
    free(a);
    free(b);
}

/* The tiles of levels 0..2 of two ortho producers are identical, and so are their NOT_FOUNDs. */
static inline void check_same_ortho(pyramid_ortho* reference, pyramid_ortho* other) {
    int side = 0, channels = 0, level, tx, ty;
    size_t bytes;
    unsigned char* a;
    unsigned char* b;
    long differ = 0, found = 0;
    CHECK(pyramid_ortho_layout(reference, &side, &channels) == PYRAMID_OK);
    bytes = (size_t)side * (size_t)side * (size_t)channels;
    a = (unsigned char*)malloc(bytes);
    b = (unsigned char*)malloc(bytes);
    for (level = 0; level <= 2; ++level) {
        for (ty = 0; ty < 1 << level; ++ty) {
            for (tx = 0; tx < 1 << level; ++tx) {
                const pyramid_status sa = pyramid_ortho_tile(reference, level, tx, ty, a, bytes);
                const pyramid_status sb = pyramid_ortho_tile(other, level, tx, ty, b, bytes);
                CHECK(sa == sb);
                CHECK(sa == PYRAMID_OK || sa == PYRAMID_ERROR_NOT_FOUND);
                found += sa == PYRAMID_OK;
                differ += sa == PYRAMID_OK && memcmp(a, b, bytes) != 0;
            }
        }
    }
    CHECK(found >= 5);
    CHECK(differ == 0);
    free(a);
    free(b);
}

#endif
