/*
 * libpyramid C API: read Proland residual (DEM) and ortho pyramid files and rebuild their
 * tiles, from C, C++ or any language with a C FFI. See doc/c-api.md.
 *
 * Conventions
 *   - Every function returns a pyramid_status; PYRAMID_OK is 0. On failure, pyramid_last_error()
 *     returns a one-line message (thread-local: it describes the calling thread's last failure).
 *   - Handles are opaque. A handle may be used from several threads at once.
 *   - Tiles are row-major with row 0 = the tile's bottom (south) row, as stored in the files.
 *   - No C++ exception ever crosses this interface.
 */
#ifndef LIBPYRAMID_PYRAMID_H
#define LIBPYRAMID_PYRAMID_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The functions below are the shared library's exports; it hides every other symbol. */
#if defined(__GNUC__)
#define PYRAMID_API __attribute__((visibility("default")))
#else
#define PYRAMID_API
#endif

#define PYRAMID_VERSION_MAJOR 0
#define PYRAMID_VERSION_MINOR 2
#define PYRAMID_VERSION_PATCH 0
/* MAJOR * 10000 + MINOR * 100 + PATCH */
#define PYRAMID_VERSION_NUMBER (PYRAMID_VERSION_MAJOR * 10000 + PYRAMID_VERSION_MINOR * 100 + PYRAMID_VERSION_PATCH)

typedef enum pyramid_status {
    PYRAMID_OK = 0,
    PYRAMID_ERROR_ARGUMENT = 1,  /* a null pointer, a tile outside the pyramid, a buffer too small */
    PYRAMID_ERROR_FILE = 2,      /* a file is missing, unreadable, or not a valid pyramid file */
    PYRAMID_ERROR_MEMORY = 3,
    PYRAMID_ERROR_INTERNAL = 4,
    PYRAMID_ERROR_CANCELLED = 6  /* an encoding stopped by its cancel callback (pyramid_encode.h) */
} pyramid_status;

typedef enum pyramid_kind {
    PYRAMID_KIND_RESIDUAL = 1, /* residual (DEM) file: int16 residual tiles */
    PYRAMID_KIND_ORTHO = 2     /* ortho file: 8-bit TIFF or DXT tiles */
} pyramid_kind;

/* The library's version (as PYRAMID_VERSION_NUMBER) and version text ("0.2.0"). */
PYRAMID_API int pyramid_version_number(void);
PYRAMID_API const char* pyramid_version_string(void);

/* The calling thread's last error message, "" if none. Valid until its next failing call. */
PYRAMID_API const char* pyramid_last_error(void);
/* A constant name for a status: "ok", "argument", "file", "memory", "internal". */
PYRAMID_API const char* pyramid_status_name(pyramid_status status);

/* ---- Files ------------------------------------------------------------------------------- */

typedef struct pyramid_file pyramid_file;

typedef struct pyramid_info {
    pyramid_kind kind;
    int max_level;      /* deepest level, counted from the file's root tile */
    int tile_size;      /* residual: intervals (tiles are tile_size + 5 samples); ortho: pixels */
    int root_level, root_tx, root_ty;
    int min_level;      /* residual files; 0 for ortho files */
    float scale;        /* residual files: height units per residual unit; 0 for ortho files */
    int channels;       /* ortho files: 1..4; 1 for residual files */
    int border;         /* ortho files: 0 or 2 pixels; 2 for residual files */
    int dxt;            /* ortho files: 1 when tiles are DXT blocks */
    long long tile_count;
} pyramid_info;

PYRAMID_API pyramid_status pyramid_open(const char* path, pyramid_file** file);
PYRAMID_API void pyramid_close(pyramid_file* file); /* NULL is allowed */
PYRAMID_API pyramid_status pyramid_get_info(const pyramid_file* file, pyramid_info* info);

/* Samples per side of the stored tiles of `level` (borders included). */
PYRAMID_API pyramid_status pyramid_tile_side(const pyramid_file* file, int level, int* side);

