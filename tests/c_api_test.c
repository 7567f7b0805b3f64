/* The C API from C99, through the public header only, on the original tools' files: a residual
 * file's tiles, the elevation, normal and ortho producers, the errors and their messages, the
 * residual producer's scale and the colour_residuals option. Opens by memory and callbacks are
 * in c_api_io_test.c, the size-prefixed structs and tile stats in c_api_structs_test.c.
 * argv[1] is the tests/data directory. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libpyramid/capi/pyramid.h"
#include "tests/support/c_api_io.h"
#include "tests/support/c_check.h"

static void test_residual_file(const char* dir) {
    char path[4096];
    pyramid_file* file = NULL;
    pyramid_info info;
    int side = 0;
    size_t needed = 0;
    short* tile;
    path_of(path, sizeof path, dir, "proland/DEM.dat");
    CHECK(pyramid_open(path, &file) == PYRAMID_OK);
    if (!file) {
        return;
    }
    CHECK(pyramid_get_info(file, &info) == PYRAMID_OK);
    CHECK(info.kind == PYRAMID_KIND_RESIDUAL);
    CHECK(info.min_level == 3 && info.max_level == 5 && info.tile_size == 192);
    CHECK(info.scale == 0.1f);
    CHECK(info.tile_count == 24);
    CHECK(pyramid_tile_side(file, 0, &side) == PYRAMID_OK && side == 29);
    CHECK(pyramid_read_tile(file, 0, 0, 0, NULL, 0, &needed) == PYRAMID_OK);
    CHECK(needed == 29 * 29 * 2);
    tile = (short*)malloc(needed);
    CHECK(pyramid_read_tile(file, 0, 0, 0, tile, needed, NULL) == PYRAMID_OK);
    CHECK(tile[0] == 1400 && tile[14 + 14 * 29] == 1470);
    /* A buffer too small is an argument error; a tile outside the pyramid is not found. */
    CHECK(pyramid_read_tile(file, 0, 0, 0, tile, 10, NULL) == PYRAMID_ERROR_ARGUMENT);
    CHECK(strstr(pyramid_last_error(), "needed") != NULL);
    CHECK(pyramid_read_tile(file, 2, 1, 0, tile, needed, NULL) == PYRAMID_ERROR_NOT_FOUND);
    free(tile);
    pyramid_close(file);
}

static void test_elevation(const char* dir) {
    char path[4096];
    pyramid_elevation* producer = NULL;
    float* zf;
    float* zc;
    int side;
    double height = 0.0;
    path_of(path, sizeof path, dir, "proland/DEM.dat");
    CHECK(pyramid_elevation_open(path, 24, 0, 16, &producer) == PYRAMID_OK);
    if (!producer) {
        return;
    }
    side = pyramid_elevation_side(producer);
    CHECK(side == 29);
    zf = (float*)malloc(sizeof(float) * 29 * 29);
    zc = (float*)malloc(sizeof(float) * 29 * 29);
    CHECK(pyramid_elevation_tile(producer, 0, 0, 0, zf, zc, NULL, 29 * 29) == PYRAMID_OK);
    CHECK(zf[0] == 1400.0f * 0.1f);
    CHECK(zf[14 + 14 * 29] == 1470.0f * 0.1f);
    /* The root tile's samples, at its corner and its centre; half-way between two samples. */
    CHECK(pyramid_elevation_height(producer, 0, 0.0, 0.0, &height) == PYRAMID_OK);
    CHECK(height == (double)zf[2 + 2 * 29]);
    CHECK(pyramid_elevation_height(producer, 0, 0.5, 0.5, &height) == PYRAMID_OK);
    CHECK(height == (double)zf[14 + 14 * 29]);
    CHECK(pyramid_elevation_height(producer, 0, 0.5 + 0.5 / 24.0, 0.5, &height) == PYRAMID_OK);
    CHECK(fabs(height - ((double)zf[14 + 14 * 29] + (double)zf[15 + 14 * 29]) / 2.0) < 1e-9);
    CHECK(pyramid_elevation_height(producer, -1, 0.3, 0.7, &height) == PYRAMID_OK);
    CHECK(isfinite(height) && height > 0.0);
    CHECK(pyramid_elevation_height(producer, 0, 1.5, 0.5, &height) == PYRAMID_ERROR_ARGUMENT);
    CHECK(pyramid_elevation_tile(producer, 3, 5, 2, zf, zc, NULL, 29 * 29) == PYRAMID_OK);
    CHECK(isfinite(zf[100]) && zf[100] > 0.0f);
    CHECK(pyramid_elevation_tile(producer, 1, 2, 0, zf, NULL, NULL, 29 * 29) == PYRAMID_ERROR_NOT_FOUND);
    CHECK(pyramid_elevation_tile(producer, 0, 0, 0, zf, NULL, NULL, 10) == PYRAMID_ERROR_ARGUMENT);
    free(zf);
    free(zc);
    pyramid_elevation_close(producer);
    /* 100 is not 192 / 2^k. */
    CHECK(pyramid_elevation_open(path, 100, 0, 16, &producer) == PYRAMID_ERROR_ARGUMENT);
    CHECK(producer == NULL);
}

