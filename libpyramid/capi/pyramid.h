/*
 * libpyramid C API: read Proland residual (DEM) and ortho pyramid files and rebuild their
 * tiles, from C, C++ or any language with a C FFI. See doc/c-api.md.
 *
 * Conventions
 *   - Every function returns a pyramid_status; PYRAMID_OK is 0. On failure, pyramid_last_error()
 *     returns a one-line message (thread-local: it describes the calling thread's last failure).
 *   - Handles are opaque. Every function that takes a handle may be called from several threads
 *     at once on the same handle, except its *_close function, which must be the handle's last
 *     call. Functions without a handle may be called from any thread at any time.
 *   - Ownership: a handle is the caller's from its open until its *_close. Strings and arrays
 *     passed to a function are only read during the call, except the memory of a memory source
 *     and the callbacks of an I/O source (see pyramid_source).
 *   - Structs whose first member is `size_t struct_size` can grow: the caller sets struct_size to
 *     sizeof the struct it was compiled with. The library reads or fills only that many bytes;
 *     members beyond them take their zero defaults (inputs) or are left alone (outputs). In a
 *     struct larger than the library's own, the members it does not know must be zero (inputs)
 *     or are zeroed (outputs). struct_size < sizeof(size_t) is PYRAMID_ERROR_ARGUMENT.
 *   - Tiles are row-major with row 0 = the tile's bottom (south) row, as stored in the files.
 *   - No C++ exception ever crosses this interface.
 */
#ifndef LIBPYRAMID_PYRAMID_H
#define LIBPYRAMID_PYRAMID_H

#include <stddef.h>
#include <stdint.h>

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
#define PYRAMID_VERSION_PATCH 2
/* MAJOR * 10000 + MINOR * 100 + PATCH */
#define PYRAMID_VERSION_NUMBER (PYRAMID_VERSION_MAJOR * 10000 + PYRAMID_VERSION_MINOR * 100 + PYRAMID_VERSION_PATCH)

typedef enum pyramid_status {
    PYRAMID_OK = 0,
    PYRAMID_ERROR_ARGUMENT = 1,  /* a null pointer, a buffer too small, an option out of range */
    PYRAMID_ERROR_FILE = 2,      /* a file (source) is missing, unreadable, or not a valid pyramid
                                    file; a read callback failed */
    PYRAMID_ERROR_MEMORY = 3,
    PYRAMID_ERROR_INTERNAL = 4,
    PYRAMID_ERROR_NOT_FOUND = 5,  /* (0.2.1) a tile the pyramid does not hold: outside its levels
                                    or tiles, or stored as an empty byte range */
    PYRAMID_ERROR_CANCELLED = 6  /* an encoding stopped by its cancel callback (pyramid_encode.h) */
} pyramid_status;

typedef enum pyramid_kind {
    PYRAMID_KIND_RESIDUAL = 1, /* residual (DEM) file: int16 residual tiles */
    PYRAMID_KIND_ORTHO = 2     /* ortho file: 8-bit TIFF or DXT tiles */
} pyramid_kind;

/* The library's version (as PYRAMID_VERSION_NUMBER) and version text ("0.2.2"). */
PYRAMID_API int pyramid_version_number(void);
PYRAMID_API const char* pyramid_version_string(void);

/* The calling thread's last error message, "" if none. Valid until its next failing call. */
PYRAMID_API const char* pyramid_last_error(void);
/* A constant name for a status: "ok", "argument", "file", "memory", "internal", "not_found",
 * "cancelled" ("unknown" for a value outside the enum). */
PYRAMID_API const char* pyramid_status_name(pyramid_status status);

/* ---- Sources (0.2.1) ----------------------------------------------------------------------- */

/* I/O callbacks: a pyramid file read at offsets from anything (a pak file, an asset manager,
 * HTTP range requests). */
typedef struct pyramid_io {
    /* Reads `size` bytes at byte `offset` of the source into `buffer` and stores the number of
     * bytes read in *bytes_read. Returns 0 on success. A non-zero return or fewer bytes than
     * asked is a failure: the call that read gives PYRAMID_ERROR_FILE with a message naming the
     * source. The library never asks for bytes past `size`. Called from the threads that use
     * the handle, from several at once when a handle is shared: it must be thread-safe. */
    int (*read)(void* user, uint64_t offset, void* buffer, size_t size, size_t* bytes_read);
    /* May be NULL. Called once with `user` when the handle that took these callbacks is closed,
     * after its last read (an elevation handle with a normal producer made from it: when the
     * later of the two closes, since the producer reads through it); never when the open fails
     * (the callbacks stay the caller's). */
    void (*release)(void* user);
    void* user;    /* passed to read and release */
    uint64_t size; /* total bytes of the source */
} pyramid_io;

