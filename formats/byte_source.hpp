// Where a pyramid file's bytes come from: a file, a block of memory, or anything a caller can
// read at an offset (the C API's I/O callbacks). Readers (TileTable, ResidualFileReader,
// OrthoFileReader) read through one, so a pyramid opens the same way from any of them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pyramid {

class ByteSource {
public:
    explicit ByteSource(std::string name) : name_(std::move(name)) {}
    virtual ~ByteSource() = default;
    ByteSource(const ByteSource&) = delete;
    ByteSource& operator=(const ByteSource&) = delete;

    // What messages call the source: a file's path, or a name its opener chose.
    const std::string& name() const { return name_; }
    // Total bytes of the source, fixed for its lifetime.
    virtual uint64_t size() const = 0;
    // Reads exactly `size` bytes at byte `offset` into `out`. Safe from many threads at once.
    // Throws Error("NAME: ...") when the range passes the end or the read fails.
    virtual void readAt(uint64_t offset, void* out, size_t size) const = 0;

private:
    std::string name_;
};

// Opens the regular file `path` (named by its path). Throws Error("PATH: cannot open: ...").
std::shared_ptr<const ByteSource> openFileSource(const std::string& path);
// openFileSource of each path, in order.
std::vector<std::shared_ptr<const ByteSource>> openFileSources(const std::vector<std::string>& paths);

// The `size` bytes at `data`, borrowed: they must stay unchanged while the source lives.
std::shared_ptr<const ByteSource> memorySource(std::string name, const void* data, size_t size);

// Throws Error("NAME: unexpected end of file ...") unless [offset, offset + size) lies within
// the source's `total` bytes: the check every implementation of readAt makes first.
void checkRange(const ByteSource& source, uint64_t total, uint64_t offset, size_t size);

} // namespace pyramid
