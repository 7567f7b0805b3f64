/* The C API from C99, through the public header only, on the original tools' files.
 * argv[1] is the tests/data directory. */
#include <math.h>
#include <stddef.h>
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

/* ---- Memory and callback sources ----------------------------------------------------------- */

/* A whole file in memory; NULL (and *size 0) when it cannot be read. */
static unsigned char* load_file(const char* path, size_t* size) {
    FILE* f = fopen(path, "rb");
    unsigned char* data = NULL;
    long n;
    *size = 0;
    if (!f) {
        return NULL;
    }
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) > 0 && fseek(f, 0, SEEK_SET) == 0) {
        data = (unsigned char*)malloc((size_t)n);
        if (data && fread(data, 1, (size_t)n, f) == (size_t)n) {
            *size = (size_t)n;
        } else {
            free(data);
            data = NULL;
        }
    }
    fclose(f);
    return data;
}

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

static int counting_read(void* user, uint64_t offset, void* buffer, size_t size, size_t* bytes_read) {
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

static void counting_release(void* user) { ++((counting_io*)user)->released; }

static void counting_init(counting_io* io, const unsigned char* data, size_t size) {
    memset(io, 0, sizeof *io);
    io->data = data;
    io->size = size;
}

static pyramid_source path_source(const char* path) {
    pyramid_source s;
    memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_PATH;
    s.path = path;
    return s;
}

static pyramid_source memory_source(const void* data, size_t size) {
    pyramid_source s;
    memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_MEMORY;
    s.name = "DEM in memory";
    s.data = data;
    s.size = size;
    return s;
}

static pyramid_source io_source(counting_io* io, const char* name) {
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
static void check_same_tiles(pyramid_file* reference, pyramid_file* other) {
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
static void check_same_elevations(pyramid_elevation* reference, pyramid_elevation* other) {
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
static void check_same_ortho(pyramid_ortho* reference, pyramid_ortho* other) {
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
    test_sources(argv[1]);
    test_stat(argv[1]);
    test_status_names();
    test_sized_structs(argv[1]);
    test_sized_options(argv[1]);
    test_failing_io(argv[1]);
    test_scale(argv[1]);
    printf("%d passed, %d failed\n", checks - failures, failures);
    return failures ? 1 : 0;
}
