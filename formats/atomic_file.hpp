// Outputs appear atomically: data goes to a temporary file in the destination's directory,
// PATH.tmp-<pid>-<hex> (registered while it exists: formats/temporaries.hpp), and is renamed
// onto the destination only by commit(). Destroyed before commit(), the temporary is removed.
// Errors name the output and say the system's words: "DEM.dat: cannot write: no space left on
// device".
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

struct aiocb;

namespace pyramid {

class AtomicFile {
public:
    // Throws Error("PATH: cannot create ..."). With a `temporarySuffix` (".tif"), the temporary's
    // name ends with it, so that a writer choosing the format by the name can write it by path
    // (temporaryPath()) before commit().
    explicit AtomicFile(const std::string& path, const std::string& temporarySuffix = "");
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    int fd() const { return fd_; }
    const std::string& path() const { return path_; }
    const std::string& temporaryPath() const { return tmp_; }
    void writeAt(uint64_t offset, const void* data, size_t size); // throws on short writes
    // Everything but the rename: fsync and close (both checked). Lets a caller put several
    // files in place together with nothing slow left between their renames.
    void flush();
    void commit(); // flush() unless done, rename, fsync of the directory

private:
    // Every kWritebackBytes written, unless the last one still runs, an fdatasync of the file
    // starts in the background (POSIX aio_fsync): the data goes to disk, and the disk makes it
    // durable, while the run goes on. The fsync of flush() then waits for what came after the
    // last one only, instead of the whole file at the end of a run.
    static constexpr size_t kWritebackBytes = size_t{2} << 20;
    void startSync();
    void finishSync(); // waits for the background fdatasync under way, if any; keeps its error
    std::string path_;
    std::string tmp_;
    int fd_ = -1;
    bool committed_ = false;
    size_t unflushed_ = 0; // bytes written since the last background fdatasync started
    std::unique_ptr<::aiocb> sync_; // the background fdatasync under way (null: none)
    int syncError_ = 0;             // the first error one of them met (reported by flush())
};

} // namespace pyramid