/* The normal producer over an elevation producer: a root tile's normal by the documented
 * float32 order from its own heights (doc/shading.md), coarse = fine at level 0, the elevation
 * handle closed first, and the argument errors. */
static void test_normals(const char* dir) {
    char path[4096];
    pyramid_elevation* elevations = NULL;
    pyramid_normal* normals = NULL;
    pyramid_normal_options o;
    float zf[29 * 29];
    float* n;
    float two, gx, gy, l;
    int side;
    path_of(path, sizeof path, dir, "proland/DEM.dat");
    CHECK(pyramid_elevation_open(path, 24, 0, 16, &elevations) == PYRAMID_OK);
    if (!elevations) {
        return;
    }
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    CHECK(pyramid_normal_open(elevations, &o, &normals) == PYRAMID_ERROR_ARGUMENT); /* no size */
    CHECK(strstr(pyramid_last_error(), "root quad's size") != NULL);
    o.deformation = 7;
    o.size = 24000.0;
    CHECK(pyramid_normal_open(elevations, &o, &normals) == PYRAMID_ERROR_ARGUMENT);
    o.deformation = PYRAMID_DEFORM_PLANE;
    CHECK(pyramid_normal_open(elevations, &o, &normals) == PYRAMID_OK);
    CHECK(pyramid_elevation_tile(elevations, 0, 0, 0, zf, NULL, NULL, 29 * 29) == PYRAMID_OK);
    pyramid_elevation_close(elevations); /* the normal producer keeps what it needs */
    if (!normals) {
        return;
    }
    side = pyramid_normal_side(normals);
    CHECK(side == 25);
    n = (float*)malloc(sizeof(float) * 4 * 25 * 25);
    CHECK(pyramid_normal_tile(normals, 0, 0, 0, n, 4 * 25 * 25) == PYRAMID_OK);
    /* Vertex (12, 7) is tile sample (14, 9); the root's 24 intervals span 24000: 1000 apart. */
    two = 2000.0f;
    gx = (zf[15 + 9 * 29] - zf[13 + 9 * 29]) / two;
    gy = (zf[14 + 10 * 29] - zf[14 + 8 * 29]) / two;
    l = sqrtf((gx * gx + gy * gy) + 1.0f);
    CHECK(n[4 * (12 + 7 * 25)] == -gx / l);
    CHECK(n[4 * (12 + 7 * 25) + 1] == -gy / l);
    CHECK(n[4 * (12 + 7 * 25) + 2] == n[4 * (12 + 7 * 25)]);
    CHECK(gx != 0.0f && gy != 0.0f);
    CHECK(pyramid_normal_tile(normals, 2, 3, 1, n, 4 * 25 * 25) == PYRAMID_OK);
    CHECK(pyramid_normal_tile(normals, 1, 2, 0, n, 4 * 25 * 25) == PYRAMID_ERROR_NOT_FOUND);
    CHECK(pyramid_normal_tile(normals, 0, 0, 0, n, 100) == PYRAMID_ERROR_ARGUMENT);
    free(n);
    pyramid_normal_close(normals);
}

static void test_ortho(const char* dir) {
    char path[4096];
    pyramid_ortho* producer = NULL;
    pyramid_file* file = NULL;
    int side = 0, channels = 0;
    unsigned char* a;
    unsigned char* b;
    size_t bytes;
    path_of(path, sizeof path, dir, "proland/RGB.dat");
    CHECK(pyramid_ortho_open(path, 0, 8, &producer) == PYRAMID_OK);
    CHECK(pyramid_open(path, &file) == PYRAMID_OK);
    if (!producer || !file) {
        return;
    }
    CHECK(pyramid_ortho_layout(producer, &side, &channels) == PYRAMID_OK);
    CHECK(side == 196 && channels == 4);
    bytes = (size_t)side * (size_t)side * (size_t)channels;
    a = (unsigned char*)malloc(bytes);
    b = (unsigned char*)malloc(bytes);
    CHECK(pyramid_ortho_tile(producer, 1, 1, 1, a, bytes) == PYRAMID_OK);
    CHECK(pyramid_read_tile(file, 1, 1, 1, b, bytes, NULL) == PYRAMID_OK);
    CHECK(memcmp(a, b, bytes) == 0);
    CHECK(pyramid_ortho_tile(producer, 2, 0, 0, a, bytes) == PYRAMID_ERROR_NOT_FOUND);
    free(a);
    free(b);
    pyramid_close(file);
    pyramid_ortho_close(producer);
}

