/* The C encoding entry points (libpyramid/capi/pyramid_encode.h): an array and a callback give
 * the same file, which reads back through the C API within scale / 2; failures and cancellation
 * return their statuses and leave no file. Strict C99. Usage: c_encode_test DATA_DIR */
#define _XOPEN_SOURCE 700 /* mkdtemp */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "libpyramid/capi/pyramid.h"
#include "libpyramid/capi/pyramid_encode.h"
#include "tests/support/c_check.h"

#define W 97
#define H 65
static float heights[W * H];

static int read_heights(void* user, int x0, int y0, int x1, int y1, float* out) {
    int x, y;
    (void)user;
    for (y = y0; y < y1; ++y) {
        for (x = x0; x < x1; ++x) {
            *out++ = heights[y * W + x];
        }
    }
    return 0;
}

static int failing_read(void* user, int x0, int y0, int x1, int y1, float* out) {
    (void)user, (void)x0, (void)y0, (void)x1, (void)y1, (void)out;
    return 7;
}

static long long tiles_seen = 0;
static void progress(void* user, long long done, long long total) {
    (void)user, (void)total;
    tiles_seen = done;
}
static int cancel_after_two(void* user) {
    (void)user;
    return tiles_seen >= 2;
}

static char* read_all(const char* path, long* size) {
    FILE* f = fopen(path, "rb");
    char* data;
    if (!f) {
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    fseek(f, 0, SEEK_SET);
    data = (char*)malloc((size_t)*size);
    if (fread(data, 1, (size_t)*size, f) != (size_t)*size) {
        free(data);
        data = NULL;
    }
    fclose(f);
    return data;
}

int main(void) {
    char dir[] = "/tmp/c_encode_testXXXXXX";
    char array_path[256], callback_path[256], cancelled_path[256], ortho_dir[256], ortho_file[300];
    pyramid_height_source source;
    pyramid_dem_encode_options options;
    pyramid_file* file = NULL;
    pyramid_info info;
    long a_size = 0, c_size = 0;
    char *a, *c;
    int i, j;

    if (!mkdtemp(dir)) {
        return 1;
    }
    sprintf(array_path, "%s/array.dat", dir);
    sprintf(callback_path, "%s/callback.dat", dir);
    sprintf(cancelled_path, "%s/cancelled.dat", dir);
    sprintf(ortho_dir, "%s/ortho", dir);
    for (j = 0; j < H; ++j) {
        for (i = 0; i < W; ++i) {
            heights[j * W + i] = (float)(100.0 * sin(i * 0.11) * cos(j * 0.07) + 0.37 * i - 0.21 * j);
        }
    }

    memset(&source, 0, sizeof source);
    source.struct_size = sizeof source;
    source.width = W;
    source.height = H;
    source.heights = heights;
    options.struct_size = sizeof options;
    pyramid_dem_encode_defaults(&options);
    CHECK(options.tile_size == 192 && options.root_tile_size == 24 && options.max_level == -1 && options.scale == 1.0);
    options.tile_size = 16;
    options.root_tile_size = 4;
    options.scale = 0.5;
    CHECK(pyramid_encode_dem(&source, &options, array_path) == PYRAMID_OK);

    source.heights = NULL;
    source.read = read_heights;
    CHECK(pyramid_encode_dem(&source, &options, callback_path) == PYRAMID_OK);
    a = read_all(array_path, &a_size);
    c = read_all(callback_path, &c_size);
    CHECK(a && c && a_size == c_size && a_size > 500 && memcmp(a, c, (size_t)a_size) == 0);
    free(a);
    free(c);

    /* Read back: the finest level's heights within scale / 2 of the source. */
    CHECK(pyramid_open(array_path, &file) == PYRAMID_OK);
    if (file) {
        pyramid_elevation* producer = NULL;
        CHECK(pyramid_get_info(file, &info) == PYRAMID_OK);
        CHECK(info.kind == PYRAMID_KIND_RESIDUAL && info.tile_size == 16 && info.scale == 0.5f);
        CHECK(info.max_level == 5); /* 4 << 5 = 128 >= 96 intervals */
        pyramid_close(file);
        CHECK(pyramid_elevation_open(array_path, 0, 0, 16, &producer) == PYRAMID_OK);
        if (producer) {
            double z = 0.0;
            /* The longer side (96 intervals) spans the root quad's 128 finest intervals, the map at
             * its north-west corner: finest sample (x, y) is input column 3x/4, row (128 - y) 3/4.
             * Sample (40, 48) is input (30, 60), exactly. */
            CHECK(pyramid_elevation_height(producer, -1, 40.0 / 128.0, 48.0 / 128.0, &z) == PYRAMID_OK);
            CHECK(fabs(z - heights[60 * W + 30]) <= 0.25 + 1e-4);
            pyramid_elevation_close(producer);
        }
    }

    /* Tiles fitted to the map (96 intervals across: the finest level is its grid), coded with
     * Deflate and with context coding: the same residuals in every tile, in fewer bytes. */
    {
        pyramid_dem_encode_options fit = options;
        pyramid_file *deflate = NULL, *context = NULL;
        long deflate_size = 0, context_size = 0;
        char fit_deflate[300], fit_context[300];
        char* bytes;
        sprintf(fit_deflate, "%s/fit-deflate.dat", dir);
        sprintf(fit_context, "%s/fit-context.dat", dir);
        CHECK(options.fit_tiles == 0 && options.compression == PYRAMID_RESIDUAL_DEFLATE && options.deflate_level == 0);
        fit.fit_tiles = 1;
        fit.max_level = 9; /* ignored: the fit chooses */
        CHECK(pyramid_encode_dem(&source, &fit, fit_deflate) == PYRAMID_OK);
        fit.compression = PYRAMID_RESIDUAL_CONTEXT;
        CHECK(pyramid_encode_dem(&source, &fit, fit_context) == PYRAMID_OK);
        bytes = read_all(fit_deflate, &deflate_size);
        free(bytes);
        bytes = read_all(fit_context, &context_size);
        free(bytes);
        CHECK(context_size > 0 && context_size < deflate_size);
        CHECK(pyramid_open(fit_deflate, &deflate) == PYRAMID_OK);
        CHECK(pyramid_open(fit_context, &context) == PYRAMID_OK);
        if (deflate && context) {
            int level, tx, ty, tiles = 0;
            CHECK(pyramid_get_info(context, &info) == PYRAMID_OK);
            CHECK((info.tile_size >> info.min_level) << info.max_level == 96);
            for (level = 0; level <= info.max_level; ++level) {
                const int side = level < info.min_level ? 1 : 1 << (level - info.min_level);
                for (ty = 0; ty < side; ++ty) {
                    for (tx = 0; tx < side; ++tx) {
                        static short d[300 * 300], x[300 * 300];
                        size_t dn = 0, xn = 0;
                        CHECK(pyramid_read_tile(deflate, level, tx, ty, d, sizeof d, &dn) == PYRAMID_OK);
                        CHECK(pyramid_read_tile(context, level, tx, ty, x, sizeof x, &xn) == PYRAMID_OK);
                        CHECK(dn == xn && dn > 0 && memcmp(d, x, dn) == 0);
                        ++tiles;
                    }
                }
            }
            CHECK(tiles > 1);
        }
        pyramid_close(deflate);
        pyramid_close(context);
        remove(fit_deflate);
        remove(fit_context);
        fit.compression = 3;
        CHECK(pyramid_encode_dem(&source, &fit, cancelled_path) == PYRAMID_ERROR_ARGUMENT);
        CHECK(strstr(pyramid_last_error(), "compression 3") != NULL);
        fit.compression = PYRAMID_RESIDUAL_SMALLEST;
        fit.deflate_level = 13;
        CHECK(pyramid_encode_dem(&source, &fit, cancelled_path) == PYRAMID_ERROR_ARGUMENT);
        CHECK(strstr(pyramid_last_error(), "deflateLevel") != NULL);
        CHECK(access(cancelled_path, F_OK) != 0);
    }

    /* An old caller's smaller options struct: the missing fields take their defaults. */
    {
        pyramid_dem_encode_options old;
        memset(&old, 0, sizeof old);
        old.struct_size = offsetof(pyramid_dem_encode_options, scale);
        pyramid_dem_encode_defaults(&old);
        CHECK(old.struct_size == offsetof(pyramid_dem_encode_options, scale));
        CHECK(old.scale == 0.0); /* beyond its size: untouched */
        old.tile_size = 16;
        old.root_tile_size = 4;
        CHECK(pyramid_encode_dem(&source, &old, cancelled_path) == PYRAMID_OK);
        CHECK(remove(cancelled_path) == 0);
    }

    /* A newer caller's larger struct: *_defaults zeroes the members this library does not
     * know and keeps struct_size; set, such a member is refused, not dropped. */
    {
        struct newer_dem_options {
            pyramid_dem_encode_options known;
            double future;
        } newer;
        memset(&newer, 0xab, sizeof newer);
        newer.known.struct_size = sizeof newer;
        pyramid_dem_encode_defaults(&newer.known);
        CHECK(newer.known.struct_size == sizeof newer);
        CHECK(newer.future == 0.0);
        CHECK(newer.known.tile_size == 192 && newer.known.max_level == -1);
        newer.known.tile_size = 16;
        newer.known.root_tile_size = 4;
        CHECK(pyramid_encode_dem(&source, &newer.known, cancelled_path) == PYRAMID_OK);
        CHECK(remove(cancelled_path) == 0);
        newer.future = 1.0;
        CHECK(pyramid_encode_dem(&source, &newer.known, cancelled_path) == PYRAMID_ERROR_ARGUMENT);
        CHECK(strstr(pyramid_last_error(), "pyramid_dem_encode_options: members past byte") != NULL);
        CHECK(access(cancelled_path, F_OK) != 0);
    }

    /* A struct_size that cannot hold itself: *_defaults leaves the struct, the encode refuses it. */
    {
        pyramid_dem_encode_options unsized;
        memset(&unsized, 0, sizeof unsized);
        pyramid_dem_encode_defaults(&unsized);
        CHECK(unsized.struct_size == 0 && unsized.tile_size == 0);
        CHECK(pyramid_encode_dem(&source, &unsized, cancelled_path) == PYRAMID_ERROR_ARGUMENT);
        CHECK(strstr(pyramid_last_error(), "pyramid_dem_encode_options: struct_size 0 is too small") != NULL);
        CHECK(access(cancelled_path, F_OK) != 0);
    }

    /* A failing callback, and a cancelled run: statuses, messages, no file. */
    source.read = failing_read;
    CHECK(pyramid_encode_dem(&source, &options, cancelled_path) == PYRAMID_ERROR_FILE);
    CHECK(strstr(pyramid_last_error(), "returned 7") != NULL);
    CHECK(access(cancelled_path, F_OK) != 0);
    source.read = read_heights;
    options.progress = progress;
    options.cancel = cancel_after_two;
    options.threads = 1;
    CHECK(pyramid_encode_dem(&source, &options, cancelled_path) == PYRAMID_ERROR_CANCELLED);
    CHECK(strcmp(pyramid_status_name(PYRAMID_ERROR_CANCELLED), "cancelled") == 0);
    CHECK(tiles_seen == 2);
    CHECK(access(cancelled_path, F_OK) != 0);
    options.tile_size = 7;
    options.cancel = NULL;
    CHECK(pyramid_encode_dem(&source, &options, cancelled_path) == PYRAMID_ERROR_ARGUMENT);
    CHECK(strstr(pyramid_last_error(), "tileSize") != NULL);

    /* Ortho: an RGB array into three pyramids, read back as stored. */
    {
        /* 64 x 64 pixels: level 1 of 32-pixel tiles is the input, pixel for pixel. */
        static unsigned char pixels[64 * 64 * 3];
        pyramid_colour_source colours;
        pyramid_ortho_encode_options o;
        pyramid_ortho* ortho = NULL;
        for (i = 0; i < 64 * 64 * 3; ++i) {
            pixels[i] = (unsigned char)(i * 31 % 256);
        }
        memset(&colours, 0, sizeof colours);
        colours.struct_size = sizeof colours;
        colours.width = 64;
        colours.height = 64;
        colours.channels = 3;
        colours.pixels = pixels;
        o.struct_size = sizeof o;
        pyramid_ortho_encode_defaults(&o);
        o.tile_size = 32;
        o.name = "IMG";
        o.outputs = PYRAMID_ORTHO_TIFF;
        CHECK(pyramid_encode_ortho(&colours, &o, ortho_dir) == PYRAMID_OK);
        sprintf(ortho_file, "%s/IMG.dat", ortho_dir);
        CHECK(pyramid_ortho_open(ortho_file, 0, 4, &ortho) == PYRAMID_OK);
        if (ortho) {
            int side = 0, channels = 0;
            static unsigned char tile[36 * 36 * 3];
            CHECK(pyramid_ortho_layout(ortho, &side, &channels) == PYRAMID_OK);
            CHECK(side == 36 && channels == 3);
            /* Tile (1, 0, 1) is the north-west tile of level 1; its pixel (2 + x, 2 + 31 - y), row 0
             * = south, is input pixel (x, y), row 0 = north. */
            CHECK(pyramid_ortho_tile(ortho, 1, 0, 1, tile, sizeof tile) == PYRAMID_OK);
            CHECK(memcmp(&tile[((2 + 31) * 36 + 2) * 3], &pixels[0], 3) == 0);
            CHECK(memcmp(&tile[((2 + 31 - 5) * 36 + 2 + 9) * 3], &pixels[(5 * 64 + 9) * 3], 3) == 0);
            pyramid_ortho_close(ortho);
            ortho = NULL;
        }
        remove(ortho_file);
        /* fit_tiles (0 by default): one 64-pixel tile holds the 64 x 64 image, the tile size and
         * max_level given ignored. */
        pyramid_ortho_encode_defaults(&o);
        CHECK(o.fit_tiles == 0);
        o.fit_tiles = 1;
        o.tile_size = 0;
        o.max_level = 3;
        o.name = "IMG";
        o.outputs = PYRAMID_ORTHO_TIFF;
        CHECK(pyramid_encode_ortho(&colours, &o, ortho_dir) == PYRAMID_OK);
        CHECK(pyramid_ortho_open(ortho_file, 0, 4, &ortho) == PYRAMID_OK);
        if (ortho) {
            int side = 0, channels = 0;
            CHECK(pyramid_ortho_layout(ortho, &side, &channels) == PYRAMID_OK);
            CHECK(side == 68 && channels == 3);
            pyramid_ortho_close(ortho);
        }
        remove(ortho_file);
        rmdir(ortho_dir);
    }

    remove(array_path);
    remove(callback_path);
    rmdir(dir);
    return check_summary();
}
