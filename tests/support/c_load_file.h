/* A whole file read into memory, for the C tests (strict C99, header-only). */
#ifndef PYRAMID_TESTS_SUPPORT_C_LOAD_FILE_H
#define PYRAMID_TESTS_SUPPORT_C_LOAD_FILE_H

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

/* A whole file in memory; NULL (and *size 0) when it cannot be read. */
static inline unsigned char* load_file(const char* path, size_t* size) {
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

#endif
