// Numbers as the library's messages and reports print them.
#pragma once
#include <charconv>
#include <cstdio>
#include <string>

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

} // namespace pyramid