static void test_errors(const char* dir) {
    char path[4096];
    pyramid_file* file = (pyramid_file*)1;
    pyramid_elevation* elevations = NULL;
    pyramid_normal* normals;
    pyramid_normal_options no;
    const char* message;
    path_of(path, sizeof path, dir, "no-such-file.dat");
    CHECK(pyramid_open(path, &file) == PYRAMID_ERROR_FILE);
    CHECK(file == NULL);
    CHECK(strstr(pyramid_last_error(), "no-such-file.dat") != NULL);
    CHECK(strchr(pyramid_last_error(), '\n') == NULL);
    CHECK(pyramid_open(NULL, &file) == PYRAMID_ERROR_ARGUMENT);
    CHECK(strcmp(pyramid_status_name(PYRAMID_ERROR_FILE), "file") == 0);
    CHECK(pyramid_version_number() == PYRAMID_VERSION_NUMBER);
    CHECK(strlen(pyramid_version_string()) >= 5);
    pyramid_close(NULL);

    /* A bad grid size names the file once. */
    path_of(path, sizeof path, dir, "proland/DEM.dat");
    CHECK(pyramid_elevation_open(path, 24, 7, 4, &elevations) == PYRAMID_ERROR_ARGUMENT);
    CHECK(elevations == NULL);
    message = pyramid_last_error();
    CHECK(strncmp(message, path, strlen(path)) == 0 && strstr(message, "gridSize 7") != NULL);
    CHECK(strstr(message + 1, path) == NULL);
    /* ... and so does a bad tile size. */
    CHECK(pyramid_elevation_open(path, 100, 0, 4, &elevations) == PYRAMID_ERROR_ARGUMENT);
    message = pyramid_last_error();
    CHECK(strncmp(message, path, strlen(path)) == 0 && strstr(message + 1, path) == NULL);

    /* Every open clears the handle when it fails, a null argument included. */
    memset(&no, 0, sizeof no);
    no.struct_size = sizeof no;
    no.deformation = PYRAMID_DEFORM_PLANE;
    no.size = 1.0;
    normals = (pyramid_normal*)&no;
    CHECK(pyramid_normal_open(NULL, &no, &normals) == PYRAMID_ERROR_ARGUMENT);
    CHECK(normals == NULL);
    CHECK(strstr(pyramid_last_error(), "pyramid_normal_open: null argument") != NULL);
    CHECK(pyramid_elevation_open(path, 24, 0, 4, &elevations) == PYRAMID_OK);
    normals = (pyramid_normal*)&no;
    CHECK(pyramid_normal_open(elevations, NULL, &normals) == PYRAMID_ERROR_ARGUMENT);
    CHECK(normals == NULL);
    CHECK(pyramid_normal_open(elevations, &no, NULL) == PYRAMID_ERROR_ARGUMENT);
    pyramid_elevation_close(elevations);
}

