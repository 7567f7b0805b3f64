/* The C API from C99, through the public header only, on the original tools' files.
 * argv[1] is the tests/data directory. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libpyramid/capi/pyramid.h"

static int checks = 0;
static int failures = 0;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        ++checks;                                                                    \
        if (!(cond)) {                                                               \
            fprintf(stderr, "%s:%d: CHECK failed: %s (%s)\n", __FILE__, __LINE__, #cond, \
                    pyramid_last_error());                                           \
            ++failures;                                                              \
        }                                                                            \
    } while (0)

static void path_of(char* out, size_t size, const char* dir, const char* name) {
    snprintf(out, size, "%s/%s", dir, name);
}

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
}

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: c_api_test DATA_DIR\n");
        return 2;
    }
    test_residual_file(argv[1]);
    test_elevation(argv[1]);
    test_ortho(argv[1]);
    test_errors(argv[1]);
    printf("%d passed, %d failed\n", checks - failures, failures);
    return failures ? 1 : 0;
}
