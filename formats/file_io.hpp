// Whole reads and writes at an offset: the one loop every file access of the library shares,
// retried on interruption and on short transfers; and a file opened for such reads.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace pyramid {

// Reads `size` bytes at `offset`. True when all were read; false on an error (errno set) or
// at the end of the file first (errno 0).
bool readFully(int fd, void* out, size_t size, uint64_t offset);

// Writes `size` bytes at `offset`. True when all were written; false on an error (errno set;
// ENOSPC for a device that takes no more).
bool writeFully(int fd, const void* data, size_t size, uint64_t offset);

// A file opened for reading (close-on-exec), closed with the object. The constructor and size()
// throw Error naming the path when the file cannot be opened or examined.
class InputFile {
public:
    explicit InputFile(std::string path);
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;
    int fd() const { return fd_; }
    uint64_t size() const;
    // As readFully.
    bool readAt(void* out, size_t size, uint64_t offset) const { return readFully(fd_, out, size, offset); }

private:
    std::string path_;
    int fd_;
};

} // namespace pyramid