typedef enum pyramid_source_kind {
    PYRAMID_SOURCE_PATH = 1,   /* a file, by its path */
    PYRAMID_SOURCE_MEMORY = 2, /* a block of memory holding the whole file */
    PYRAMID_SOURCE_IO = 3      /* I/O callbacks */
} pyramid_source_kind;

/* Where a pyramid file's bytes come from. Size-prefixed: set struct_size = sizeof(pyramid_source).
 * Ownership: `name` and `path` are copied during the open call. The memory of a MEMORY source is
 * borrowed: it must stay allocated and unchanged until the handle opened from it is closed.
 * An IO source's callbacks are the handle's once the open succeeds (release, above). */
typedef struct pyramid_source {
    size_t struct_size;
    pyramid_source_kind kind;
    const char* name; /* MEMORY, IO: used in messages (NULL: "(memory)", "(io)"); a PATH source
                         is named by its path */
    const char* path; /* PYRAMID_SOURCE_PATH */
    const void* data; /* PYRAMID_SOURCE_MEMORY: the file's bytes (borrowed) ... */
    size_t size;      /* ... and their number */
    pyramid_io io;    /* PYRAMID_SOURCE_IO */
} pyramid_source;

/* ---- Files ------------------------------------------------------------------------------- */

typedef struct pyramid_file pyramid_file;

/* The header of a file (pyramid_get_info). Fixed: new members go to pyramid_file_info. */
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

/* (0.2.1) The same header, size-prefixed so that it can grow, and what the offset table says. */
typedef struct pyramid_file_info {
    size_t struct_size; /* set by the caller: sizeof(pyramid_file_info) */
    pyramid_kind kind;
    int max_level, tile_size, root_level, root_tx, root_ty, min_level;
    float scale;
    int channels, border, dxt;
    long long tile_count;
    uint64_t source_size;    /* bytes of the file (source) */
    uint64_t data_offset;    /* where the tile data begins: after the header and offset table */
    long long stored_tiles;  /* tiles with a non-empty byte range (the others are NOT_FOUND) */
    long long distinct_tiles; /* distinct byte ranges: tiles sharing bytes count once */
} pyramid_file_info;

/* (0.2.1) One tile as the offset table and header describe it (pyramid_tile_stat). */
typedef struct pyramid_tile_info {
    size_t struct_size;   /* set by the caller: sizeof(pyramid_tile_info) */
    int exists;           /* 1 when the file stores bytes for the tile, 0 for an empty range */
    int side;             /* samples (pixels) per side of the decoded tile, borders included */
    int channels;         /* residual files: 1 (int16 samples); ortho files: bytes per pixel */
    size_t stored_bytes;  /* pyramid_read_tile_bytes' size; 0 when the tile does not exist */
    size_t decoded_bytes; /* pyramid_read_tile's size: side^2 x 2 (residual) or x channels */
    uint64_t offset;      /* byte offset of the stored bytes in the file (source) */
} pyramid_tile_info;

/* Opens a residual or ortho file; the kind is detected from the content (the header and the
 * whole offset table are validated against the file size). */
PYRAMID_API pyramid_status pyramid_open(const char* path, pyramid_file** file);
/* (0.2.1) The same from a path, a block of memory or I/O callbacks. */
PYRAMID_API pyramid_status pyramid_open_source(const pyramid_source* source, pyramid_file** file);
PYRAMID_API void pyramid_close(pyramid_file* file); /* NULL is allowed */
PYRAMID_API pyramid_status pyramid_get_info(const pyramid_file* file, pyramid_info* info);
/* (0.2.1) Fills info->struct_size bytes of `info` (at least sizeof(size_t)). No read. */
PYRAMID_API pyramid_status pyramid_get_file_info(const pyramid_file* file, pyramid_file_info* info);

/* Samples per side of the stored tiles of `level` (borders included). A level outside the
 * file is PYRAMID_ERROR_NOT_FOUND. */
PYRAMID_API pyramid_status pyramid_tile_side(const pyramid_file* file, int level, int* side);

/* (0.2.1) Existence, stored and decoded sizes of a tile, from the offset table and the header:
 * nothing is read or decoded. A tile outside the pyramid is PYRAMID_ERROR_NOT_FOUND (info
 * zeroed); a tile inside it stored as an empty range is PYRAMID_OK with exists = 0. */
PYRAMID_API pyramid_status pyramid_tile_stat(const pyramid_file* file, int level, int tx, int ty,
                                             pyramid_tile_info* info);

