// Where the web viewer's files are (viewer_files.hpp).
#include "libpyramid/serve/viewer_files.hpp"

#include <algorithm>
#include <system_error>

namespace pyramid::serve {

namespace fs = std::filesystem;

fs::path viewerDirectory(const std::string& given) {
    if (!given.empty()) {
        return fs::path(given);
    }
    std::error_code ec;
    const fs::path program = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path installed = (program.parent_path() / PYRAMID_VIEWER_INSTALL_DIR).lexically_normal();
        if (fs::is_directory(installed, ec)) {
            return installed;
        }
    }
    return fs::path(PYRAMID_VIEWER_BUILD_DIR);
}

fs::path viewerFile(const fs::path& directory, const std::string& name) {
    const bool plain = !name.empty() && name.front() != '.' && std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-' ||
               c == '_';
    });
    std::error_code ec;
    if (!plain || !fs::is_regular_file(directory / name, ec)) {
        return {};
    }
    return directory / name;
}

} // namespace pyramid::serve
