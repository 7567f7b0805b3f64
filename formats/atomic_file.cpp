#include "formats/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>

#include "formats/error.hpp"
#include "formats/file_io.hpp"

namespace pyramid {

AtomicFile::AtomicFile(const std::string& path) : path_(path) {
    // The temporary sits in the destination's directory so that rename() is atomic.
    std::random_device rd;
    for (int attempt = 0; attempt < 32 && fd_ < 0; ++attempt) {
        tmp_ = path + ".tmp-" + std::to_string(rd());
        fd_ = ::open(tmp_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
        if (fd_ < 0 && errno != EEXIST) {
            break;
        }
    }
    if (fd_ < 0) {
        fail(path, std::string("cannot create output file: ") + std::strerror(errno));
    }
}

AtomicFile::~AtomicFile() {
    if (!committed_) {
        if (fd_ >= 0) {
            ::close(fd_);
        }
        ::unlink(tmp_.c_str());
    }
}

void AtomicFile::writeAt(uint64_t offset, const void* data, size_t size) {
    if (!writeFully(fd_, data, size, offset)) {
        fail(path_, std::string("write failed: ") + (errno == ENOSPC ? "no space left" : std::strerror(errno)));
    }
}

void AtomicFile::commit() {
    if (::fsync(fd_) != 0) {
        fail(path_, std::string("cannot flush output file: ") + std::strerror(errno));
    }
    ::close(fd_);
    fd_ = -1;
    if (::rename(tmp_.c_str(), path_.c_str()) != 0) {
        fail(path_, std::string("cannot move output file into place: ") + std::strerror(errno));
    }
    committed_ = true;
    // The rename itself survives a crash only once the directory entry is on disk.
    const size_t slash = path_.rfind('/');
    const std::string directory = slash == std::string::npos ? "." : (slash == 0 ? "/" : path_.substr(0, slash));
    const int dirFd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        ::fsync(dirFd); // best effort: the file is complete and in place either way
        ::close(dirFd);
    }
}

} // namespace pyramid
