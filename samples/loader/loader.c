/*
 * loader: streams the elevation tiles of a residual (DEM) pyramid file through libpyramid's C
 * API, as a terrain renderer does when its camera stands over a point.
 *
 * Starting from the root tile, each tile is produced and, when it lies close enough to the
 * point of interest, split into its four children; splitting stops at a level limit. Parents
 * are produced before their children, which is the order the elevation producer's cache is
 * built for (doc/c-api.md, "Elevation producer"): each tile costs one residual decode and one
 * upsample. The summary gives the tiles produced per level, the range of heights they hold and
 * the height under the point.
 *
 * Usage: loader [options] FILE.dat   (loader -h lists the options)
 * Exit status: 0 on success, 1 when the library reports an error, 2 on a bad command line.
 *
 * Build it against an installed libpyramid with pkg-config (samples/loader/Makefile,
 * samples/README.md).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libpyramid/capi/pyramid.h"

/* What the command line asks for. */
typedef struct options {
    const char* path;
    double u, v;      /* the point of interest in the root quad: u east, v north, in [0, 1] */
    int max_level;    /* deepest level produced; -1: the deepest that holds residuals */
    double split;     /* a tile is split when the point is within split x its width of it */
    int all;          /* 1: split every tile down to max_level (split is ignored) */
    int tile_size;    /* elevation tiles' intervals; 0: the file's tile size */
    int cache_tiles;  /* tiles the producer keeps */
    int verbose;      /* 1: one line per tile */
} options;

/* What the walk has seen so far. */
typedef struct walk {
    pyramid_elevation* producer;
    const options* opts;
    float* zf;        /* one tile of side^2 elevations, reused for every tile */
    size_t count;
    int side;
    int max_level;
    long long tiles_per_level[31];
    long long tiles;
    float lo, hi;     /* heights over the tiles' quads */
} walk;

static void usage(FILE* out, const char* program) {
    fprintf(out,
            "usage: %s [options] FILE.dat\n"
            "Produces the elevation tiles a renderer standing over a point would request from\n"
            "the residual (DEM) pyramid FILE.dat, and prints what they hold.\n"
            "  -p U,V     point of interest in the root quad, u east and v north in [0, 1]\n"
            "             (default 0.5,0.5)\n"
            "  -l LEVEL   deepest level produced (default: the deepest with residuals)\n"
            "  -s FACTOR  split a tile when the point is within FACTOR tile widths of it\n"
            "             (default 1)\n"
            "  -a         produce every tile of every level down to LEVEL\n"
            "  -n SIZE    intervals per elevation tile: the file's tile size divided by a power\n"
            "             of two (default: the file's tile size)\n"
            "  -c TILES   tiles the producer caches (default 64)\n"
            "  -v         print one line per tile\n"
            "  -h         print this help\n",
            program);
}

/* Parses an integer that must fill the whole argument and lie in [lo, hi]. */
static int parse_int(const char* text, int lo, int hi, int* value) {
    char* end = NULL;
    long parsed;
    errno = 0;
    parsed = strtol(text, &end, 10);
    if (errno != 0 || end == text || *end != '\0' || parsed < lo || parsed > hi) {
        return 0;
    }
    *value = (int)parsed;
    return 1;
}

/* Parses a number in [lo, hi] that ends at `stop` (a character, or '\0' for the argument's
 * end); *rest is set past it. */
static int parse_double(const char* text, char stop, double lo, double hi, double* value, const char** rest) {
    char* end = NULL;
    double parsed;
    errno = 0;
    parsed = strtod(text, &end);
    if (errno != 0 || end == text || *end != stop || !(parsed >= lo && parsed <= hi)) {
        return 0;
    }
    *value = parsed;
    *rest = *end != '\0' ? end + 1 : end;
    return 1;
}

/* Fills `opts` from the command line; returns 0 (after a message) when it is not valid, and
 * exits with status 0 after -h. */
