/* A loader built against an installed copy (tests/install/install_test.sh): the C API only,
 * linked with the runtime library alone. Reads the original tools' DEM.dat and checks a tile. */
#include <stdio.h>
#include <stdlib.h>

#include "libpyramid/capi/pyramid.h"

int main(int argc, char** argv) {
    char path[4096];
    pyramid_file* file = NULL;
    pyramid_info info;
    short tile[29 * 29];
    if (argc != 2) {
        fprintf(stderr, "usage: consumer DATA_DIR\n");
        return 2;
    }
    snprintf(path, sizeof path, "%s/proland/DEM.dat", argv[1]);
    if (pyramid_version_number() != PYRAMID_VERSION_NUMBER || pyramid_open(path, &file) != PYRAMID_OK ||
        pyramid_get_info(file, &info) != PYRAMID_OK ||
        pyramid_read_tile(file, 0, 0, 0, tile, sizeof tile, NULL) != PYRAMID_OK) {
        fprintf(stderr, "consumer: %s\n", pyramid_last_error());
        return 1;
    }
    if (info.tile_size != 192 || info.tile_count != 24 || tile[0] != 1400 || tile[14 + 14 * 29] != 1470) {
        fprintf(stderr, "consumer: unexpected values\n");
        return 1;
    }
    pyramid_close(file);
    printf("libpyramid %s: tile (0,0,0) centre %d\n", pyramid_version_string(), tile[14 + 14 * 29]);
    return 0;
}
