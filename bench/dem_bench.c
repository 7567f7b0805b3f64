/* bench/dem_bench.sh's residual statistics: the order-0 entropy of a residual (DEM) pyramid's
 * stored residuals, against the bytes Deflate made of them. A benchmark tool over the C API
 * (libpyramid/capi/pyramid.h), never a test.
 *
 *   dem_bench FILE.dat
 *
 * prints one line: residual_samples entropy_bits_per_residual tile_bytes distinct_tiles.
 * Every distinct stored tile counts once (tiles sharing bytes are stored once), with its
 * (n + 5)^2 residuals, borders included: what the file codes. The entropy is that of the int16
 * values pooled over the whole file, -sum p log2 p: what an order-0 coder with one table for
 * the file would reach, table aside. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "libpyramid/capi/pyramid.h"

static int seen(const uint64_t* offsets, long long count, uint64_t offset) {
    for (long long i = 0; i < count; ++i) {
        if (offsets[i] == offset) {
            return 1;
        }
    }
    return 0;
}

int main(int argc, char** argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: dem_bench FILE.dat\n");
        return 2;
    }
    pyramid_file* file = NULL;
    if (pyramid_open(argv[1], &file) != PYRAMID_OK) {
        fprintf(stderr, "dem_bench: %s: %s\n", argv[1], pyramid_last_error());
        return 1;
    }
    pyramid_info info;
    pyramid_get_info(file, &info);
    if (info.kind != PYRAMID_KIND_RESIDUAL) {
        fprintf(stderr, "dem_bench: %s: not a residual file\n", argv[1]);
        return 1;
    }
    static double histogram[65536];
    uint64_t* offsets = malloc(sizeof(uint64_t) * (size_t)info.tile_count);
    long long distinct = 0;
    double samples = 0.0, tileBytes = 0.0;
    int16_t* tile = NULL;
    size_t capacity = 0;
    for (int level = 0; level <= info.max_level; ++level) {
        const int side = level < info.min_level ? 1 : 1 << (level - info.min_level);
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                pyramid_tile_info stat;
                stat.struct_size = sizeof stat;
                if (pyramid_tile_stat(file, level, tx, ty, &stat) != PYRAMID_OK || !stat.exists ||
                    seen(offsets, distinct, stat.offset)) {
                    continue;
                }
                offsets[distinct++] = stat.offset;
                if (stat.decoded_bytes > capacity) {
                    capacity = stat.decoded_bytes;
                    tile = realloc(tile, capacity);
                }
                size_t written = 0;
                if (pyramid_read_tile(file, level, tx, ty, tile, capacity, &written) != PYRAMID_OK) {
                    fprintf(stderr, "dem_bench: %s: tile (%d,%d,%d): %s\n", argv[1], level, tx, ty, pyramid_last_error());
                    return 1;
                }
                for (size_t i = 0; i < written / 2; ++i) {
                    histogram[(uint16_t)tile[i]] += 1.0;
                }
                samples += (double)(written / 2);
                tileBytes += (double)stat.stored_bytes;
            }
        }
    }
    double entropy = 0.0;
    for (int v = 0; v < 65536; ++v) {
        if (histogram[v] > 0.0) {
            const double p = histogram[v] / samples;
            entropy -= p * log2(p);
        }
    }
    printf("%.0f %.6f %.0f %lld\n", samples, entropy, tileBytes, distinct);
    free(tile);
    free(offsets);
    pyramid_close(file);
    return 0;
}
