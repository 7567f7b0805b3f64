#include "formats/byte_source.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "formats/error.hpp"
#include "formats/file_io.hpp"

namespace pyramid {

namespace {

class FileSource final : public ByteSource {
public:
    explicit FileSource(const std::string& path) : ByteSource(path) {
        fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd_ < 0) {
            fail(path, std::string("cannot open: ") + std::strerror(errno));
        }
        struct stat st {};
        if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
            ::close(fd_);
            fail(path, "not a regular file");
        }
        size_ = static_cast<uint64_t>(st.st_size);
    }
    ~FileSource() override { ::close(fd_); }

    uint64_t size() const override { return size_; }

    void readAt(uint64_t offset, void* out, size_t size) const override {
        checkRange(*this, size_, offset, size);
        if (!readFully(fd_, out, size, offset)) {
            fail(name(), errno ? std::string("read failed: ") + std::strerror(errno) : "unexpected end of file");
        }
    }

private:
    int fd_ = -1;
    uint64_t size_ = 0;
};

class MemorySource final : public ByteSource {
public:
    MemorySource(std::string name, const void* data, size_t size)
        : ByteSource(std::move(name)), data_(static_cast<const uint8_t*>(data)), size_(size) {}

    uint64_t size() const override { return size_; }

    void readAt(uint64_t offset, void* out, size_t size) const override {
        checkRange(*this, size_, offset, size);
        if (size > 0) {
            std::memcpy(out, data_ + offset, size);
        }
    }

private:
    const uint8_t* data_;
    uint64_t size_;
};

} // namespace

void checkRange(const ByteSource& source, uint64_t total, uint64_t offset, size_t size) {
    if (offset > total || size > total - offset) {
        fail(source.name(), "unexpected end of file (" + std::to_string(size) + " bytes at offset " +
                                std::to_string(offset) + " of " + std::to_string(total) + ")");
    }
}

std::shared_ptr<const ByteSource> openFileSource(const std::string& path) {
    return std::make_shared<FileSource>(path);
}

std::vector<std::shared_ptr<const ByteSource>> openFileSources(const std::vector<std::string>& paths) {
    std::vector<std::shared_ptr<const ByteSource>> sources;
    sources.reserve(paths.size());
    for (const std::string& path : paths) {
        sources.push_back(openFileSource(path));
    }
    return sources;
}

std::shared_ptr<const ByteSource> memorySource(std::string name, const void* data, size_t size) {
    if (!data && size > 0) {
        fail(name, "no data for a memory source of " + std::to_string(size) + " bytes");
    }
    return std::make_shared<MemorySource>(std::move(name), data, size);
}

} // namespace pyramid
