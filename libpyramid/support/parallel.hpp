// Parallel loops over independent work items (OpenMP). An exception may not leave an OpenMP
// region, so each item's exception is caught and, after the loop, the one of the lowest index
// is rethrown: the error a user sees does not depend on thread timing.
#pragma once
#include <cstdint>
#include <exception>
#include <limits>
#include <mutex>

namespace pyramid {

template <class Body>
void parallelFor(int64_t count, int threads, const Body& body) {
    std::exception_ptr error;
    int64_t errorIndex = std::numeric_limits<int64_t>::max();
    std::mutex mutex;
#pragma omp parallel for schedule(dynamic) num_threads(threads)
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