/* The residual producer's scale: every residual times (file scale x scale), in float32. */
static void test_scale(const char* dir) {
    char path[4096];
    pyramid_source source;
    pyramid_elevation_options o;
    pyramid_elevation* plain = NULL;
    pyramid_elevation* scaled = NULL;
    pyramid_file* file = NULL;
    short residuals[29 * 29];
    float zf[29 * 29], zs[29 * 29];
    const float scale = 2.5f;
    const float product = 0.1f * 2.5f;
    int k, exact = 1, close = 1, level;
    path_of(path, sizeof path, dir, "proland/DEM.dat");
    source = path_source(path);
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.tile_size = 24;
    o.cache_tiles = 8;
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &o, &plain) == PYRAMID_OK);
    o.scale = scale;
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &o, &scaled) == PYRAMID_OK);
    CHECK(pyramid_open(path, &file) == PYRAMID_OK);
    if (!plain || !scaled || !file) {
        return;
    }
    /* The root tile is the file's level 0 residuals times 0.1f * 2.5f, exactly. */
    CHECK(pyramid_read_tile(file, 0, 0, 0, residuals, sizeof residuals, NULL) == PYRAMID_OK);
    CHECK(pyramid_elevation_tile(scaled, 0, 0, 0, zs, NULL, NULL, 29 * 29) == PYRAMID_OK);
    for (k = 0; k < 29 * 29; ++k) {
        exact &= zs[k] == (float)residuals[k] * product;
    }
    CHECK(exact);
    /* Deeper tiles: the scaled heights are the plain ones times 2.5, up to float rounding. */
    for (level = 1; level <= 3; ++level) {
        CHECK(pyramid_elevation_tile(plain, level, 1, 0, zf, NULL, NULL, 29 * 29) == PYRAMID_OK);
        CHECK(pyramid_elevation_tile(scaled, level, 1, 0, zs, NULL, NULL, 29 * 29) == PYRAMID_OK);
        for (k = 0; k < 29 * 29; ++k) {
            close &= fabs((double)zs[k] - 2.5 * (double)zf[k]) <= 1e-4 * fabs(2.5 * (double)zf[k]) + 1e-3;
        }
        CHECK(zs[14 + 14 * 29] != zf[14 + 14 * 29]);
    }
    CHECK(close);
    /* Non-finite scales are refused. */
    o.scale = (float)INFINITY;
    pyramid_elevation_close(scaled);
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &o, &scaled) == PYRAMID_ERROR_ARGUMENT);
    CHECK(scaled == NULL);
    CHECK(strstr(pyramid_last_error(), "scale") != NULL);
    o.scale = (float)NAN;
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &o, &scaled) == PYRAMID_ERROR_ARGUMENT);
    /* So are finite scales whose product with the file's 0.1 puts a residual beyond float's range
     * (3e38 x 0.1 x 32768), or underflows to 0 (the smallest float times 0.1). */
    o.scale = 3e38f;
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &o, &scaled) == PYRAMID_ERROR_ARGUMENT);
    CHECK(scaled == NULL);
    CHECK(strstr(pyramid_last_error(), "beyond float's range") != NULL);
    o.scale = 1e-45f;
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &o, &scaled) == PYRAMID_ERROR_ARGUMENT);
    CHECK(strstr(pyramid_last_error(), "underflows to 0") != NULL);
    /* A large scale whose residuals stay finite is served. */
    o.scale = 1e33f;
    CHECK(pyramid_elevation_open_sources(&source, NULL, 0, &o, &scaled) == PYRAMID_OK);
    pyramid_elevation_close(scaled);
    pyramid_elevation_close(plain);
    pyramid_close(file);
}

/* colour_residuals is 0 or 1: anything else is refused, by every open. */
static void test_colour_residuals_option(const char* dir) {
    char path[4096];
    pyramid_ortho* producer;
    pyramid_source source;
    pyramid_ortho_options o;
    const int refused[] = {2, -1, 256};
    size_t k;
    path_of(path, sizeof path, dir, "proland/RGB.dat");
    source = path_source(path);
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    for (k = 0; k < sizeof refused / sizeof refused[0]; ++k) {
        producer = (pyramid_ortho*)&o; /* stale: must come back NULL */
        CHECK(pyramid_ortho_open(path, refused[k], 4, &producer) == PYRAMID_ERROR_ARGUMENT);
        CHECK(producer == NULL);
        CHECK(strstr(pyramid_last_error(), "pyramid_ortho_open: colour_residuals") != NULL);
        producer = (pyramid_ortho*)&o;
        CHECK(pyramid_ortho_open_regions(path, NULL, 0, refused[k], 4, &producer) == PYRAMID_ERROR_ARGUMENT);
        CHECK(producer == NULL);
        CHECK(strstr(pyramid_last_error(), "pyramid_ortho_open_regions: colour_residuals") != NULL);
        o.colour_residuals = refused[k];
        producer = (pyramid_ortho*)&o;
        CHECK(pyramid_ortho_open_sources(&source, NULL, 0, &o, &producer) == PYRAMID_ERROR_ARGUMENT);
        CHECK(producer == NULL);
        CHECK(strstr(pyramid_last_error(), "pyramid_ortho_open_sources: colour_residuals") != NULL);
    }
    for (k = 0; k <= 1; ++k) {
        o.colour_residuals = (int)k;
        producer = NULL;
        CHECK(pyramid_ortho_open_sources(&source, NULL, 0, &o, &producer) == PYRAMID_OK);
        pyramid_ortho_close(producer);
    }
}

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: c_api_test DATA_DIR\n");
        return 2;
    }
    test_residual_file(argv[1]);
    test_elevation(argv[1]);
    test_normals(argv[1]);
    test_ortho(argv[1]);
    test_colour_residuals_option(argv[1]);
    test_errors(argv[1]);
    test_scale(argv[1]);
    return check_summary();
}
