// Numbers as the library's messages and reports print them.
#pragma once
#include <cstdio>
#include <string>

namespace pyramid {

// Up to 6 significant digits, no trailing zeros: "0.5", "1e+06".
inline std::string numberText(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", x);
    return text;
}

} // namespace pyramid
