/* The C API's own answers, as the reference the Python package's arrays are compared with: built
 * by the tests against the installed copy (pkg-config libpyramid-runtime), it writes the raw
 * results of the calls the package wraps, one after the other, to OUT.
 *
 *   tile_dump elevation FILE OUT L,TX,TY...   zf of each tile (float32), file's tile size
 *   tile_dump residual  FILE OUT L,TX,TY...   pyramid_read_tile (int16)
 *   tile_dump normals   FILE OUT SIZE L,TX,TY...  pyramid_normal_tile, plane of side SIZE (float32)
 *   tile_dump ortho     FILE OUT L,TX,TY...   pyramid_ortho_tile, no colour residuals (uint8)
 *   tile_dump height    FILE OUT U,V...       pyramid_elevation_height at level -1 (double)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libpyramid/capi/pyramid.h"

static int fail(const char* what, pyramid_status s) {
    fprintf(stderr, "tile_dump: %s: %s: %s\n", what, pyramid_status_name(s), pyramid_last_error());
    return 1;
}

static int write_all(FILE* out, const void* data, size_t bytes) {
    return fwrite(data, 1, bytes, out) == bytes ? 0 : 1;
}

int main(int argc, char** argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: tile_dump KIND FILE OUT [SIZE] ARGS...\n");
        return 2;
    }
    const char* kind = argv[1];
    const char* path = argv[2];
    FILE* out = fopen(argv[3], "wb");
    int first = 4, status = 0;
    if (!out) {
        perror(argv[3]);
        return 1;
    }
    pyramid_status s = PYRAMID_OK;
    pyramid_file* file = NULL;
    pyramid_elevation* elevation = NULL;
    pyramid_normal* normal = NULL;
    pyramid_ortho* ortho = NULL;
    if (strcmp(kind, "residual") == 0) {
        s = pyramid_open(path, &file);
    } else if (strcmp(kind, "ortho") == 0) {
        s = pyramid_ortho_open(path, 0, 16, &ortho);
    } else {
        s = pyramid_elevation_open(path, 0, 0, 16, &elevation);
        if (s == PYRAMID_OK && strcmp(kind, "normals") == 0) {
            pyramid_normal_options o;
            memset(&o, 0, sizeof o);
            o.struct_size = sizeof o;
            o.deformation = PYRAMID_DEFORM_PLANE;
            o.size = atof(argv[first++]);
            o.cache_tiles = 16;
            s = pyramid_normal_open(elevation, &o, &normal);
        }
    }
    if (s != PYRAMID_OK) {
        return fail(path, s);
    }
    for (int a = first; a < argc && status == 0; ++a) {
        int level = 0, tx = 0, ty = 0;
        double u = 0.0, v = 0.0;
        if (strcmp(kind, "height") == 0) {
            double h = 0.0;
            if (sscanf(argv[a], "%lf,%lf", &u, &v) != 2) {
                return 2;
            }
            s = pyramid_elevation_height(elevation, -1, u, v, &h);
            status = s != PYRAMID_OK ? fail(argv[a], s) : write_all(out, &h, sizeof h);
            continue;
        }
        if (sscanf(argv[a], "%d,%d,%d", &level, &tx, &ty) != 3) {
            return 2;
        }
        if (strcmp(kind, "elevation") == 0) {
            const size_t n = (size_t)pyramid_elevation_side(elevation) * (size_t)pyramid_elevation_side(elevation);
            float* zf = malloc(n * sizeof(float));
            s = pyramid_elevation_tile(elevation, level, tx, ty, zf, NULL, NULL, n);
            status = s != PYRAMID_OK ? fail(argv[a], s) : write_all(out, zf, n * sizeof(float));
            free(zf);
        } else if (strcmp(kind, "normals") == 0) {
            const size_t n = 4 * (size_t)pyramid_normal_side(normal) * (size_t)pyramid_normal_side(normal);
            float* nv = malloc(n * sizeof(float));
            s = pyramid_normal_tile(normal, level, tx, ty, nv, n);
            status = s != PYRAMID_OK ? fail(argv[a], s) : write_all(out, nv, n * sizeof(float));
            free(nv);
        } else if (strcmp(kind, "residual") == 0) {
            size_t needed = 0;
            s = pyramid_read_tile(file, level, tx, ty, NULL, 0, &needed);
            void* buffer = malloc(needed ? needed : 1);
            if (s == PYRAMID_OK) {
                s = pyramid_read_tile(file, level, tx, ty, buffer, needed, NULL);
            }
            status = s != PYRAMID_OK ? fail(argv[a], s) : write_all(out, buffer, needed);
            free(buffer);
        } else if (strcmp(kind, "ortho") == 0) {
            int side = 0, channels = 0;
            s = pyramid_ortho_layout(ortho, &side, &channels);
            const size_t bytes = (size_t)side * (size_t)side * (size_t)channels;
            unsigned char* pixels = malloc(bytes);
            if (s == PYRAMID_OK) {
                s = pyramid_ortho_tile(ortho, level, tx, ty, pixels, bytes);
            }
            status = s != PYRAMID_OK ? fail(argv[a], s) : write_all(out, pixels, bytes);
            free(pixels);
        } else {
            fprintf(stderr, "tile_dump: unknown kind %s\n", kind);
            status = 2;
        }
    }
    pyramid_normal_close(normal);
    pyramid_elevation_close(elevation);
    pyramid_ortho_close(ortho);
    pyramid_close(file);
    if (fclose(out) != 0) {
        status = 1;
    }
    return status;
}
