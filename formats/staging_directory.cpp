#include "formats/staging_directory.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <set>
#include <system_error>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/temporaries.hpp"

namespace pyramid {

namespace fs = std::filesystem;

namespace {

std::atomic<int> renameFailureForTesting{-1};

constexpr const char* kBackups = ".old";
constexpr const char* kJournal = ".commit";

struct Entry {
    std::string relative;
    bool old = false;  // the destination had a file, backed up in .old/
    bool drop = false; // no new file: a file named after an output, removed by the commit
};

// Flushes a file or directory to disk. False (errno set) when that fails.
bool fsyncPath(const std::string& path, bool directory) {
    const int fd = ::open(path.c_str(), (directory ? O_RDONLY | O_DIRECTORY : O_RDONLY) | O_CLOEXEC);
    if (fd < 0) {
        return false;
    }
    const bool ok = ::fsync(fd) == 0;
    const int error = errno;
    ::close(fd);
    errno = error;
    return ok;
}

// Puts back the destinations whose new file was moved in: the old file from .old/, or no
// file where there was none. True when every one is back.
bool rollBack(const fs::path& staging, const fs::path& destination, const std::vector<Entry>& entries) {
    bool ok = true;
    std::set<std::string> directories;
    for (const Entry& e : entries) {
        std::error_code ec;
        if (fs::exists(fs::symlink_status(staging / e.relative, ec))) {
            continue; // never moved
        }
        const fs::path target = destination / e.relative;
        if (e.old) {
            ok = ::rename((staging / kBackups / e.relative).c_str(), target.c_str()) == 0 && ok;
        } else if (::unlink(target.c_str()) != 0 && errno != ENOENT) {
            ok = false;
        }
        directories.insert(target.parent_path().string());
    }
    for (const std::string& d : directories) {
        fsyncPath(d.empty() ? "." : d, true);
    }
    return ok;
}

std::vector<Entry> readJournal(const fs::path& journal) {
    std::vector<Entry> entries;
    std::ifstream in(journal);
    std::string line;
    while (std::getline(in, line)) {
        if (line.size() > 4 && (line.rfind("old ", 0) == 0 || line.rfind("new ", 0) == 0)) {
            entries.push_back({line.substr(4), line[0] == 'o'});
        }
    }
    return entries;
}

} // namespace

void StagingDirectory::failRenameForTesting(int index) { renameFailureForTesting = index; }

StagingDirectory::StagingDirectory(const std::string& destination) : destination_(destination) {
    makeOutputDirectory(destination, created_, destination);
    std::error_code ec;
    auto lock = lockTemporaries();
    // The process id tells a later run whether this run is still going (sweepStaleTemporaries).
    staging_ = (fs::path(destination) / stagingDirectoryName()).string();
    registerTemporary(staging_, TemporaryKind::Tree);
    if (!fs::create_directory(staging_, ec) || ec) {
        unregisterTemporary(staging_);
        fail(destination, "cannot create a staging directory (" + (ec ? systemWords(ec.value()) : "it exists") + ")");
    }
}

StagingDirectory::~StagingDirectory() {
    std::error_code ec;
    auto lock = lockTemporaries();
    if (!keep_) {
        fs::remove_all(staging_, ec);
    }
    unregisterTemporary(staging_);
    // created_ then removes the directories made for the destination, if empty and not committed.
}

std::string StagingDirectory::path(const std::string& relative) const {
    const fs::path p = fs::path(staging_) / relative;
    std::error_code ec;
    auto lock = lockTemporaries(); // not after a signal's cleanup has removed the staging tree
    fs::create_directories(p.parent_path(), ec);
    return p.string();
}

void StagingDirectory::commit() {
    const fs::path staging(staging_), destination(destination_);
    std::vector<Entry> entries;
    for (auto it = fs::recursive_directory_iterator(staging); it != fs::recursive_directory_iterator(); ++it) {
        if (it->path().filename() == kBackups && it.depth() == 0) {
            it.disable_recursion_pending();
            continue;
        }
        if (it->is_regular_file() && !(it.depth() == 0 && it->path().filename() == kJournal)) {
            entries.push_back({fs::relative(it->path(), staging).generic_string(), false});
        }
    }
    // The files named after each output that it does not write again (an earlier run's region
    // index, region files, georeference sidecar) go in the same commit: an output replaces
    // them all, or, should the commit fail, none.
    std::set<std::string> staged;
    for (const Entry& e : entries) {
        staged.insert(e.relative);
    }
    const size_t outputs = entries.size();
    for (size_t i = 0; i < outputs; ++i) {
        for (const std::string& named : filesNamedAfter((destination / entries[i].relative).string())) {
            const std::string relative = fs::path(named).lexically_relative(destination).generic_string();
            if (!relative.empty() && relative.rfind("..", 0) != 0 && staged.insert(relative).second) {
                entries.push_back({relative, false, true});
            }
        }
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.relative < b.relative; });

