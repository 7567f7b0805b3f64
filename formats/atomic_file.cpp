#include "formats/atomic_file.hpp"

#include <aio.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "formats/error.hpp"
#include "formats/file_io.hpp"
#include "formats/temporaries.hpp"

namespace pyramid {

namespace {

// A failure of the file system, in the system's words ("no space left on device", "file too
// large", "input/output error"), naming the output as the user knows it.
[[noreturn]] void failWithErrno(const std::string& path, const std::string& what, int error) {
    fail(outputName(path), what + ": " + systemWords(error));
}

} // namespace

AtomicFile::AtomicFile(const std::string& path, const std::string& temporarySuffix) : path_(path) {
    // The temporary sits in the destination's directory so that rename() is atomic. Its name is
    // registered before it exists, so a signal at any moment finds it (temporaries.hpp).
    int error = 0;
    for (int attempt = 0; attempt < 32 && fd_ < 0; ++attempt) {
        auto lock = lockTemporaries();
        tmp_ = temporaryFileName(path, temporarySuffix);
        registerTemporary(tmp_, TemporaryKind::File);
        fd_ = ::open(tmp_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
        error = errno;
        if (fd_ < 0) {
            unregisterTemporary(tmp_);
            if (error != EEXIST) {
                break;
            }
        }
    }
    if (fd_ < 0) {
        failWithErrno(path, "cannot create output file", error);
    }
}

AtomicFile::~AtomicFile() {
    finishSync(); // no fdatasync may outlive the descriptor it was given
    if (!committed_) {
        if (fd_ >= 0) {
            ::close(fd_);
        }
        auto lock = lockTemporaries();
        ::unlink(tmp_.c_str());
        unregisterTemporary(tmp_);
    }
}

void AtomicFile::writeAt(uint64_t offset, const void* data, size_t size) {
    if (!writeFully(fd_, data, size, offset)) {
        failWithErrno(path_, "cannot write", errno);
    }
    unflushed_ += size;
    if (unflushed_ >= kWritebackBytes) {
        startSync();
    }
}

void AtomicFile::startSync() {
    if (sync_) {
        if (::aio_error(sync_.get()) == EINPROGRESS) {
            return; // the next one covers these bytes too
        }
        finishSync();
    }
    unflushed_ = 0;
    auto request = std::make_unique<::aiocb>();
    std::memset(request.get(), 0, sizeof(::aiocb));
    request->aio_fildes = fd_;
    request->aio_sigevent.sigev_notify = SIGEV_NONE;
    if (::aio_fsync(O_DSYNC, request.get()) == 0) {
        sync_ = std::move(request);
    } // else (no resources for it): flush() makes the file durable all the same
}

void AtomicFile::finishSync() {
    if (!sync_) {
        return;
    }
    const ::aiocb* const list[1] = {sync_.get()};
    while (::aio_error(sync_.get()) == EINPROGRESS) {
        ::aio_suspend(list, 1, nullptr);
    }
    const int error = ::aio_error(sync_.get());
    (void)::aio_return(sync_.get());
    if (error != 0 && syncError_ == 0) {
        syncError_ = error;
    }
    sync_.reset();
}

void AtomicFile::flush() {
    if (fd_ < 0) {
        return;
    }
    // Write errors a file system defers (a full disk on NFS, EIO) show at fsync or close; one
    // that a background fdatasync met is not shown again to the next.
    finishSync();
    if (syncError_ != 0) {
        failWithErrno(path_, "cannot write (flush)", syncError_);
    }
    if (::fsync(fd_) != 0) {
        failWithErrno(path_, "cannot write (flush)", errno);
    }
    const int closed = ::close(fd_);
    fd_ = -1;
    if (closed != 0 && errno != EINTR) {
        failWithErrno(path_, "cannot write (close)", errno);
    }
}

void AtomicFile::commit() {
    flush();
    {
        // Under the registry's lock: a signal's cleanup finds either the temporary or the
        // finished file, never a file it would remove after it was put in place.
        auto lock = lockTemporaries();
        if (::rename(tmp_.c_str(), path_.c_str()) != 0) {
            failWithErrno(path_, "cannot move output file into place", errno);
        }
        committed_ = true;
        unregisterTemporary(tmp_);
    }
    // The rename itself survives a crash only once the directory entry is on disk. Not for a
    // file inside a staging directory: the staging directory's commit makes its files' entries
    // durable where they end up (staging_directory.hpp), and until its journal is on disk a
    // crash leaves the staging directory to be removed whole.
    if (insideStagingDirectory(path_)) {
        return;
    }
    const size_t slash = path_.rfind('/');
    const std::string directory = slash == std::string::npos ? "." : (slash == 0 ? "/" : path_.substr(0, slash));
    const int dirFd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        ::fsync(dirFd); // best effort: the file is complete and in place either way
        ::close(dirFd);
    }
}

} // namespace pyramid
