/* The C API's structs from C99 on the original tools' files: tile stats from the offset table
 * alone (tiles stored as empty ranges included), the status names, and size-prefixed structs and
 * options from older (smaller) and newer (larger) callers. argv[1] is the tests/data directory. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libpyramid/capi/pyramid.h"
#include "tests/support/c_api_io.h"
#include "tests/support/c_load_file.h"
#include "tests/support/c_check.h"

/* Sizes and existence come from the offset table: no tile byte is read. */
static void test_stat(const char* dir) {
    char path[4096];
    size_t size = 0, written = 0, stored = 0;
    unsigned char* dem;
    unsigned char* copy;
    counting_io io;
    pyramid_source source;
    pyramid_file* file = NULL;
    pyramid_tile_info t;
    short small[4];
    long reads;
    int level;
    pyramid_file_info fi;
    pyramid_elevation* left_out = NULL;
    pyramid_elevation* reference = NULL;
    pyramid_ortho* ortho = NULL;
    pyramid_ortho_options oo;
    float* zf;
    float* zr;
    double height = 0.0;
    unsigned char* pixels;
    path_of(path, sizeof path, dir, "proland/DEM.dat");
    dem = load_file(path, &size);
    CHECK(dem != NULL);
    if (!dem) {
        return;
    }
    counting_init(&io, dem, size);
    source = io_source(&io, "DEM.dat by callbacks");
    CHECK(pyramid_open_source(&source, &file) == PYRAMID_OK);
    if (!file) {
        free(dem);
        return;
    }
    /* The open reads the header and the offset table, nothing else. */
    CHECK(io.bytes <= 2 * 28 + 24 * 8 + 28);
    reads = io.reads;
    memset(&t, 0, sizeof t);
    t.struct_size = sizeof t;
    for (level = 0; level <= 5; ++level) {
        CHECK(pyramid_tile_stat(file, level, 0, 0, &t) == PYRAMID_OK);
        CHECK(t.exists == 1 && t.channels == 1 && t.stored_bytes > 0);
        CHECK(t.side == (level < 3 ? (192 >> (3 - level)) + 5 : 197));
        CHECK(t.decoded_bytes == (size_t)t.side * (size_t)t.side * 2);
        CHECK(t.offset >= 28 + 24 * 8 && t.offset + t.stored_bytes <= size);
        CHECK(pyramid_read_tile(file, level, 0, 0, NULL, 0, &written) == PYRAMID_OK);
        CHECK(written == t.decoded_bytes);
        CHECK(pyramid_read_tile(file, level, 0, 0, small, sizeof small, &written) == PYRAMID_ERROR_ARGUMENT);
        CHECK(written == t.decoded_bytes);
        CHECK(pyramid_read_tile_bytes(file, level, 0, 0, NULL, 0, &stored) == PYRAMID_OK);
        CHECK(stored == t.stored_bytes);
        CHECK(pyramid_read_tile_bytes(file, level, 0, 0, small, sizeof small, &stored) == PYRAMID_ERROR_ARGUMENT);
    }
    CHECK(io.reads == reads); /* none of the above read anything */
    /* The stored bytes are where the stat says. */
    CHECK(pyramid_tile_stat(file, 4, 1, 1, &t) == PYRAMID_OK);
    copy = (unsigned char*)malloc(t.stored_bytes);
    CHECK(pyramid_read_tile_bytes(file, 4, 1, 1, copy, t.stored_bytes, &stored) == PYRAMID_OK);
    CHECK(stored == t.stored_bytes && memcmp(copy, dem + t.offset, stored) == 0);
    CHECK(io.reads == reads + 1 && io.bytes > 0);
    free(copy);
    /* Outside the pyramid: not found, the info zeroed. */
    t.exists = 7;
    CHECK(pyramid_tile_stat(file, 6, 0, 0, &t) == PYRAMID_ERROR_NOT_FOUND);
    CHECK(t.exists == 0 && t.stored_bytes == 0 && t.struct_size == sizeof t);
    CHECK(pyramid_tile_stat(file, 4, 2, 0, &t) == PYRAMID_ERROR_NOT_FOUND);
    CHECK(pyramid_tile_stat(file, 0, 0, 0, NULL) == PYRAMID_ERROR_ARGUMENT);
    pyramid_close(file);

    /* A tile stored as an empty range (its end moved onto its begin): it exists in the quadtree
     * but not in the file. */
    copy = (unsigned char*)malloc(size);
    memcpy(copy, dem, size);
    memcpy(copy + 28 + 8 * 5 + 4, copy + 28 + 8 * 5, 4); /* tile 5 = (4, 1, 0) */
    source = memory_source(copy, size);
    CHECK(pyramid_open_source(&source, &file) == PYRAMID_OK);
    if (file) {
        CHECK(pyramid_tile_stat(file, 4, 1, 0, &t) == PYRAMID_OK);
        CHECK(t.exists == 0 && t.stored_bytes == 0 && t.decoded_bytes == 197 * 197 * 2);
        CHECK(pyramid_read_tile(file, 4, 1, 0, NULL, 0, &written) == PYRAMID_ERROR_NOT_FOUND);
        CHECK(written == 0);
        CHECK(pyramid_read_tile_bytes(file, 4, 1, 0, NULL, 0, &written) == PYRAMID_ERROR_NOT_FOUND);
        CHECK(pyramid_tile_stat(file, 4, 0, 0, &t) == PYRAMID_OK && t.exists == 1);
        /* Every tile of the original has bytes of its own: 23 left, 23 distinct ranges. */
        memset(&fi, 0, sizeof fi);
        fi.struct_size = sizeof fi;
        CHECK(pyramid_get_file_info(file, &fi) == PYRAMID_OK);
        CHECK(fi.stored_tiles == 23 && fi.distinct_tiles == 23);
        pyramid_close(file);
    }
    /* The elevation producer continues smoothly there (zero residuals), at the tile and below:
     * file tile (4, 1, 0) is producer tile (1, 1, 0) for elevation tiles of 192 (delta 3). */
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, NULL, &left_out) == PYRAMID_OK);
    CHECK(pyramid_elevation_open(path, 0, 0, 8, &reference) == PYRAMID_OK);
    if (left_out && reference) {
        zf = (float*)malloc(197 * 197 * sizeof(float));
        zr = (float*)malloc(197 * 197 * sizeof(float));
        CHECK(pyramid_elevation_tile(left_out, 1, 1, 0, zf, NULL, NULL, 197 * 197) == PYRAMID_OK);
        CHECK(pyramid_elevation_tile(reference, 1, 1, 0, zr, NULL, NULL, 197 * 197) == PYRAMID_OK);
        CHECK(isfinite(zf[98 + 98 * 197]) && memcmp(zf, zr, 197 * 197 * sizeof(float)) != 0);
        CHECK(pyramid_elevation_tile(left_out, 2, 2, 1, zf, NULL, NULL, 197 * 197) == PYRAMID_OK);
        CHECK(isfinite(zf[98 + 98 * 197]));
        CHECK(pyramid_elevation_height(left_out, -1, 0.7, 0.2, &height) == PYRAMID_OK && isfinite(height));
        /* Elsewhere the same tiles as the original's. */
        CHECK(pyramid_elevation_tile(left_out, 2, 0, 0, zf, NULL, NULL, 197 * 197) == PYRAMID_OK);
        CHECK(pyramid_elevation_tile(reference, 2, 0, 0, zr, NULL, NULL, 197 * 197) == PYRAMID_OK);
        CHECK(memcmp(zf, zr, 197 * 197 * sizeof(float)) == 0);
        free(zf);
        free(zr);
    }
    pyramid_elevation_close(left_out);
    pyramid_elevation_close(reference);
    free(copy);
    free(dem);

    /* An ortho tile stored as an empty range: no tile as it is, no residual for the colour
     * residual producer (the prediction alone), at the tile and below. */
    path_of(path, sizeof path, dir, "proland/RGB.dat");
    dem = load_file(path, &size);
    CHECK(dem != NULL);
    if (!dem) {
        return;
    }
    memcpy(dem + 28 + 16 * 1 + 8, dem + 28 + 16 * 1, 8); /* tile 1 = (1, 0, 0) */
    source = memory_source(dem, size);
    pixels = (unsigned char*)malloc(196 * 196 * 4);
    CHECK(pyramid_ortho_open_sources(&source, NULL, 0, NULL, &ortho) == PYRAMID_OK);
    if (ortho) {
        CHECK(pyramid_ortho_tile(ortho, 1, 0, 0, pixels, 196 * 196 * 4) == PYRAMID_ERROR_NOT_FOUND);
        CHECK(pyramid_ortho_tile(ortho, 1, 1, 0, pixels, 196 * 196 * 4) == PYRAMID_OK);
        pyramid_ortho_close(ortho);
    }
    memset(&oo, 0, sizeof oo);
    oo.struct_size = sizeof oo;
    oo.colour_residuals = 1;
    CHECK(pyramid_ortho_open_sources(&source, NULL, 0, &oo, &ortho) == PYRAMID_OK);
    if (ortho) {
        CHECK(pyramid_ortho_tile(ortho, 1, 0, 0, pixels, 196 * 196 * 4) == PYRAMID_OK);
        CHECK(pyramid_ortho_tile(ortho, 2, 1, 1, pixels, 196 * 196 * 4) == PYRAMID_OK);
        CHECK(pyramid_ortho_tile(ortho, 2, 2, 0, pixels, 196 * 196 * 4) == PYRAMID_OK);
        pyramid_ortho_close(ortho);
    }
    free(pixels);
    free(dem);
}

