// A temporary file for decoded samples that do not fit the input cache: an input with no
// random access (a PNG, a TIFF stored as a few huge strips) is decoded once, in order, into it,
// and read back by window with pread, so its decoded size costs disk (and page cache, which the
// kernel may drop) instead of process memory. The file is unlinked as soon as it is created: it
// leaves nothing behind, however the process ends.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace pyramid {

class ScratchFile {
public:
    // A new, empty file in the temporary directory (TMPDIR, else /tmp). `input` names the input
    // in messages. Throws Error when none can be created.
    explicit ScratchFile(const std::string& input);
    ~ScratchFile();
    ScratchFile(const ScratchFile&) = delete;
    ScratchFile& operator=(const ScratchFile&) = delete;

    // Writes `bytes` at `offset`; throws Error naming the input (a full disk says so).
    void write(uint64_t offset, const void* data, size_t bytes) const;
    // Reads `bytes` at `offset`, which were written before; throws Error on a read error.
    void read(uint64_t offset, void* data, size_t bytes) const;

private:
    std::string input_;
    int fd_ = -1;
};

} // namespace pyramid
