// The rules of `pyramid serve`'s /files/ answers (doc/cli/pyramid-serve.md, "Files"): which file
// a request names, never one outside the served directory, and which bytes a Range header asks.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace pyramid::serve {

// The regular file `relative` (a URL path after /files/, percent-decoded) names under `root` (a
// canonical directory), as a canonical path; nullopt when there is none or it is not allowed:
// an empty, absolute or backslashed path, a ".", ".." or empty component, a NUL, or a canonical
// path (symbolic links resolved) outside `root`.
std::optional<std::filesystem::path> servedFile(const std::filesystem::path& root, const std::string& relative);

// A Range header's answer for a resource of `size` bytes. One range "bytes=A-B", "bytes=A-" or
// "bytes=-N" is served as a part (B clamped to the last byte); several ranges are served as the
// whole resource (HTTP allows a server to ignore Range); a range that is malformed or starts at
// or beyond the end (or a suffix of 0 bytes) is unsatisfiable (416).
struct RangeAnswer {
    enum Kind { Whole, Part, Unsatisfiable } kind = Whole;
    uint64_t offset = 0;
    uint64_t length = 0; // Whole: size
};
RangeAnswer answerRange(const std::string& header, uint64_t size);

// "bytes A-B/SIZE" for a part, "bytes */SIZE" for an unsatisfiable range.
std::string contentRange(const RangeAnswer& answer, uint64_t size);

// The content type of a file served by name (by its extension; application/octet-stream else).
std::string contentTypeOf(const std::string& name);

} // namespace pyramid::serve
