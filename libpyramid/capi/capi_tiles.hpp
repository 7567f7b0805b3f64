// What the C API's tile calls share, a file's and the producers' alike: a tile copied out into
// the caller's buffer (or only its size told), a buffer too small, a tile outside the pyramid.
#pragma once
#include <cstddef>
#include <cstring>
#include <string>

#include "formats/error.hpp"
#include "libpyramid/capi/capi_status.hpp"
#include "libpyramid/capi/pyramid.h"

namespace pyramid::capi {

inline pyramid_status tooSmall(size_t size, size_t bytes) {
    return failWith(PYRAMID_ERROR_ARGUMENT,
                    "buffer of " + std::to_string(size) + " bytes, " + std::to_string(bytes) + " needed");
}

inline pyramid_status copyOut(const void* data, size_t bytes, void* buffer, size_t size, size_t* written) {
    if (written) {
        *written = bytes;
    }
    if (!buffer) {
        return PYRAMID_OK;
    }
    if (size < bytes) {
        return tooSmall(size, bytes);
    }
    std::memcpy(buffer, data, bytes);
    return PYRAMID_OK;
}

inline pyramid_status outside(int level, int tx, int ty) {
    return failWith(PYRAMID_ERROR_NOT_FOUND, "no tile " + pyramid::tileCoordinates(level, tx, ty) + " in this pyramid");
}

} // namespace pyramid::capi
