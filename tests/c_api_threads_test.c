/* The C API's handles shared by 16 threads: pyramid_read_tile on two files, and the elevation,
 * ortho and colour-residual producers, each with a cache of one tile (so that the threads keep
 * evicting each other's tiles and rebuilding parents). Every result must equal the one a serial
 * run gives. CI runs this test built with ThreadSanitizer as well (.ci/run), where any report
 * fails it. argv[1] is the tests/data directory. */
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libpyramid/capi/pyramid.h"

#define THREADS 16
/* Each work item is done by THREADS / SHARE threads (and once by the serial run). */
#define SHARE 4

enum work_kind { READ_DEM, READ_RGB, ELEVATION, ORTHO, COLOUR };

typedef struct work_item {
    enum work_kind kind;
    int level, tx, ty;
    uint64_t hash; /* of the serial run's result */
} work_item;

typedef struct shared_handles {
    pyramid_file* dem;
    pyramid_file* rgb;
    pyramid_elevation* elevation;
    pyramid_ortho* ortho;
    pyramid_ortho* colour;
    work_item* items;
    size_t count;
    size_t buffer_bytes;
} shared_handles;

typedef struct thread_state {
    const shared_handles* shared;
    int index;
    long done;
    long mismatches;
    long failures;
    char first_error[512];
} thread_state;

static uint64_t fnv1a(const void* data, size_t size) {
    const unsigned char* p = (const unsigned char*)data;
    uint64_t h = 1469598103934665603ull;
    size_t k;
    for (k = 0; k < size; ++k) {
        h = (h ^ p[k]) * 1099511628211ull;
    }
    return h;
}

/* Runs one item into `buffer`; returns PYRAMID_OK and the hash of what it produced. */
static pyramid_status run_item(const shared_handles* s, const work_item* w, unsigned char* buffer, uint64_t* hash) {
    pyramid_status status = PYRAMID_ERROR_INTERNAL;
    size_t written = 0;
    int side = 0, channels = 0;
    switch (w->kind) {
    case READ_DEM:
    case READ_RGB:
        status = pyramid_read_tile(w->kind == READ_DEM ? s->dem : s->rgb, w->level, w->tx, w->ty, buffer,
                                   s->buffer_bytes, &written);
        break;
    case ELEVATION: {
        const size_t n = (size_t)pyramid_elevation_side(s->elevation) * (size_t)pyramid_elevation_side(s->elevation);
        float* zf = (float*)buffer;
        status = pyramid_elevation_tile(s->elevation, w->level, w->tx, w->ty, zf, zf + n, zf + 2 * n, n);
        written = 3 * n * sizeof(float);
        break;
    }
    case ORTHO:
    case COLOUR: {
        pyramid_ortho* producer = w->kind == ORTHO ? s->ortho : s->colour;
        status = pyramid_ortho_layout(producer, &side, &channels);
        if (status == PYRAMID_OK) {
            written = (size_t)side * (size_t)side * (size_t)channels;
            status = pyramid_ortho_tile(producer, w->level, w->tx, w->ty, buffer, written);
        }
        break;
    }
    }
    *hash = status == PYRAMID_OK ? fnv1a(buffer, written) : 0;
    return status;
}

static void* worker(void* arg) {
    thread_state* t = (thread_state*)arg;
    const shared_handles* s = t->shared;
    unsigned char* buffer = (unsigned char*)malloc(s->buffer_bytes);
    size_t k;
    if (!buffer) {
        t->failures = 1;
        return NULL;
    }
    /* Every thread walks the list from its own place, so that different threads ask for the
     * same tiles and for different tiles of one producer at once. */
    for (k = 0; k < s->count; ++k) {
        const size_t i = (k + (size_t)t->index * s->count / THREADS) % s->count;
        const work_item* w = &s->items[i];
        uint64_t hash = 0;
        if ((i + (size_t)t->index) % SHARE != 0) {
            continue;
        }
        if (run_item(s, w, buffer, &hash) != PYRAMID_OK) {
            if (t->failures++ == 0) {
                snprintf(t->first_error, sizeof t->first_error, "%s", pyramid_last_error());
            }
        } else if (hash != w->hash) {
            ++t->mismatches;
        }
        ++t->done;
    }
    free(buffer);
    return NULL;
}

/* Appends the side x side tiles of `level`. */
static size_t add_tiles(work_item* items, size_t count, enum work_kind kind, int level, int side) {
    int tx, ty;
    for (ty = 0; ty < side; ++ty) {
        for (tx = 0; tx < side; ++tx) {
            items[count].kind = kind;
            items[count].level = level;
            items[count].tx = tx;
            items[count].ty = ty;
            items[count].hash = 0;
            ++count;
        }
    }
    return count;
}

/* Appends every tile of levels first..last of a full quadtree. */
static size_t add_levels(work_item* items, size_t count, enum work_kind kind, int first, int last) {
    int level;
    for (level = first; level <= last; ++level) {
        count = add_tiles(items, count, kind, level, 1 << level);
    }
    return count;
}