/* A decoded tile. Residual files: side^2 int16 residuals (2 bytes each); ortho files:
 * side^2 x channels bytes (DXT decoded to RGB or RGBA). `size` is the buffer's size in bytes;
 * `written` (may be NULL) receives the bytes written. With buffer == NULL, only `written`
 * is set, to the size needed, from the header (nothing is read or decoded). A buffer too small
 * is PYRAMID_ERROR_ARGUMENT (`written` still gives the size needed); a tile the file does not
 * hold is PYRAMID_ERROR_NOT_FOUND (`written` 0). */
PYRAMID_API pyramid_status pyramid_read_tile(const pyramid_file* file, int level, int tx, int ty, void* buffer, size_t size,
                                 size_t* written);

/* The tile as stored (a TIFF file, or raw DXT blocks ready for a compressed-texture upload);
 * same buffer protocol as pyramid_read_tile (with buffer == NULL, the size comes from the
 * offset table). */
PYRAMID_API pyramid_status pyramid_read_tile_bytes(const pyramid_file* file, int level, int tx, int ty, void* buffer,
                                       size_t size, size_t* written);

/* ---- Elevation producer ------------------------------------------------------------------ */

typedef struct pyramid_elevation pyramid_elevation;

/* Elevation tiles of n = tile_size intervals ((n+5)^2 samples), n = the file's tile size
 * divided by a power of two no larger than 2^min_level (0 = the file's tile size), rendered
 * with grid_size quads per side for the coarse elevations zc (0 = n). At most `cache_tiles`
 * tiles are kept (least recently used first out). `residual_path` may also name a region set
 * (doc/format.md 1.5): its main file with its index beside it, the index (NAME.regions.json)
 * or the directory holding it; the set's rules are checked and each tile comes from the
 * deepest file holding it. */
PYRAMID_API pyramid_status pyramid_elevation_open(const char* residual_path, int tile_size, int grid_size, size_t cache_tiles,
                                      pyramid_elevation** producer);
/* The same over a main file and `region_count` region files nested in it (each rooted at a tile
 * of the main pyramid, or of another region, with the main file's tile size): a tile's
 * residuals come from the deepest file that holds it. */
PYRAMID_API pyramid_status pyramid_elevation_open_regions(const char* residual_path, const char* const* region_paths,
                                              size_t region_count, int tile_size, int grid_size, size_t cache_tiles,
                                              pyramid_elevation** producer);

/* (0.2.1) The elevation producer's options. Size-prefixed; a zeroed struct (with struct_size
 * set) gives the defaults. */
typedef struct pyramid_elevation_options {
    size_t struct_size; /* sizeof(pyramid_elevation_options) */
    int tile_size;      /* n; 0 = the file's tile size */
    int grid_size;      /* quads per side of the render grid for zc; 0 = n */
    size_t cache_tiles; /* produced tiles kept; 0 is taken as 1 */
    /* The residual producer's `scale`: every residual of every file is multiplied by
     * (file scale x scale), that product taken once in float32. 0 = 1 (the files' scales as
     * they are); non-finite is PYRAMID_ERROR_ARGUMENT, and so is a product with a file's scale
     * that underflows to 0 or puts a residual beyond float's range. */
    float scale;
} pyramid_elevation_options;

/* (0.2.1) The elevation producer over a main source and `region_count` region sources
 * (`regions` may be NULL when region_count is 0); `options` may be NULL (the defaults). */
PYRAMID_API pyramid_status pyramid_elevation_open_sources(const pyramid_source* main_source,
                                                          const pyramid_source* const* regions, size_t region_count,
                                                          const pyramid_elevation_options* options,
                                                          pyramid_elevation** producer);
PYRAMID_API void pyramid_elevation_close(pyramid_elevation* producer);
/* Samples per side of the produced tiles (n + 5). */
PYRAMID_API int pyramid_elevation_side(const pyramid_elevation* producer);
/* Quadtree tile (level, tx, ty): zf (elevations), zc (coarse elevations) and zm (modified
 * elevations, = zf) into arrays of `count` floats, count >= side^2; zc and zm may be NULL.
 * Every tile of levels 0..30 exists; (level, tx, ty) outside them is PYRAMID_ERROR_NOT_FOUND. */
PYRAMID_API pyramid_status pyramid_elevation_tile(pyramid_elevation* producer, int level, int tx, int ty, float* zf, float* zc,
                                      float* zm, size_t count);

/* The height at point (u, v) of the root quad (u east, v north, both in [0, 1]) in the tiles of
 * `level` (-1: the deepest with residuals; deeper levels, which add no detail, are refused with
 * PYRAMID_ERROR_ARGUMENT): the bilinear interpolation, in double precision, of the four zf
 * samples around the point in the tile that holds it. */
PYRAMID_API pyramid_status pyramid_elevation_height(pyramid_elevation* producer, int level, double u, double v, double* height);

/* ---- Normal producer (0.2.2) ------------------------------------------------------------- */

