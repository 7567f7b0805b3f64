/*
 * libpyramid C API, encoding: a DEM (residual) or ortho pyramid from a caller's array or
 * callback, as preprocessDem and preprocessOrtho make them from files. Part of the preprocess
 * library (libpyramid::preprocess, pkg-config libpyramid-preprocess), not of the runtime; the
 * conventions of pyramid.h hold (statuses, pyramid_last_error, no exception crosses).
 * See doc/library.md.
 *
 * Option structs are size-prefixed, by the rule of pyramid.h's structs: set struct_size to
 * sizeof the struct, fill it with the *_defaults function, then change what you need. A caller
 * built against an older, smaller struct keeps working: the fields it does not have take their
 * defaults. A larger struct (a newer header) is accepted when the members this library does
 * not know are zero, which *_defaults makes them, and refused (PYRAMID_ERROR_ARGUMENT)
 * otherwise: an option the library cannot honour is not dropped silently. *_defaults leaves a
 * struct whose struct_size cannot hold itself untouched; the encode call then refuses it.
 */
#ifndef LIBPYRAMID_PYRAMID_ENCODE_H
#define LIBPYRAMID_PYRAMID_ENCODE_H

#include <stddef.h>

#include "libpyramid/capi/pyramid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads columns [x0, x1) of rows [y0, y1), row y0 first (row 0 = north), into `out`: heights
 * (x1 - x0) * (y1 - y0) floats, or colours (x1 - x0) * (y1 - y0) * channels bytes, channels
 * interleaved. Returns 0 on success; anything else stops the encoding (PYRAMID_ERROR_FILE).
 * Called from several threads at once. */
typedef int (*pyramid_read_heights_fn)(void* user, int x0, int y0, int x1, int y1, float* out);
typedef int (*pyramid_read_colours_fn)(void* user, int x0, int y0, int x1, int y1, unsigned char* out);
/* Called after every tile, from one thread at a time. */
typedef void (*pyramid_progress_fn)(void* user, long long done, long long total);
/* Called after every tile, from one thread at a time: non-zero stops the encoding, which
 * returns PYRAMID_ERROR_CANCELLED and leaves no file behind. */
typedef int (*pyramid_cancel_fn)(void* user);

/* Heights of a width x height map: `heights` (width * height floats, row-major, row 0 = north,
 * borrowed for the call) or, when it is NULL, `read` with `user`. */
typedef struct pyramid_height_source {
    size_t struct_size;
    int width, height;
    const float* heights;
    pyramid_read_heights_fn read;
    void* user;
    int has_nodata;        /* 1: `nodata` marks missing heights (NAN allowed) */
    double nodata;
} pyramid_height_source;

typedef struct pyramid_dem_encode_options {
    size_t struct_size;
    int tile_size;         /* 192: intervals per tile (tiles are tile_size + 5 samples) */
    int root_tile_size;    /* 24: intervals of the level-0 tile */
    int max_level;         /* -1: the smallest pyramid whose finest level holds every sample (other negatives: refused) */
    double scale;          /* 1: height units per residual unit; 0: the smallest 1-2-5 step that fits */
    int threads;           /* 0: every core; at most 1024 (the file does not depend on it) */
    pyramid_progress_fn progress; /* may be NULL */
    pyramid_cancel_fn cancel;     /* may be NULL */
    void* user;                   /* passed to progress and cancel */
    /* 1: tile_size, root_tile_size and max_level are chosen (and those given ignored) so that
     * the finest level is the map's own grid, as preprocessDem --tile-size auto does. */
    int fit_tiles;
    int compression;       /* PYRAMID_RESIDUAL_DEFLATE (the default), _SMALLEST or _CONTEXT */
    int deflate_level;     /* 0: the codec's default (2, or 12 for _SMALLEST); 1..12 */
} pyramid_dem_encode_options;

/* How residual tiles are coded (preprocessDem --compression; doc/format.md). */
enum {
    PYRAMID_RESIDUAL_DEFLATE = 0,  /* TIFF tiles as the original tools write them */
    PYRAMID_RESIDUAL_SMALLEST = 1, /* per tile the smallest TIFF the original runtime reads */
    PYRAMID_RESIDUAL_CONTEXT = 2   /* context-coded: smallest, libpyramid's readers only */
};

PYRAMID_API void pyramid_dem_encode_defaults(pyramid_dem_encode_options* options);

/* Writes the residual pyramid file `output` (atomically: the whole file or nothing). Reports
 * are the C++ API's (doc/library.md); this returns the status only. */
PYRAMID_API pyramid_status pyramid_encode_dem(const pyramid_height_source* source,
                                              const pyramid_dem_encode_options* options, const char* output);

/* Colours of a width x height image with 1 to 4 8-bit channels: `pixels` (row-major, row 0 =
 * north, channels interleaved, borrowed for the call) or, when it is NULL, `read`. */
typedef struct pyramid_colour_source {
    size_t struct_size;
    int width, height, channels;
    const unsigned char* pixels;
    pyramid_read_colours_fn read;
    void* user;
} pyramid_colour_source;

enum {
    PYRAMID_ORTHO_TIFF = 1,      /* DIR/NAME.dat */
    PYRAMID_ORTHO_DXT = 2,       /* DIR/dxt/NAME.dat */
    PYRAMID_ORTHO_RESIDUALS = 4  /* DIR/residuals/NAME.dat */
};

typedef struct pyramid_ortho_encode_options {
    size_t struct_size;
    int tile_size;         /* 192: pixels per tile, without borders */
    int max_level;         /* -1: the smallest level whose width holds the longer side (other negatives: refused) */
    const char* name;      /* "RGB": the files' name */
    int outputs;           /* PYRAMID_ORTHO_* flags; all three by default */
    int threads;           /* 0: every core; at most 1024 */
    pyramid_progress_fn progress;
    pyramid_cancel_fn cancel;
    void* user;
    /* 1: tile_size and max_level are chosen (and those given ignored) so that the finest level
     * fits the image's longer side with the least resampling, as preprocessOrtho --tile-size
     * auto does. */
    int fit_tiles;
} pyramid_ortho_encode_options;

PYRAMID_API void pyramid_ortho_encode_defaults(pyramid_ortho_encode_options* options);

/* Writes the ortho pyramids into `directory` (created if missing); they appear together, or
 * none does. */
PYRAMID_API pyramid_status pyramid_encode_ortho(const pyramid_colour_source* source,
                                                const pyramid_ortho_encode_options* options, const char* directory);

#ifdef __cplusplus
}
#endif

#endif /* LIBPYRAMID_PYRAMID_ENCODE_H */