    // 1. Every destination replaceable. The new files are on disk already: each was written
    // by an AtomicFile, whose commit flushed it before renaming it into the staging tree.
    auto lock = lockTemporaries();
    for (Entry& e : entries) {
        const fs::path target = destination / e.relative;
        std::error_code ec;
        const fs::file_status status = fs::symlink_status(target, ec);
        if (!fs::exists(status)) {
            continue;
        }
        if (!fs::is_regular_file(status) && !fs::is_symlink(status)) {
            fail(target.string(), std::string("cannot replace it with the new output: it is ") +
                                      (fs::is_directory(status) ? "a directory" : "not a file") +
                                      " (nothing was changed)");
        }
        // 2. The backup: a second name for the old file.
        const fs::path backup = staging / kBackups / e.relative;
        fs::create_directories(backup.parent_path(), ec);
        if (::link(target.c_str(), backup.c_str()) != 0) {
            fail(target.string(), "cannot keep the old file while the new one is moved in: " + systemWords(errno) +
                                      " (nothing was changed)");
        }
        e.old = true;
    }
    // 3. The journal: which destinations the next run must restore should this one die.
    {
        const fs::path journal = staging / kJournal;
        const fs::path partial = staging / (std::string(kJournal) + ".partial");
        std::ofstream out(partial, std::ios::binary | std::ios::trunc);
        for (const Entry& e : entries) {
            out << (e.old ? "old " : "new ") << e.relative << "\n";
        }
        out.close();
        if (!out || !fsyncPath(partial.string(), false) || ::rename(partial.c_str(), journal.c_str()) != 0 ||
            !fsyncPath(staging_, true)) {
            fail(destination_, "cannot write the commit journal in " + staging_ + ": " + systemWords(errno ? errno : EIO) +
                                   " (nothing was changed)");
        }
    }
    // 4. The new files in place, or all the old ones back.
    std::vector<std::string> createdHere;
    std::set<std::string> directories;
    for (size_t i = 0; i < entries.size(); ++i) {
        const fs::path target = destination / entries[i].relative;
        std::error_code ec;
        for (fs::path p = target.parent_path(); !p.empty() && p != destination && !fs::exists(p, ec); p = p.parent_path()) {
            createdHere.push_back(p.string());
        }
        fs::create_directories(target.parent_path(), ec);
        directories.insert(target.parent_path().string());
        int error = 0;
        if (static_cast<int>(i) == renameFailureForTesting.load()) {
            error = EIO;
        } else if (entries[i].drop ? ::unlink(target.c_str()) != 0 && errno != ENOENT
                                   : ::rename((staging / entries[i].relative).c_str(), target.c_str()) != 0) {
            error = errno;
        }
        if (error != 0) {
            const std::string what = entries[i].drop ? "cannot remove the earlier run's file named after an output: "
                                                     : "cannot move the new output into place: ";
            const bool restored = rollBack(staging, destination, entries);
            for (const std::string& d : createdHere) {
                fs::remove(d, ec);
            }
            if (!restored) {
                keep_ = true; // the old files that could not be put back are still in .old/
                unregisterTemporary(staging_);
                fail(target.string(), what + systemWords(error) + "; some old files could not be put back: they are in " +
                                          staging_ + "/" + kBackups);
            }
            ::unlink((staging / kJournal).c_str());
            fail(target.string(), what + systemWords(error) + " (the old outputs are unchanged)");
        }
    }
    // 5. The renames on disk.
    for (const std::string& d : directories) {
        fsyncPath(d.empty() ? "." : d, true);
    }
    // 6. Committed.
    ::unlink((staging / kJournal).c_str());
    fsyncPath(staging_, true);
    std::error_code ec;
    fs::remove_all(staging_, ec);
    created_.keep();
}

bool StagingDirectory::recover(const std::string& staging, const std::string& destination) {
    const fs::path journal = fs::path(staging) / kJournal;
    std::error_code ec;
    if (!fs::exists(journal, ec)) {
        return true;
    }
    auto lock = lockTemporaries();
    if (!rollBack(staging, destination, readJournal(journal))) {
        return false;
    }
    ::unlink(journal.c_str());
    return true;
}

} // namespace pyramid
