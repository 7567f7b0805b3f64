// Whole reads and writes at an offset: the one loop every file access of the library shares,
// retried on interruption and on short transfers.
#pragma once
#include <cstddef>
#include <cstdint>

namespace pyramid {

// Reads `size` bytes at `offset`. True when all were read; false on an error (errno set) or
// at the end of the file first (errno 0).
bool readFully(int fd, void* out, size_t size, uint64_t offset);

// Writes `size` bytes at `offset`. True when all were written; false on an error (errno set;
// ENOSPC for a device that takes no more).
bool writeFully(int fd, const void* data, size_t size, uint64_t offset);

} // namespace pyramid
