// The C API's last error and statuses (capi_status.hpp), and the version it reports.
#include <cstring>
#include <string>

#include "libpyramid/capi/capi_status.hpp"
#include "libpyramid/capi/pyramid.h"

namespace {

thread_local std::string lastError;

} // namespace

extern "C" {

int pyramid_version_number(void) { return PYRAMID_VERSION_NUMBER; }

const char* pyramid_version_string(void) {
    static const std::string text = std::to_string(PYRAMID_VERSION_MAJOR) + "." + std::to_string(PYRAMID_VERSION_MINOR) +
                                    "." + std::to_string(PYRAMID_VERSION_PATCH);
    return text.c_str();
}

const char* pyramid_last_error(void) { return lastError.c_str(); }

const char* pyramid_status_name(pyramid_status status) {
    int value = 0; // any int a C caller passes, read as one (see SourceSet::make)
    static_assert(sizeof value == sizeof status);
    std::memcpy(&value, &status, sizeof value);
    switch (value) {
    case PYRAMID_OK:
        return "ok";
    case PYRAMID_ERROR_ARGUMENT:
        return "argument";
    case PYRAMID_ERROR_FILE:
        return "file";
    case PYRAMID_ERROR_MEMORY:
        return "memory";
    case PYRAMID_ERROR_INTERNAL:
        return "internal";
    case PYRAMID_ERROR_NOT_FOUND:
        return "not_found";
    case PYRAMID_ERROR_CANCELLED:
        return "cancelled";
    }
    return "unknown";
}

} // extern "C"

namespace pyramid::capi {

pyramid_status failWith(pyramid_status status, const std::string& message) {
    lastError = message;
    return status;
}

} // namespace pyramid::capi