int main(int argc, char** argv) {
    char dem_path[4096], rgb_path[4096];
    shared_handles s;
    thread_state states[THREADS];
    pthread_t threads[THREADS];
    unsigned char* buffer;
    size_t k, distinct = 0;
    long done = 0, mismatches = 0, failures = 0;
    int t;
    if (argc < 2) {
        fprintf(stderr, "usage: %s TESTS_DATA_DIR\n", argv[0]);
        return 2;
    }
    snprintf(dem_path, sizeof dem_path, "%s/proland/DEM.dat", argv[1]);
    snprintf(rgb_path, sizeof rgb_path, "%s/proland/RGB.dat", argv[1]);
    memset(&s, 0, sizeof s);
    if (pyramid_open(dem_path, &s.dem) != PYRAMID_OK || pyramid_open(rgb_path, &s.rgb) != PYRAMID_OK ||
        pyramid_elevation_open(dem_path, 24, 0, 1, &s.elevation) != PYRAMID_OK ||
        pyramid_ortho_open(rgb_path, 0, 1, &s.ortho) != PYRAMID_OK ||
        /* RGB.dat's tiles read as colour residuals: tiles rebuilt from their parents, below the
         * file's levels too, through a cache of one tile. */
        pyramid_ortho_open(rgb_path, 1, 1, &s.colour) != PYRAMID_OK) {
        fprintf(stderr, "cannot open the test files: %s\n", pyramid_last_error());
        return 1;
    }
    /* DEM.dat: levels 0..5, one tile per level below its minLevel 3, then 4 and 16 tiles. */
    s.items = (work_item*)calloc(1024, sizeof(work_item));
    if (!s.items) {
        return 1;
    }
    for (t = 0; t <= 3; ++t) {
        s.count = add_tiles(s.items, s.count, READ_DEM, t, 1);
    }
    s.count = add_tiles(s.items, s.count, READ_DEM, 4, 2);
    s.count = add_tiles(s.items, s.count, READ_DEM, 5, 4);
    s.count = add_levels(s.items, s.count, READ_RGB, 0, 1);
    s.count = add_levels(s.items, s.count, ELEVATION, 0, 3);
    s.count = add_levels(s.items, s.count, ORTHO, 0, 1);
    s.count = add_levels(s.items, s.count, COLOUR, 0, 2);
    s.buffer_bytes = 197 * 197 * 2;
    if (s.buffer_bytes < 196 * 196 * 4) {
        s.buffer_bytes = 196 * 196 * 4;
    }
    buffer = (unsigned char*)malloc(s.buffer_bytes);
    if (!buffer) {
        return 1;
    }

    /* The serial run gives every item's expected result. */
    for (k = 0; k < s.count; ++k) {
        if (run_item(&s, &s.items[k], buffer, &s.items[k].hash) != PYRAMID_OK) {
            fprintf(stderr, "serial run: item %lu (kind %d, tile %d %d %d): %s\n", (unsigned long)k,
                    (int)s.items[k].kind, s.items[k].level, s.items[k].tx, s.items[k].ty, pyramid_last_error());
            return 1;
        }
    }
    /* The items are different tiles: their results differ (the test would see nothing if every
     * item gave the same bytes). */
    for (k = 1; k < s.count; ++k) {
        distinct += s.items[k].hash != s.items[k - 1].hash;
    }
    if (distinct < s.count / 2) {
        fprintf(stderr, "only %lu of %lu results differ from the previous one\n", (unsigned long)distinct,
                (unsigned long)s.count);
        return 1;
    }

    for (t = 0; t < THREADS; ++t) {
        memset(&states[t], 0, sizeof states[t]);
        states[t].shared = &s;
        states[t].index = t;
        if (pthread_create(&threads[t], NULL, worker, &states[t]) != 0) {
            fprintf(stderr, "cannot start thread %d\n", t);
            return 1;
        }
    }
    for (t = 0; t < THREADS; ++t) {
        pthread_join(threads[t], NULL);
        done += states[t].done;
        mismatches += states[t].mismatches;
        failures += states[t].failures;
        if (states[t].failures) {
            fprintf(stderr, "thread %d: %ld failures, the first: %s\n", t, states[t].failures, states[t].first_error);
        }
    }
    printf("%lu items, %ld runs on %d threads: %ld differ from the serial run, %ld failed\n", (unsigned long)s.count,
           done, THREADS, mismatches, failures);

    free(buffer);
    free(s.items);
    pyramid_ortho_close(s.colour);
    pyramid_ortho_close(s.ortho);
    pyramid_elevation_close(s.elevation);
    pyramid_close(s.rgb);
    pyramid_close(s.dem);
    return done == (long)s.count * (THREADS / SHARE) && mismatches == 0 && failures == 0 ? 0 : 1;
}
