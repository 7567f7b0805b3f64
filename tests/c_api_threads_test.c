/* The C API's handles shared by 16 threads: pyramid_read_tile on two files, and the elevation,
 * ortho and colour-residual producers, each with a cache of one tile (so that the threads keep
 * evicting each other's tiles and rebuilding parents). Every handle is opened three times: by
 * path, from memory and through I/O callbacks (called from all the threads at once). Every
 * result must equal the one a serial run gives, and the three opens must give the same results.
 * CI runs this test built with ThreadSanitizer as well (.ci/run), where any report fails it.
 * argv[1] is the tests/data directory. */
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libpyramid/capi/pyramid.h"
#include "tests/support/c_load_file.h"

#define THREADS 16
/* Each work item is done by THREADS / SHARE threads (and once by the serial run). */
#define SHARE 4

enum work_kind { READ_DEM, READ_RGB, ELEVATION, ORTHO, COLOUR };
/* How a handle was opened. */
enum { BY_PATH, FROM_MEMORY, BY_CALLBACKS, SOURCES };

typedef struct work_item {
    enum work_kind kind;
    int source;
    int level, tx, ty;
    uint64_t hash; /* of the serial run's result */
} work_item;

/* I/O callbacks over a file held in memory; the count of reads is shared by the threads. */
typedef struct memory_io {
    const unsigned char* data;
    size_t size;
    pthread_mutex_t lock;
    long reads;
    int released;
} memory_io;

static int memory_read(void* user, uint64_t offset, void* buffer, size_t size, size_t* bytes_read) {
    memory_io* io = (memory_io*)user;
    if (offset > io->size || size > io->size - offset) {
        return -1;
    }
    memcpy(buffer, io->data + offset, size);
    *bytes_read = size;
    pthread_mutex_lock(&io->lock);
    ++io->reads;
    pthread_mutex_unlock(&io->lock);
    return 0;
}

static void memory_release(void* user) {
    memory_io* io = (memory_io*)user;
    pthread_mutex_lock(&io->lock);
    ++io->released;
    pthread_mutex_unlock(&io->lock);
}

