/* The C API's sources from C99 on the original tools' files: files and producers opened by path,
 * from memory and through counting callbacks give the same tiles, the callbacks released once, at
 * close; failing callbacks, bad descriptors and a truncated memory source are file or argument
 * errors naming the source. argv[1] is the tests/data directory. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libpyramid/capi/pyramid.h"
#include "tests/support/c_api_io.h"
#include "tests/support/c_load_file.h"
#include "tests/support/c_check.h"

/* Path, memory and callback sources give the same tiles, for files, elevation producers (two
 * tile sizes) and ortho producers (as stored and as colour residuals). */
static void test_sources(const char* dir) {
    char dem_path[4096], rgb_path[4096];
    size_t dem_size = 0, rgb_size = 0;
    unsigned char* dem;
    unsigned char* rgb;
    counting_io dem_io, rgb_io;
    pyramid_source by_path, in_memory, by_io;
    pyramid_file* reference = NULL;
    pyramid_file* other = NULL;
    pyramid_elevation* e_reference = NULL;
    pyramid_elevation* e_other = NULL;
    pyramid_ortho* o_reference = NULL;
    pyramid_ortho* o_other = NULL;
    pyramid_elevation_options eo;
    pyramid_ortho_options oo;
    int colour;
    path_of(dem_path, sizeof dem_path, dir, "proland/DEM.dat");
    path_of(rgb_path, sizeof rgb_path, dir, "proland/RGB.dat");
    dem = load_file(dem_path, &dem_size);
    rgb = load_file(rgb_path, &rgb_size);
    CHECK(dem && rgb);
    if (!dem || !rgb) {
        return;
    }

    /* Files: path, memory and callbacks give the same tiles, for both kinds. */
    by_path = path_source(dem_path);
    CHECK(pyramid_open_source(&by_path, &reference) == PYRAMID_OK);
    in_memory = memory_source(dem, dem_size);
    CHECK(pyramid_open_source(&in_memory, &other) == PYRAMID_OK);
    if (reference && other) {
        check_same_tiles(reference, other);
    }
    pyramid_close(other);
    counting_init(&dem_io, dem, dem_size);
    by_io = io_source(&dem_io, "dem callbacks");
    CHECK(pyramid_open_source(&by_io, &other) == PYRAMID_OK);
    if (reference && other) {
        check_same_tiles(reference, other);
    }
    CHECK(dem_io.reads > 0 && dem_io.released == 0);
    pyramid_close(other);
    CHECK(dem_io.released == 1); /* once, at close */
    pyramid_close(reference);

    by_path = path_source(rgb_path);
    CHECK(pyramid_open_source(&by_path, &reference) == PYRAMID_OK);
    in_memory = memory_source(rgb, rgb_size);
    CHECK(pyramid_open_source(&in_memory, &other) == PYRAMID_OK);
    if (reference && other) {
        check_same_tiles(reference, other);
    }
    pyramid_close(other);
    counting_init(&rgb_io, rgb, rgb_size);
    by_io = io_source(&rgb_io, "rgb callbacks");
    CHECK(pyramid_open_source(&by_io, &other) == PYRAMID_OK);
    if (reference && other) {
        check_same_tiles(reference, other);
    }
    pyramid_close(other);
    pyramid_close(reference);
    CHECK(rgb_io.released == 1);

    /* Elevation producers, for two tile sizes. */
    memset(&eo, 0, sizeof eo);
    eo.struct_size = sizeof eo;
    eo.cache_tiles = 8;
    for (eo.tile_size = 24; eo.tile_size <= 192; eo.tile_size *= 8) {
        CHECK(pyramid_elevation_open(dem_path, eo.tile_size, 0, 8, &e_reference) == PYRAMID_OK);
        in_memory = memory_source(dem, dem_size);
        CHECK(pyramid_elevation_open_sources(&in_memory, NULL, 0, &eo, &e_other) == PYRAMID_OK);
        if (e_reference && e_other) {
            check_same_elevations(e_reference, e_other);
        }
        pyramid_elevation_close(e_other);
        counting_init(&dem_io, dem, dem_size);
        by_io = io_source(&dem_io, "dem callbacks");
        CHECK(pyramid_elevation_open_sources(&by_io, NULL, 0, &eo, &e_other) == PYRAMID_OK);
        if (e_reference && e_other) {
            check_same_elevations(e_reference, e_other);
        }
        pyramid_elevation_close(e_other);
        CHECK(dem_io.released == 1);
        pyramid_elevation_close(e_reference);
    }

    /* Ortho producers: the file's tiles, and the same file read as colour residuals. */
    memset(&oo, 0, sizeof oo);
    oo.struct_size = sizeof oo;
    oo.cache_tiles = 4;
    for (colour = 0; colour <= 1; ++colour) {
        oo.colour_residuals = colour;
        CHECK(pyramid_ortho_open(rgb_path, colour, 4, &o_reference) == PYRAMID_OK);
        in_memory = memory_source(rgb, rgb_size);
        CHECK(pyramid_ortho_open_sources(&in_memory, NULL, 0, &oo, &o_other) == PYRAMID_OK);
        if (o_reference && o_other) {
            check_same_ortho(o_reference, o_other);
        }
        pyramid_ortho_close(o_other);
        counting_init(&rgb_io, rgb, rgb_size);
        by_io = io_source(&rgb_io, "rgb callbacks");
        CHECK(pyramid_ortho_open_sources(&by_io, NULL, 0, &oo, &o_other) == PYRAMID_OK);
        if (o_reference && o_other) {
            check_same_ortho(o_reference, o_other);
        }
        pyramid_ortho_close(o_other);
        CHECK(rgb_io.released == 1);
        pyramid_ortho_close(o_reference);
    }
    free(dem);
    free(rgb);
}

