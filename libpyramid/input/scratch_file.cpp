#include "libpyramid/input/scratch_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "formats/error.hpp"
#include "formats/file_io.hpp"
#include "formats/temporaries.hpp"

namespace pyramid {

namespace {

std::string temporaryDirectory() {
    const char* tmp = std::getenv("TMPDIR");
    return tmp && *tmp ? tmp : "/tmp";
}

} // namespace

ScratchFile::ScratchFile(const std::string& input) : input_(input) {
    const std::string dir = temporaryDirectory();
#ifdef O_TMPFILE
    fd_ = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
#endif
    if (fd_ < 0) {
        // Without O_TMPFILE (some file systems): a named file, unlinked at once.
        // Under the temporaries' lock: a signal's cleanup never comes between the two.
        std::string name = (std::filesystem::path(dir) / "libpyramid-scratch-XXXXXX").string();
        auto lock = lockTemporaries();
        fd_ = ::mkstemp(name.data());
        if (fd_ >= 0) {
            ::unlink(name.c_str());
        }
    }
    if (fd_ < 0) {
        fail(input_, "cannot create a scratch file in " + dir + " for the decoded samples: " + std::strerror(errno) +
                         " (set TMPDIR to a writable directory with room for them)");
    }
}

ScratchFile::~ScratchFile() {
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

void ScratchFile::write(uint64_t offset, const void* data, size_t bytes) const {
    if (!writeFully(fd_, data, bytes, offset)) {
        const int e = errno;
        fail(input_, std::string("cannot write the decoded samples to the scratch file in ") + temporaryDirectory() +
                         ": " + systemWords(e) + (e == ENOSPC ? " (set TMPDIR to a directory with more room)" : ""));
    }
}

void ScratchFile::read(uint64_t offset, void* data, size_t bytes) const {
    if (!readFully(fd_, data, bytes, offset)) {
        fail(input_, std::string("cannot read the scratch file of decoded samples: ") +
                         (errno ? std::strerror(errno) : "file too short"));
    }
}

} // namespace pyramid