/* A decoded tile. Residual files: side^2 int16 residuals (2 bytes each); ortho files:
 * side^2 x channels bytes (DXT decoded to RGB or RGBA). `size` is the buffer's size in bytes;
 * `written` (may be NULL) receives the bytes written. With buffer == NULL, only `written`
 * is set, to the size needed. */
PYRAMID_API pyramid_status pyramid_read_tile(const pyramid_file* file, int level, int tx, int ty, void* buffer, size_t size,
                                 size_t* written);

/* The tile as stored (a TIFF file, or raw DXT blocks ready for a compressed-texture upload);
 * same buffer protocol as pyramid_read_tile. */
PYRAMID_API pyramid_status pyramid_read_tile_bytes(const pyramid_file* file, int level, int tx, int ty, void* buffer,
                                       size_t size, size_t* written);

/* ---- Elevation producer ------------------------------------------------------------------ */

typedef struct pyramid_elevation pyramid_elevation;

/* Elevation tiles of n = tile_size intervals ((n+5)^2 samples), n = the file's tile size
 * divided by a power of two no larger than 2^min_level (0 = the file's tile size), rendered
 * with grid_size quads per side for the coarse elevations zc (0 = n). At most `cache_tiles`
 * tiles are kept (least recently used first out). */
PYRAMID_API pyramid_status pyramid_elevation_open(const char* residual_path, int tile_size, int grid_size, size_t cache_tiles,
                                      pyramid_elevation** producer);
/* The same over a main file and `region_count` region files nested in it (each rooted at a tile
 * of the main pyramid, or of another region, with the main file's tile size): a tile's
 * residuals come from the deepest file that holds it. */
PYRAMID_API pyramid_status pyramid_elevation_open_regions(const char* residual_path, const char* const* region_paths,
                                              size_t region_count, int tile_size, int grid_size, size_t cache_tiles,
                                              pyramid_elevation** producer);
PYRAMID_API void pyramid_elevation_close(pyramid_elevation* producer);
/* Samples per side of the produced tiles (n + 5). */
PYRAMID_API int pyramid_elevation_side(const pyramid_elevation* producer);
/* Quadtree tile (level, tx, ty): zf (elevations), zc (coarse elevations) and zm (modified
 * elevations, = zf) into arrays of `count` floats, count >= side^2; zc and zm may be NULL. */
PYRAMID_API pyramid_status pyramid_elevation_tile(pyramid_elevation* producer, int level, int tx, int ty, float* zf, float* zc,
                                      float* zm, size_t count);

/* The height at point (u, v) of the root quad (u east, v north, both in [0, 1]) in the tiles of
 * `level` (-1: the deepest with residuals): the bilinear interpolation, in double precision, of
 * the four zf samples around the point in the tile that holds it. */
PYRAMID_API pyramid_status pyramid_elevation_height(pyramid_elevation* producer, int level, double u, double v, double* height);

/* ---- Ortho producer ---------------------------------------------------------------------- */

typedef struct pyramid_ortho pyramid_ortho;

/* colour_residuals = 0: the file's tiles as they are; 1: the file holds colour residuals and
 * tiles are rebuilt by the colour upsample (any level, smooth beyond the file's deepest). */
PYRAMID_API pyramid_status pyramid_ortho_open(const char* path, int colour_residuals, size_t cache_tiles, pyramid_ortho** producer);
/* The same over a main file and `region_count` nested region files (same tile size, channels
 * and flags). */
PYRAMID_API pyramid_status pyramid_ortho_open_regions(const char* path, const char* const* region_paths, size_t region_count,
                                          int colour_residuals, size_t cache_tiles, pyramid_ortho** producer);
PYRAMID_API void pyramid_ortho_close(pyramid_ortho* producer);
/* Pixels per side and channels of the produced tiles. */
PYRAMID_API pyramid_status pyramid_ortho_layout(const pyramid_ortho* producer, int* side, int* channels);
/* side^2 x channels bytes into `pixels` (`size` bytes). */
PYRAMID_API pyramid_status pyramid_ortho_tile(pyramid_ortho* producer, int level, int tx, int ty, unsigned char* pixels,
                                  size_t size);

#ifdef __cplusplus
}
#endif

#endif /* LIBPYRAMID_PYRAMID_H */
