#include "formats/output_paths.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>

#include "formats/error.hpp"
#include "formats/temporaries.hpp"

namespace pyramid {

namespace fs = std::filesystem;

namespace {

// The nearest existing ancestor of `p` (itself if it exists); "." for a relative path whose
// first part is missing.
fs::path nearestExisting(const fs::path& p) {
    std::error_code ec;
    for (fs::path q = p; !q.empty(); q = q.parent_path()) {
        if (fs::exists(fs::symlink_status(q, ec)) || fs::exists(q, ec)) {
            return q;
        }
        if (q == q.parent_path()) {
            break;
        }
    }
    return ".";
}

// Throws unless `dir` is a directory this process may create files in.
void checkWritableDirectory(const std::string& output, const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        fail(output, "cannot be written: " + dir.string() + " is not a directory");
    }
    if (::access(dir.c_str(), W_OK | X_OK) != 0) {
        fail(output, "cannot be written in " + dir.string() + ": " + systemWords(errno));
    }
}

} // namespace

OutputParents::~OutputParents() {
    if (kept_) {
        for (const std::string& d : created_) {
            unregisterTemporary(d);
        }
        return;
    }
    auto lock = lockTemporaries();
    for (const std::string& d : created_) {
        ::rmdir(d.c_str()); // only succeeds when empty
        unregisterTemporary(d);
    }
}

void prepareOutputFile(const std::string& path, OutputParents& parents) {
    std::error_code ec;
    const fs::path file = fs::path(path).lexically_normal();
    if (path.empty() || file.filename().empty()) {
        fail(path, "is not a file name");
    }
    if (fs::is_directory(file, ec)) {
        fail(path, "is a directory: name the file to write in it");
    }
    const fs::path parent = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    checkWritableDirectory(path, nearestExisting(parent));
    makeOutputDirectory(parent.string(), parents, path);
    sweepStaleTemporaries(parent.string());
}

void makeOutputDirectory(const std::string& directory, OutputParents& parents, const std::string& who) {
    const fs::path dir = fs::path(directory).lexically_normal();
    const fs::path existing = nearestExisting(dir);
    if (existing == dir) {
        std::error_code ec;
        if (!fs::is_directory(dir, ec)) {
            fail(who, "cannot be written: " + dir.string() + " is not a directory");
        }
        return;
    }
    auto lock = lockTemporaries();
    std::vector<std::string> missing;
    for (fs::path p = dir; p != existing && !p.empty(); p = p.parent_path()) {
        missing.push_back(p.string());
    }
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
        registerTemporary(*it, TemporaryKind::EmptyDirectory);
        if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST) {
            const int error = errno;
            unregisterTemporary(*it);
            fail(who, "cannot create the directory " + *it + ": " + systemWords(error));
        }
        parents.created_.insert(parents.created_.begin(), *it);
    }
}

void prepareOutputDirectory(const std::string& directory) {
    std::error_code ec;
    const fs::path dir = fs::path(directory).lexically_normal();
    const fs::file_type type = fs::status(dir, ec).type();
    if (type != fs::file_type::not_found && type != fs::file_type::none && type != fs::file_type::directory) {
        fail(directory, "is not a directory (the outputs go into a directory of that name)");
    }
    checkWritableDirectory(directory, nearestExisting(dir));
    if (type == fs::file_type::directory) {
        sweepStaleTemporaries(dir.string());
    }
}

} // namespace pyramid