/* A failing read callback is a file error naming the source, at open or at a later read; the
 * callbacks of a failed open are not released. */
static void test_failing_io(const char* dir) {
    char path[4096];
    size_t size = 0;
    unsigned char* dem;
    unsigned char buffer[64];
    counting_io io;
    pyramid_source source;
    pyramid_file* file = NULL;
    pyramid_elevation* producer = NULL;
    float* zf;
    path_of(path, sizeof path, dir, "proland/DEM.dat");
    dem = load_file(path, &size);
    if (!dem) {
        CHECK(dem != NULL);
        return;
    }
    counting_init(&io, dem, size);
    io.fail_at = 1;
    source = io_source(&io, "pak:terrain/DEM.dat");
    CHECK(pyramid_open_source(&source, &file) == PYRAMID_ERROR_FILE);
    CHECK(file == NULL);
    CHECK(strstr(pyramid_last_error(), "pak:terrain/DEM.dat") != NULL);
    CHECK(strstr(pyramid_last_error(), "-5") != NULL);
    CHECK(io.released == 0);

    counting_init(&io, dem, size);
    io.fail_at = 2;
    io.fail_short = 1;
    CHECK(pyramid_open_source(&source, &file) == PYRAMID_ERROR_FILE);
    CHECK(strstr(pyramid_last_error(), "pak:terrain/DEM.dat") != NULL);
    CHECK(strstr(pyramid_last_error(), "returned") != NULL);
    CHECK(io.released == 0);

    /* A failure after the open: the read of a tile. */
    counting_init(&io, dem, size);
    CHECK(pyramid_open_source(&source, &file) == PYRAMID_OK);
    io.fail_at = io.reads + 1;
    CHECK(pyramid_read_tile_bytes(file, 5, 3, 3, buffer, sizeof buffer, NULL) == PYRAMID_ERROR_ARGUMENT);
    CHECK(pyramid_read_tile(file, 5, 3, 3, NULL, 0, NULL) == PYRAMID_OK);
    zf = (float*)malloc(197 * 197 * 2);
    CHECK(pyramid_read_tile(file, 5, 3, 3, zf, 197 * 197 * 2, NULL) == PYRAMID_ERROR_FILE);
    CHECK(strstr(pyramid_last_error(), "pak:terrain/DEM.dat") != NULL);
    pyramid_close(file);
    CHECK(io.released == 1);

    /* The elevation producer: a failure while producing a tile. */
    counting_init(&io, dem, size);
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, NULL, &producer) == PYRAMID_OK);
    io.fail_at = io.reads + 1;
    CHECK(pyramid_elevation_tile(producer, 0, 0, 0, zf, NULL, NULL, 0) == PYRAMID_ERROR_ARGUMENT);
    free(zf);
    zf = (float*)malloc(sizeof(float) * 197 * 197);
    CHECK(pyramid_elevation_tile(producer, 0, 0, 0, zf, NULL, NULL, 197 * 197) == PYRAMID_ERROR_FILE);
    CHECK(strstr(pyramid_last_error(), "pak:terrain/DEM.dat") != NULL);
    pyramid_elevation_close(producer);
    CHECK(io.released == 1);

    /* Bad descriptors. */
    source.io.read = NULL;
    CHECK(pyramid_open_source(&source, &file) == PYRAMID_ERROR_ARGUMENT);
    source.kind = (pyramid_source_kind)42;
    CHECK(pyramid_open_source(&source, &file) == PYRAMID_ERROR_ARGUMENT);
    CHECK(pyramid_open_source(NULL, &file) == PYRAMID_ERROR_ARGUMENT);
    /* A memory source holding half the file. */
    source = memory_source(dem, size / 2);
    CHECK(pyramid_open_source(&source, &file) == PYRAMID_ERROR_FILE);
    CHECK(file == NULL && strstr(pyramid_last_error(), "DEM in memory") != NULL);
    free(zf);
    free(dem);
}

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: c_api_io_test DATA_DIR\n");
        return 2;
    }
    test_sources(argv[1]);
    test_failing_io(argv[1]);
    return check_summary();
}