static int parse_options(int argc, char** argv, options* opts) {
    int i;
    opts->path = NULL;
    opts->u = 0.5;
    opts->v = 0.5;
    opts->max_level = -1;
    opts->split = 1.0;
    opts->all = 0;
    opts->tile_size = 0;
    opts->cache_tiles = 64;
    opts->verbose = 0;
    for (i = 1; i < argc; ++i) {
        const char* arg = argv[i];
        const char* value = i + 1 < argc ? argv[i + 1] : NULL;
        const char* rest = NULL;
        int ok = 1;
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            usage(stdout, argv[0]);
            exit(0);
        } else if (strcmp(arg, "-a") == 0) {
            opts->all = 1;
            continue;
        } else if (strcmp(arg, "-v") == 0) {
            opts->verbose = 1;
            continue;
        } else if (arg[0] == '-' && arg[1] != '\0' && arg[2] == '\0' && strchr("plsnc", arg[1]) != NULL) {
            if (value == NULL) {
                fprintf(stderr, "loader: option %s needs a value\n", arg);
                return 0;
            }
            switch (arg[1]) {
            case 'p':
                ok = parse_double(value, ',', 0.0, 1.0, &opts->u, &rest) &&
                     parse_double(rest, '\0', 0.0, 1.0, &opts->v, &rest);
                break;
            case 'l':
                ok = parse_int(value, 0, 30, &opts->max_level);
                break;
            case 's':
                ok = parse_double(value, '\0', 0.0, 1e6, &opts->split, &rest);
                break;
            case 'n':
                ok = parse_int(value, 0, 1 << 20, &opts->tile_size);
                break;
            default: /* 'c' */
                ok = parse_int(value, 1, 1 << 20, &opts->cache_tiles);
                break;
            }
            if (!ok) {
                fprintf(stderr, "loader: invalid value for %s: '%s'\n", arg, value);
                return 0;
            }
            ++i;
        } else if (arg[0] == '-' && arg[1] != '\0') {
            fprintf(stderr, "loader: unknown option '%s'\n", arg);
            return 0;
        } else if (opts->path == NULL) {
            opts->path = arg;
        } else {
            fprintf(stderr, "loader: one file only ('%s' and '%s')\n", opts->path, arg);
            return 0;
        }
    }
    if (opts->path == NULL) {
        fprintf(stderr, "loader: no file given\n");
        return 0;
    }
    return 1;
}

/* Reports a failed library call; returns the exit status for it. */
static int fail(const char* call, pyramid_status status) {
    fprintf(stderr, "loader: %s: %s error: %s\n", call, pyramid_status_name(status), pyramid_last_error());
    return 1;
}

/* Distance from the point of interest to tile (level, tx, ty) in root-quad units, the larger of
 * the east-west and north-south gaps: 0 inside. */
static double distance_to_tile(const options* opts, int level, int tx, int ty) {
    const double width = 1.0 / (double)(1L << level);
    const double x0 = tx * width, y0 = ty * width;
    const double dx = opts->u < x0 ? x0 - opts->u : (opts->u > x0 + width ? opts->u - x0 - width : 0.0);
    const double dy = opts->v < y0 ? y0 - opts->v : (opts->v > y0 + width ? opts->v - y0 - width : 0.0);
    return dx > dy ? dx : dy;
}

/* Produces tile (level, tx, ty), then its children when it is split. Returns 0, or the exit
 * status of a failure. */
static int visit(walk* w, int level, int tx, int ty) {
    const int side = w->side;
    float lo, hi;
    int i, j;
    const pyramid_status s = pyramid_elevation_tile(w->producer, level, tx, ty, w->zf, NULL, NULL, w->count);
    if (s != PYRAMID_OK) {
        return fail("pyramid_elevation_tile", s);
    }
    /* Sample (i, j) is zf[i + j * side]; the tile's quad spans samples 2 .. side - 3 (the
     * others are borders shared with the neighbours). */
    lo = hi = w->zf[2 + 2 * side];
    for (j = 2; j <= side - 3; ++j) {
        for (i = 2; i <= side - 3; ++i) {
            const float z = w->zf[i + j * side];
            lo = z < lo ? z : lo;
            hi = z > hi ? z : hi;
        }
    }
    if (w->tiles == 0 || lo < w->lo) {
        w->lo = lo;
    }
    if (w->tiles == 0 || hi > w->hi) {
        w->hi = hi;
    }
    ++w->tiles;
    ++w->tiles_per_level[level];
    if (w->opts->verbose) {
        printf("  tile (%d,%d,%d): heights %.2f .. %.2f\n", level, tx, ty, (double)lo, (double)hi);
    }

    if (level < w->max_level &&
        (w->opts->all || distance_to_tile(w->opts, level, tx, ty) <= w->opts->split / (double)(1L << level))) {
        int child, status;
        for (child = 0; child < 4; ++child) {
            status = visit(w, level + 1, 2 * tx + (child & 1), 2 * ty + (child >> 1));
            if (status != 0) {
                return status;
            }
        }
    }
    return 0;
}

