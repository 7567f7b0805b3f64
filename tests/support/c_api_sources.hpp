// A caller's sources for the C API tests (pyramid.h, pyramid_source): a path, bytes in memory, and
// I/O callbacks over memory that count their reads and releases and fail on demand; and a small
// residual region set whose files each have their own scale.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "libpyramid/capi/pyramid.h"
#include "tests/support/paths.hpp"

namespace pyramid::test {

// I/O callbacks over bytes in memory, counting reads and releases; reads fail from the
// `failAt`-th on (0: never).
struct MemoryIo {
    std::vector<uint8_t> data;
    std::atomic<long> reads{0};
    std::atomic<int> released{0};
    long failAt = 0;

    static int read(void* user, uint64_t offset, void* buffer, size_t size, size_t* bytesRead);
    static void release(void* user);
};

// A source of each kind; `name` (optional for memory) names it in messages. The path, bytes and
// callbacks are borrowed: they must outlive the source's use.
pyramid_source pathSource(const std::string& path);
pyramid_source memorySource(const std::vector<uint8_t>& bytes, const char* name = nullptr);
pyramid_source ioSource(MemoryIo& io, const char* name);

// A main residual pyramid (levels 0..2, minLevel 1) and two nested regions, each with its own
// scale: A rooted at (2, 1, 1) with levels 2..3, B inside A rooted at (3, 2, 2) with 3..4.
// Writes main.dat, a.dat and b.dat in `dir`; the tiles of each level are ramps of their own.
void writeResidualSet(const TempDir& dir);

} // namespace pyramid::test
