// Which file a /files/ request names, and which bytes its Range header asks (file_access.hpp).
#include "libpyramid/serve/file_access.hpp"

#include <algorithm>
#include <charconv>
#include <system_error>

#include "libpyramid/support/text.hpp"

namespace pyramid::serve {

namespace fs = std::filesystem;

std::optional<fs::path> servedFile(const fs::path& root, const std::string& relative) {
    if (relative.empty() || relative.front() == '/' || relative.find('\\') != std::string::npos ||
        relative.find('\0') != std::string::npos) {
        return std::nullopt;
    }
    size_t start = 0;
    while (start <= relative.size()) {
        const size_t slash = std::min(relative.find('/', start), relative.size());
        const std::string part = relative.substr(start, slash - start);
        if (part.empty() || part == "." || part == "..") {
            return std::nullopt;
        }
        start = slash + 1;
    }
    std::error_code ec;
    const fs::path file = fs::canonical(root / relative, ec);
    if (ec || !fs::is_regular_file(file, ec) || ec) {
        return std::nullopt;
    }
    // Inside root: root's components are the first components of the file's.
    const auto [rootEnd, fileAt] = std::mismatch(root.begin(), root.end(), file.begin(), file.end());
    if (rootEnd != root.end() || fileAt == file.end()) {
        return std::nullopt;
    }
    return file;
}

namespace {

// A whole decimal number of digits only; false for anything else (signs, spaces, overflow).
bool readDigits(const std::string& text, uint64_t& value) {
    if (text.empty() || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        return false;
    }
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size();
}

} // namespace

RangeAnswer answerRange(const std::string& header, uint64_t size) {
    RangeAnswer whole{RangeAnswer::Whole, 0, size};
    const RangeAnswer unsatisfiable{RangeAnswer::Unsatisfiable, 0, 0};
    if (header.empty()) {
        return whole;
    }
    const std::string prefix = "bytes=";
    if (header.compare(0, prefix.size(), prefix) != 0) {
        return unsatisfiable;
    }
    const std::string spec = header.substr(prefix.size());
    if (spec.find(',') != std::string::npos) {
        return whole;
    }
    const size_t dash = spec.find('-');
    if (dash == std::string::npos) {
        return unsatisfiable;
    }
    const std::string first = spec.substr(0, dash), last = spec.substr(dash + 1);
    uint64_t a = 0, b = 0;
    if (first.empty()) { // the last N bytes
        if (!readDigits(last, b) || b == 0 || size == 0) {
            return unsatisfiable;
        }
        const uint64_t n = std::min(b, size);
        return {RangeAnswer::Part, size - n, n};
    }
    if (!readDigits(first, a) || a >= size) {
        return unsatisfiable;
    }
    if (last.empty()) {
        return {RangeAnswer::Part, a, size - a};
    }
    if (!readDigits(last, b) || b < a) {
        return unsatisfiable;
    }
    return {RangeAnswer::Part, a, std::min(b, size - 1) - a + 1};
}

std::string contentRange(const RangeAnswer& answer, uint64_t size) {
    if (answer.kind == RangeAnswer::Part) {
        return "bytes " + std::to_string(answer.offset) + "-" + std::to_string(answer.offset + answer.length - 1) +
               "/" + std::to_string(size);
    }
    return "bytes */" + std::to_string(size);
}

std::string contentTypeOf(const std::string& name) {
    struct Type {
        const char* extension;
        const char* type;
    };
    static const Type types[] = {{".html", "text/html; charset=utf-8"},
                                 {".js", "text/javascript; charset=utf-8"},
                                 {".mjs", "text/javascript; charset=utf-8"},
                                 {".css", "text/css; charset=utf-8"},
                                 {".json", "application/json"},
                                 {".png", "image/png"},
                                 {".jpg", "image/jpeg"},
                                 {".svg", "image/svg+xml"},
                                 {".txt", "text/plain; charset=utf-8"},
                                 {".md", "text/markdown; charset=utf-8"}};
    for (const Type& t : types) {
        if (endsWithNoCase(name, t.extension)) {
            return t.type;
        }
    }
    return "application/octet-stream";
}

} // namespace pyramid::serve