int main(int argc, char** argv) {
    options opts;
    pyramid_file* file = NULL;
    pyramid_info info;
    pyramid_status s;
    walk w;
    int status, level, residual_levels, divisions;
    double height;

    if (!parse_options(argc, argv, &opts)) {
        usage(stderr, argv[0]);
        return 2;
    }

    /* The file's header: a loader checks what it was given before it streams from it. */
    s = pyramid_open(opts.path, &file);
    if (s != PYRAMID_OK) {
        return fail("pyramid_open", s);
    }
    s = pyramid_get_info(file, &info);
    pyramid_close(file);
    if (s != PYRAMID_OK) {
        return fail("pyramid_get_info", s);
    }
    if (info.kind != PYRAMID_KIND_RESIDUAL) {
        fprintf(stderr, "loader: %s: an ortho pyramid, not a residual (DEM) one\n", opts.path);
        return 1;
    }
    printf("%s: residual pyramid (libpyramid %s), tile size %d, levels %d..%d, scale %g, %lld tiles\n", opts.path,
           pyramid_version_string(), info.tile_size, info.min_level, info.max_level, (double)info.scale,
           info.tile_count);

    memset(&w, 0, sizeof w);
    w.opts = &opts;
    s = pyramid_elevation_open(opts.path, opts.tile_size, 0, (size_t)opts.cache_tiles, &w.producer);
    if (s != PYRAMID_OK) {
        return fail("pyramid_elevation_open", s);
    }
    w.side = pyramid_elevation_side(w.producer);
    w.count = (size_t)w.side * (size_t)w.side;
    /* The producer's level 0 is the root quad at n = side - 5 intervals; its levels hold the
     * file's residuals down to max_level - (min_level - k), where n = tile_size / 2^k. */
    divisions = 0;
    while (divisions < 30 && (w.side - 5) << divisions < info.tile_size) {
        ++divisions;
    }
    residual_levels = info.max_level - (info.min_level - divisions);
    if (residual_levels < 0) {
        residual_levels = 0;
    }
    w.max_level = opts.max_level >= 0 ? opts.max_level : residual_levels;
    w.zf = malloc(w.count * sizeof *w.zf);
    if (w.zf == NULL) {
        pyramid_elevation_close(w.producer);
        fprintf(stderr, "loader: out of memory\n");
        return 1;
    }
    printf("elevation tiles: %d intervals (%d x %d samples), residuals down to level %d\n", w.side - 5, w.side,
           w.side, residual_levels);
    if (opts.all) {
        printf("walk: every tile down to level %d\n", w.max_level);
    } else {
        printf("walk: around (%g, %g), split within %g tile width(s), down to level %d\n", opts.u, opts.v, opts.split,
               w.max_level);
    }

    status = visit(&w, 0, 0, 0);
    if (status == 0) {
        for (level = 0; level <= w.max_level; ++level) {
            printf("level %d: %lld tile%s\n", level, w.tiles_per_level[level], w.tiles_per_level[level] == 1 ? "" : "s");
        }
        printf("tiles produced: %lld\n", w.tiles);
        printf("heights: %.2f .. %.2f\n", (double)w.lo, (double)w.hi);
        /* The height under the point, from the tiles of the deepest level walked (heights are
         * answered down to the deepest level with residuals: below it, tiles are smooth). */
        level = w.max_level < residual_levels ? w.max_level : residual_levels;
        s = pyramid_elevation_height(w.producer, level, opts.u, opts.v, &height);
        if (s != PYRAMID_OK) {
            status = fail("pyramid_elevation_height", s);
        } else {
            printf("height at (%g, %g): %.3f (level %d)\n", opts.u, opts.v, height, level);
        }
    }
    free(w.zf);
    pyramid_elevation_close(w.producer);
    return status;
}