/* The normals of an elevation producer's tiles (doc/shading.md): per vertex of a tile of n
 * intervals ((n+1)^2, no border, row 0 = south), four floats (nx, ny, ncx, ncy): the normal's
 * horizontal components in the tile's tangent frame, and the coarse normal's (the parent's
 * normals on its render mesh of the elevation producer's grid_size, for geomorphing). The
 * vertical component is sqrt(1 - nx^2 - ny^2). */
typedef struct pyramid_normal pyramid_normal;

typedef enum pyramid_deformation {
    PYRAMID_DEFORM_PLANE = 0, /* the plane z = 0; frame x east, y north */
    PYRAMID_DEFORM_SPHERE = 1 /* the root quad is the cube face [-R, R]^2 blown up onto a sphere of radius R;
                                 frame: the tile centre's tangent plane */
} pyramid_deformation;

/* Size-prefixed; `size` must be set (there is no default geometry). */
typedef struct pyramid_normal_options {
    size_t struct_size; /* sizeof(pyramid_normal_options) */
    int deformation;    /* a pyramid_deformation */
    double size;        /* plane: the root quad's side; sphere: the radius R; in height units, > 0 */
    size_t cache_tiles; /* produced tiles kept; 0 is taken as 1 */
} pyramid_normal_options;

/* The normal producer over `elevations`, whose producer (and cache) it shares: the elevation
 * handle may be closed before this one. */
PYRAMID_API pyramid_status pyramid_normal_open(pyramid_elevation* elevations, const pyramid_normal_options* options,
                                               pyramid_normal** producer);
PYRAMID_API void pyramid_normal_close(pyramid_normal* producer);
/* Vertices per side of the produced tiles (n + 1). */
PYRAMID_API int pyramid_normal_side(const pyramid_normal* producer);
/* Quadtree tile (level, tx, ty) into `normals`, `count` >= 4 side^2 floats: (nx, ny, ncx, ncy)
 * per vertex. Tiles outside levels 0..30 are PYRAMID_ERROR_NOT_FOUND. */
PYRAMID_API pyramid_status pyramid_normal_tile(pyramid_normal* producer, int level, int tx, int ty, float* normals,
                                               size_t count);

/* ---- Ortho producer ---------------------------------------------------------------------- */

typedef struct pyramid_ortho pyramid_ortho;

/* colour_residuals = 0: the file's tiles as they are; 1: the file holds colour residuals and
 * tiles are rebuilt by the colour upsample (any level, smooth beyond the file's deepest, and
 * where the file leaves a tile out as an empty byte range); other values are
 * PYRAMID_ERROR_ARGUMENT.
 * `path` may name a region set, as for pyramid_elevation_open. */
PYRAMID_API pyramid_status pyramid_ortho_open(const char* path, int colour_residuals, size_t cache_tiles, pyramid_ortho** producer);
/* The same over a main file and `region_count` nested region files (same tile size, channels
 * and flags). */
PYRAMID_API pyramid_status pyramid_ortho_open_regions(const char* path, const char* const* region_paths, size_t region_count,
                                          int colour_residuals, size_t cache_tiles, pyramid_ortho** producer);

/* (0.2.1) The ortho producer's options. Size-prefixed; a zeroed struct (with struct_size set)
 * gives the defaults. */
typedef struct pyramid_ortho_options {
    size_t struct_size;   /* sizeof(pyramid_ortho_options) */
    int colour_residuals; /* as pyramid_ortho_open's */
    size_t cache_tiles;   /* colour-residual tiles kept; 0 is taken as 1 */
} pyramid_ortho_options;

/* (0.2.1) The ortho producer over a main source and `region_count` region sources; `options`
 * may be NULL (the defaults). */
PYRAMID_API pyramid_status pyramid_ortho_open_sources(const pyramid_source* main_source,
                                                      const pyramid_source* const* regions, size_t region_count,
                                                      const pyramid_ortho_options* options, pyramid_ortho** producer);
PYRAMID_API void pyramid_ortho_close(pyramid_ortho* producer);
/* Pixels per side and channels of the produced tiles. */
PYRAMID_API pyramid_status pyramid_ortho_layout(const pyramid_ortho* producer, int* side, int* channels);
/* side^2 x channels bytes into `pixels` (`size` bytes). Without colour residuals a tile no file
 * holds is PYRAMID_ERROR_NOT_FOUND; with them every tile of levels 0..30 exists. */
PYRAMID_API pyramid_status pyramid_ortho_tile(pyramid_ortho* producer, int level, int tx, int ty, unsigned char* pixels,
                                  size_t size);

#ifdef __cplusplus
}
#endif

#endif /* LIBPYRAMID_PYRAMID_H */