static void test_status_names(void) {
    CHECK(strcmp(pyramid_status_name(PYRAMID_ERROR_NOT_FOUND), "not_found") == 0);
    CHECK(strcmp(pyramid_status_name(PYRAMID_ERROR_ARGUMENT), "argument") == 0);
    CHECK(strcmp(pyramid_status_name(PYRAMID_ERROR_CANCELLED), "cancelled") == 0);
    CHECK(PYRAMID_ERROR_NOT_FOUND != PYRAMID_ERROR_ARGUMENT);
}

/* Size-prefixed structs: an older caller's smaller struct is filled no further than its size;
 * a newer caller's larger one has the members the library does not know zeroed. */
static void test_sized_structs(const char* dir) {
    char path[4096];
    pyramid_file* file = NULL;
    pyramid_info info;
    pyramid_file_info full;
    union {
        pyramid_file_info info;
        unsigned char bytes[sizeof(pyramid_file_info) + 64];
    } large;
    unsigned char old[sizeof(pyramid_file_info)];
    pyramid_file_info* older = (pyramid_file_info*)(void*)old;
    size_t k, cut = offsetof(pyramid_file_info, source_size);
    int intact = 1, zeroed = 1;
    path_of(path, sizeof path, dir, "proland/DEM.dat");
    CHECK(pyramid_open(path, &file) == PYRAMID_OK);
    if (!file) {
        return;
    }
    CHECK(pyramid_get_info(file, &info) == PYRAMID_OK);
    memset(&full, 0, sizeof full);
    full.struct_size = sizeof full;
    CHECK(pyramid_get_file_info(file, &full) == PYRAMID_OK);
    CHECK(full.struct_size == sizeof full);
    CHECK(full.kind == info.kind && full.min_level == info.min_level && full.max_level == info.max_level);
    CHECK(full.tile_size == info.tile_size && full.scale == info.scale && full.tile_count == info.tile_count);
    CHECK(full.channels == 1 && full.border == 2 && full.dxt == 0);
    CHECK(full.data_offset == 28 + 24 * 8);
    CHECK(full.source_size == 599422);
    CHECK(full.stored_tiles == 24);
    CHECK(full.distinct_tiles >= 1 && full.distinct_tiles <= 24);

    /* Older: the struct ends before source_size; the bytes after it are not touched. */
    memset(old, 0xAB, sizeof old);
    older->struct_size = cut;
    CHECK(pyramid_get_file_info(file, older) == PYRAMID_OK);
    CHECK(older->struct_size == cut && older->tile_count == 24 && older->min_level == 3 && older->scale == 0.1f);
    for (k = cut; k < sizeof old; ++k) {
        intact &= old[k] == 0xAB;
    }
    CHECK(intact);

    /* Newer: 64 bytes more than this header knows; they come back zero. */
    memset(large.bytes, 0xAB, sizeof large.bytes);
    large.info.struct_size = sizeof large.bytes;
    CHECK(pyramid_get_file_info(file, &large.info) == PYRAMID_OK);
    CHECK(large.info.struct_size == sizeof large.bytes);
    CHECK(large.info.stored_tiles == 24 && large.info.data_offset == full.data_offset);
    for (k = sizeof(pyramid_file_info); k < sizeof large.bytes; ++k) {
        zeroed &= large.bytes[k] == 0;
    }
    CHECK(zeroed);

    /* Too small to hold even struct_size. */
    full.struct_size = 0;
    CHECK(pyramid_get_file_info(file, &full) == PYRAMID_ERROR_ARGUMENT);
    pyramid_close(file);
}