typedef struct shared_handles {
    pyramid_file* dem[SOURCES];
    pyramid_file* rgb[SOURCES];
    pyramid_elevation* elevation[SOURCES];
    pyramid_ortho* ortho[SOURCES];
    pyramid_ortho* colour[SOURCES];
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
        status = pyramid_read_tile(w->kind == READ_DEM ? s->dem[w->source] : s->rgb[w->source], w->level, w->tx,
                                   w->ty, buffer, s->buffer_bytes, &written);
        break;
    case ELEVATION: {
        pyramid_elevation* producer = s->elevation[w->source];
        const size_t n = (size_t)pyramid_elevation_side(producer) * (size_t)pyramid_elevation_side(producer);
        float* zf = (float*)buffer;
        status = pyramid_elevation_tile(producer, w->level, w->tx, w->ty, zf, zf + n, zf + 2 * n, n);
        written = 3 * n * sizeof(float);
        break;
    }
    case ORTHO:
    case COLOUR: {
        pyramid_ortho* producer = w->kind == ORTHO ? s->ortho[w->source] : s->colour[w->source];
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

/* The source of the items appended next. */
static int adding_source = BY_PATH;

/* Appends the side x side tiles of `level`. */
static size_t add_tiles(work_item* items, size_t count, enum work_kind kind, int level, int side) {
    int tx, ty;
    for (ty = 0; ty < side; ++ty) {
        for (tx = 0; tx < side; ++tx) {
            items[count].kind = kind;
            items[count].source = adding_source;
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

/* The descriptor of `path` opened as `how`; `io` holds the callbacks' state for BY_CALLBACKS
 * (one per handle: each handle releases its own). */
static pyramid_source source_of(int how, const char* path, const unsigned char* data, size_t size, memory_io* io) {
    pyramid_source s;
    memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    if (how == BY_PATH) {
        s.kind = PYRAMID_SOURCE_PATH;
        s.path = path;
    } else if (how == FROM_MEMORY) {
        s.kind = PYRAMID_SOURCE_MEMORY;
        s.data = data;
        s.size = size;
    } else {
        io->data = data;
        io->size = size;
        io->reads = 0;
        io->released = 0;
        pthread_mutex_init(&io->lock, NULL);
        s.kind = PYRAMID_SOURCE_IO;
        s.name = path;
        s.io.read = memory_read;
        s.io.release = memory_release;
        s.io.user = io;
        s.io.size = size;
    }
    return s;
}

/* The items of one source: every tile the test asks for. */
static size_t add_items(work_item* items, size_t count, int source) {
    int t;
    adding_source = source;
    /* DEM.dat: levels 0..5, one tile per level below its minLevel 3, then 4 and 16 tiles. */
    for (t = 0; t <= 3; ++t) {
        count = add_tiles(items, count, READ_DEM, t, 1);
    }
    count = add_tiles(items, count, READ_DEM, 4, 2);
    count = add_tiles(items, count, READ_DEM, 5, 4);
    count = add_levels(items, count, READ_RGB, 0, 1);
    count = add_levels(items, count, ELEVATION, 0, 3);
    count = add_levels(items, count, ORTHO, 0, 1);
    count = add_levels(items, count, COLOUR, 0, 2);
    return count;
}

int main(int argc, char** argv) {
    char dem_path[4096], rgb_path[4096];
    shared_handles s;
    thread_state states[THREADS];
    pthread_t threads[THREADS];
    unsigned char* buffer;
    unsigned char* dem_data;
    unsigned char* rgb_data;
    size_t dem_size = 0, rgb_size = 0, per_source;
    /* One io state per handle opened by callbacks: dem, rgb, elevation, ortho, colour. */
    memory_io io[5];
    size_t k, distinct = 0, cross = 0;
    long done = 0, mismatches = 0, failures = 0, io_reads = 0;
    int t, how, released = 1;
    if (argc < 2) {
        fprintf(stderr, "usage: %s TESTS_DATA_DIR\n", argv[0]);
        return 2;
    }
    snprintf(dem_path, sizeof dem_path, "%s/proland/DEM.dat", argv[1]);
    snprintf(rgb_path, sizeof rgb_path, "%s/proland/RGB.dat", argv[1]);
    dem_data = load_file(dem_path, &dem_size);
    rgb_data = load_file(rgb_path, &rgb_size);
    if (!dem_data || !rgb_data) {
        fprintf(stderr, "cannot read the test files\n");
        return 1;
    }
    memset(&s, 0, sizeof s);
    memset(io, 0, sizeof io);
    for (how = 0; how < SOURCES; ++how) {
        const pyramid_source dem = source_of(how, dem_path, dem_data, dem_size, &io[0]);
        const pyramid_source rgb = source_of(how, rgb_path, rgb_data, rgb_size, &io[1]);
        const pyramid_source dem2 = source_of(how, dem_path, dem_data, dem_size, &io[2]);
        const pyramid_source rgb2 = source_of(how, rgb_path, rgb_data, rgb_size, &io[3]);
        const pyramid_source rgb3 = source_of(how, rgb_path, rgb_data, rgb_size, &io[4]);
        pyramid_elevation_options eo;
        pyramid_ortho_options oo;
        memset(&eo, 0, sizeof eo);
        eo.struct_size = sizeof eo;
        eo.tile_size = 24;
        eo.cache_tiles = 1;
        memset(&oo, 0, sizeof oo);
        oo.struct_size = sizeof oo;
        oo.cache_tiles = 1;
        if (pyramid_open_source(&dem, &s.dem[how]) != PYRAMID_OK || pyramid_open_source(&rgb, &s.rgb[how]) != PYRAMID_OK ||
            pyramid_elevation_open_sources(&dem2, NULL, 0, &eo, &s.elevation[how]) != PYRAMID_OK ||
            pyramid_ortho_open_sources(&rgb2, NULL, 0, &oo, &s.ortho[how]) != PYRAMID_OK) {
            fprintf(stderr, "cannot open the test files: %s\n", pyramid_last_error());
            return 1;
        }
        /* RGB.dat's tiles read as colour residuals: tiles rebuilt from their parents, below the
         * file's levels too, through a cache of one tile. */
        oo.colour_residuals = 1;
        if (pyramid_ortho_open_sources(&rgb3, NULL, 0, &oo, &s.colour[how]) != PYRAMID_OK) {
            fprintf(stderr, "cannot open the test files: %s\n", pyramid_last_error());
            return 1;
        }
    }
    s.items = (work_item*)calloc(1024, sizeof(work_item));
    if (!s.items) {
        return 1;
    }
    for (how = 0; how < SOURCES; ++how) {
        s.count = add_items(s.items, s.count, how);
    }
    per_source = s.count / SOURCES;
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
            fprintf(stderr, "serial run: item %lu (kind %d, source %d, tile %d %d %d): %s\n", (unsigned long)k,
                    (int)s.items[k].kind, s.items[k].source, s.items[k].level, s.items[k].tx, s.items[k].ty,
                    pyramid_last_error());
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
    /* Memory and callback opens give what the path open gives. */
    for (k = per_source; k < s.count; ++k) {
        cross += s.items[k].hash != s.items[k % per_source].hash;
    }
    if (cross != 0) {
        fprintf(stderr, "%lu memory or callback results differ from the path open's\n", (unsigned long)cross);
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
    for (how = 0; how < SOURCES; ++how) {
        pyramid_ortho_close(s.colour[how]);
        pyramid_ortho_close(s.ortho[how]);
        pyramid_elevation_close(s.elevation[how]);
        pyramid_close(s.rgb[how]);
        pyramid_close(s.dem[how]);
    }
    for (k = 0; k < 5; ++k) {
        io_reads += io[k].reads;
        released &= io[k].released == 1;
        pthread_mutex_destroy(&io[k].lock);
    }
    if (io_reads == 0 || !released) {
        fprintf(stderr, "callbacks: %ld reads; each set released once: %s\n", io_reads, released ? "yes" : "no");
        return 1;
    }
    free(dem_data);
    free(rgb_data);
    return done == (long)s.count * (THREADS / SHARE) && mismatches == 0 && failures == 0 ? 0 : 1;
}
