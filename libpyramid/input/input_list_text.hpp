// The text rules an input list shares with the VRTs it names (input_list.cpp, vrt_xml.cpp,
// vrt_sources.cpp): ASCII white space, trimmed names, a path resolved against a list file's
// or a VRT's directory.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>

namespace pyramid::input_list_detail {

namespace fs = std::filesystem;

inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

inline std::string trim(std::string_view text) {
    size_t begin = 0, end = text.size();
    while (begin < end && isSpace(text[begin])) {
        ++begin;
    }
    while (end > begin && isSpace(text[end - 1])) {
        --end;
    }
    return std::string(text.substr(begin, end - begin));
}

// PATH joined to DIRECTORY unless absolute; DIRECTORY empty leaves it as it is.
inline std::string resolveAgainst(const std::string& directory, const std::string& path) {
    return fs::path(path).is_absolute() ? path : (fs::path(directory) / path).string();
}

} // namespace pyramid::input_list_detail