/* Options: an older caller's struct (without scale) takes the default scale; a newer caller's
 * members are refused unless zero. */
static void test_sized_options(const char* dir) {
    char path[4096];
    pyramid_source source;
    pyramid_elevation* reference = NULL;
    pyramid_elevation* producer = NULL;
    pyramid_file* file = NULL;
    union {
        pyramid_elevation_options options;
        unsigned char bytes[sizeof(pyramid_elevation_options) + 16];
    } large;
    pyramid_elevation_options o;
    path_of(path, sizeof path, dir, "proland/DEM.dat");
    source = path_source(path);
    CHECK(pyramid_elevation_open(path, 24, 0, 4, &reference) == PYRAMID_OK);

    memset(&o, 0, sizeof o);
    o.struct_size = offsetof(pyramid_elevation_options, scale);
    o.tile_size = 24;
    o.cache_tiles = 4;
    o.scale = 1000.0f; /* past struct_size: not read */
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &o, &producer) == PYRAMID_OK);
    if (reference && producer) {
        check_same_elevations(reference, producer);
    }
    pyramid_elevation_close(producer);

    memset(large.bytes, 0, sizeof large.bytes);
    large.options.struct_size = sizeof large.bytes;
    large.options.tile_size = 24;
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &large.options, &producer) == PYRAMID_OK);
    if (reference && producer) {
        check_same_elevations(reference, producer);
    }
    pyramid_elevation_close(producer);
    large.bytes[sizeof(pyramid_elevation_options) + 3] = 1;
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &large.options, &producer) == PYRAMID_ERROR_ARGUMENT);
    CHECK(producer == NULL);
    o.struct_size = 2;
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &o, &producer) == PYRAMID_ERROR_ARGUMENT);
    /* A source too small for its own kind member. */
    source.struct_size = sizeof(size_t);
    CHECK(pyramid_open_source(&source, &file) == PYRAMID_ERROR_ARGUMENT);
    CHECK(file == NULL);
    pyramid_elevation_close(reference);
}

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: c_api_structs_test DATA_DIR\n");
        return 2;
    }
    test_stat(argv[1]);
    test_status_names();
    test_sized_structs(argv[1]);
    test_sized_options(argv[1]);
    return check_summary();
}
