#include "formats/staging_directory.hpp"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "formats/error.hpp"

namespace pyramid {

namespace fs = std::filesystem;

StagingDirectory::StagingDirectory(const std::string& destination) : destination_(destination) {
    std::error_code ec;
    for (fs::path p = fs::path(destination).lexically_normal(); !p.empty() && !fs::exists(p, ec);
         p = p.parent_path()) {
        created_.push_back(p.string());
        if (p == p.parent_path()) {
            break;
        }
    }
    fs::create_directories(destination, ec);
    if (ec || !fs::is_directory(destination)) {
        fail(destination, "cannot create the output directory (" + (ec ? ec.message() : "not a directory") + ")");
    }
    // The process id makes the name unique among concurrent runs into the same directory.
    staging_ = (fs::path(destination) / (".staging-" + std::to_string(::getpid()))).string();
    fs::remove_all(staging_, ec);
    if (!fs::create_directory(staging_, ec) || ec) {
        fail(destination, "cannot create a staging directory (" + ec.message() + ")");
    }
}

StagingDirectory::~StagingDirectory() {
    std::error_code ec;
    fs::remove_all(staging_, ec);
    if (!committed_) {
        for (const std::string& dir : created_) {
            fs::remove(dir, ec); // only succeeds when empty
        }
    }
}

std::string StagingDirectory::path(const std::string& relative) const {
    const fs::path p = fs::path(staging_) / relative;
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    return p.string();
}

void StagingDirectory::commit() {
    std::error_code ec;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(staging_)) {
        if (!e.is_regular_file()) {
            continue;
        }
        const fs::path target = fs::path(destination_) / fs::relative(e.path(), staging_);
        fs::create_directories(target.parent_path(), ec);
        fs::rename(e.path(), target, ec);
        if (ec) {
            fail(target.string(), "cannot move the finished file into place (" + ec.message() + ")");
        }
    }
    fs::remove_all(staging_, ec);
    committed_ = true;
}

} // namespace pyramid
