// Parallel loops over independent work items (OpenMP). An exception may not leave an OpenMP
// region, so each item's exception is caught and, after the loop, the one of the lowest index
// is rethrown: the error a user sees does not depend on thread timing.
#pragma once
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <limits>
#include <mutex>
#include <string>

#include "formats/error.hpp"

namespace pyramid {

// The most worker threads a `threads` option may ask for: more than any machine's cores, and
// well below what a process can start (OpenMP cannot report a thread it failed to create).
constexpr int kMaxThreads = 1024;

// The worker count of a `threads` option: 0 is all cores (OpenMP's default), 1 to kMaxThreads
// are taken as given; anything else is refused (OptionError "threads"), never clamped.
inline int workerThreads(int requested) {
    if (requested < 0 || requested > kMaxThreads) {
        failOption("threads", "must be 0 (all cores) to " + std::to_string(kMaxThreads) + ", not " +
                                  std::to_string(requested));
    }
    return requested > 0 ? requested : omp_get_max_threads();
}

// No more threads than items: a worker without one would only wait at the loop's end, and
// libgomp's waiting worker spins, holding a core that the program's other threads (a decoder,
// a writer) could use.
template <class Body>
void parallelFor(int64_t count, int threads, const Body& body) {
    std::exception_ptr error;
    int64_t errorIndex = std::numeric_limits<int64_t>::max();
    std::mutex mutex;
    const int team = static_cast<int>(std::clamp<int64_t>(count, 1, std::max(threads, 1)));
#pragma omp parallel for schedule(dynamic) num_threads(team)
    for (int64_t i = 0; i < count; ++i) {
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (i > errorIndex) {
                continue; // an earlier item already failed: skip the rest
            }
        }
        try {
            body(i);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mutex);
            if (i < errorIndex) {
                errorIndex = i;
                error = std::current_exception();
            }
        }
    }
    if (error) {
        std::rethrow_exception(error);
    }
}

} // namespace pyramid
