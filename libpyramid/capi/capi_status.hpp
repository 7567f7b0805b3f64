// The C API's statuses and its thread-local last error (pyramid_last_error, capi_status.cpp),
// shared by its two halves: the runtime's functions (pyramid_file.cpp, pyramid_elevation.cpp,
// pyramid_ortho.cpp) and the encoding ones (pyramid_encode.cpp).
#pragma once
#include <exception>
#include <new>
#include <string>

#include "formats/error.hpp"
#include "libpyramid/capi/pyramid.h"

namespace pyramid::capi {

// Keeps `message` as the calling thread's last error and returns `status`.
pyramid_status failWith(pyramid_status status, const std::string& message);

// Runs `body`, turning exceptions into statuses (no exception crosses the C API): a missing
// tile is NOT_FOUND, a cancelled run CANCELLED, an option the library refuses an argument
// error, any other Error a file problem, unless `body` already decided otherwise by returning
// a status.
template <class Body>
pyramid_status guarded(Body body) {
    try {
        return body();
    } catch (const pyramid::MissingTileError& e) {
        return failWith(PYRAMID_ERROR_NOT_FOUND, e.what());
    } catch (const pyramid::Cancelled& e) {
        return failWith(PYRAMID_ERROR_CANCELLED, e.what());
    } catch (const pyramid::OptionError& e) {
        return failWith(PYRAMID_ERROR_ARGUMENT, e.what());
    } catch (const pyramid::Error& e) {
        return failWith(PYRAMID_ERROR_FILE, e.what());
    } catch (const std::bad_alloc&) {
        return failWith(PYRAMID_ERROR_MEMORY, "out of memory");
    } catch (const std::exception& e) {
        return failWith(PYRAMID_ERROR_INTERNAL, e.what());
    } catch (...) {
        return failWith(PYRAMID_ERROR_INTERNAL, "unknown error");
    }
}

} // namespace pyramid::capi
