#include "formats/temporaries.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <system_error>
#include <thread>
#include <vector>

#include "formats/staging_directory.hpp"

namespace pyramid {

namespace fs = std::filesystem;

namespace {

struct Registry {
    std::recursive_mutex mutex;
    std::map<std::string, TemporaryKind> paths;
};

// Never destroyed: a signal may come while static objects are being destroyed at exit.
Registry& registry() {
    static Registry* r = new Registry;
    return *r;
}

bool allDigits(const std::string& s) {
    return !s.empty() && s.size() <= 10 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool allHex(const std::string& s) {
    return s.size() == 8 &&
           std::all_of(s.begin(), s.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

// The pid of "<pid>-<hex>" (or of "<pid>" alone when `hexOptional`), else 0.
pid_t parseTag(const std::string& tag, bool hexOptional) {
    const size_t dash = tag.find('-');
    const std::string pid = dash == std::string::npos ? tag : tag.substr(0, dash);
    if (!allDigits(pid)) {
        return 0;
    }
    if (dash == std::string::npos ? !hexOptional : !allHex(tag.substr(dash + 1))) {
        return 0;
    }
    const long value = std::stol(pid);
    return value > 0 && value <= 0x7fffffff ? static_cast<pid_t>(value) : 0;
}

// True when no process `pid` exists: a temporary of a live process (even another user's,
// where kill() says EPERM) is never stale.
bool processIsGone(pid_t pid) { return pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH; }

constexpr const char* kTmp = ".tmp-";
constexpr const char* kStaging = ".staging-";

} // namespace

std::unique_lock<std::recursive_mutex> lockTemporaries() { return std::unique_lock<std::recursive_mutex>(registry().mutex); }

void registerTemporary(const std::string& path, TemporaryKind kind) {
    auto lock = lockTemporaries();
    registry().paths[path] = kind;
}

void unregisterTemporary(const std::string& path) {
    auto lock = lockTemporaries();
    registry().paths.erase(path);
}

void removeTemporariesForExit() {
    Registry& r = registry();
    r.mutex.lock(); // kept: no commit may start once the temporaries are going
    std::vector<std::string> directories;
    for (const auto& [path, kind] : r.paths) {
        std::error_code ec;
        switch (kind) {
        case TemporaryKind::File:
            ::unlink(path.c_str());
            break;
        case TemporaryKind::Tree:
            // Workers may still be writing into it: remove again until it stays gone.
            for (int attempt = 0; attempt < 100; ++attempt) {
                fs::remove_all(path, ec);
                if (!fs::exists(fs::symlink_status(path, ec))) {
                    break;
                }
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            }
            break;
        case TemporaryKind::EmptyDirectory:
            directories.push_back(path);
            break;
        }
    }
    std::sort(directories.begin(), directories.end(),
              [](const std::string& a, const std::string& b) { return a.size() > b.size(); });
    for (const std::string& d : directories) {
        ::rmdir(d.c_str()); // only succeeds when empty
    }
}

std::string temporaryTag() {
    static std::mutex mutex;
    static std::mt19937 generator(std::random_device{}());
    uint32_t random = 0;
    {
        std::lock_guard<std::mutex> lock(mutex);
        random = static_cast<uint32_t>(generator());
    }
    char hex[9];
    std::snprintf(hex, sizeof hex, "%08x", random);
    return std::to_string(::getpid()) + "-" + hex;
}

std::string temporaryFileName(const std::string& path, const std::string& suffix) {
    return path + kTmp + temporaryTag() + suffix;
}

std::string stagingDirectoryName() { return kStaging + temporaryTag(); }

namespace {

bool isStagingName(const std::string& name) {
    return name.rfind(kStaging, 0) == 0 && parseTag(name.substr(std::strlen(kStaging)), true) != 0;
}

} // namespace

bool insideStagingDirectory(const std::string& path) {
    const fs::path p(path);
    return std::any_of(p.begin(), p.end(), [](const fs::path& part) { return isStagingName(part.string()); });
}

std::string outputName(const std::string& path) {
    fs::path out;
    for (const fs::path& part : fs::path(path)) {
        const std::string name = part.string();
        if (isStagingName(name)) {
            if (out == ".") {
                out.clear(); // staged in the working directory: the output named as given, "DEM.dat"
            }
            continue;
        }
        out /= part;
    }
    return out.string();
}

int sweepStaleTemporaries(const std::string& directory) {
    std::error_code ec;
    fs::directory_iterator it(directory.empty() ? "." : directory, ec);
    if (ec) {
        return 0;
    }
    int removed = 0;
    for (; it != fs::directory_iterator(); it.increment(ec)) {
        if (ec) {
            break;
        }
        const fs::path path = it->path();
        const std::string name = path.filename().string();
        const fs::file_status status = fs::symlink_status(path, ec);
        if (ec) {
            continue;
        }
        if (name.rfind(kStaging, 0) == 0) {
            const pid_t pid = parseTag(name.substr(std::strlen(kStaging)), true);
            if (pid != 0 && fs::is_directory(status) && processIsGone(pid)) {
                // An interrupted commit is undone before its backups go with the directory.
                if (StagingDirectory::recover(path.string(), directory.empty() ? "." : directory)) {
                    fs::remove_all(path, ec);
                    removed += ec ? 0 : 1;
                }
            }
            continue;
        }
        const size_t tmp = name.rfind(kTmp);
        if (tmp != std::string::npos && tmp > 0 && fs::is_regular_file(status)) {
            const std::string tag = name.substr(tmp + std::strlen(kTmp));
            const pid_t pid = parseTag(tag.substr(0, tag.find('.')), false); // without a suffix
            if (pid != 0 && processIsGone(pid) && ::unlink(path.c_str()) == 0) {
                ++removed;
            }
        }
    }
    return removed;
}

std::string systemWords(int error) {
    std::string words = std::strerror(error);
    if (!words.empty()) {
        words[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(words[0])));
    }
    return words;
}

} // namespace pyramid
