// Text: numbers as the library's messages and reports print them, and names compared without
// regard to ASCII case (file extensions, tags, prefixes such as "EPSG:").
#pragma once
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <string>
#include <string_view>

namespace pyramid {

// Up to 6 significant digits, no trailing zeros: "0.5", "1e+06".
inline std::string numberText(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", x);
    return text;
}

// The shortest text that reads back as the same double: for values stored as text (metadata).
inline std::string exactNumberText(double x) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, x).ptr;
    return std::string(text, end);
}

// ASCII letters lowered; every other byte as it is (no locale).
inline char lowerAscii(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

inline bool equalNoCase(std::string_view a, std::string_view b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return lowerAscii(x) == lowerAscii(y); });
}

inline bool startsWithNoCase(std::string_view text, std::string_view prefix) {
    return text.size() >= prefix.size() && equalNoCase(text.substr(0, prefix.size()), prefix);
}

inline bool endsWithNoCase(std::string_view text, std::string_view suffix) {
    return text.size() >= suffix.size() && equalNoCase(text.substr(text.size() - suffix.size()), suffix);
}

} // namespace pyramid
