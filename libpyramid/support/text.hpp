// Text: numbers as the library's messages and reports print them, a file's bytes quoted in them,
// and names compared without
// regard to ASCII case (file extensions, tags, prefixes such as "EPSG:").
#pragma once
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

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

// A file's bytes quoted in a message: printable ASCII as it is, any other byte as \xNN, so that
// the message stays one line of text whatever the file holds.
inline std::string printableText(std::string_view bytes) {
    static constexpr char digits[] = "0123456789abcdef";
    std::string text;
    for (const char c : bytes) {
        const auto b = static_cast<unsigned char>(c);
        if (b >= 0x20 && b < 0x7f) {
            text += c;
        } else {
            text += "\\x";
            text += digits[b >> 4];
            text += digits[b & 15];
        }
    }
    return text;
}

// Bytes as lowercase hexadecimal ("0aff"), and back; nullopt for text that is not such.
inline std::string hexText(const std::vector<uint8_t>& bytes) {
    static constexpr char digits[] = "0123456789abcdef";
    std::string text;
    text.reserve(2 * bytes.size());
    for (const uint8_t b : bytes) {
        text += digits[b >> 4];
        text += digits[b & 15];
    }
    return text;
}

inline std::optional<std::vector<uint8_t>> bytesOfHex(std::string_view text) {
    const auto digit = [](char c) {
        return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
    };
    if (text.size() % 2) {
        return std::nullopt;
    }
    std::vector<uint8_t> bytes(text.size() / 2);
    for (size_t k = 0; k < bytes.size(); ++k) {
        const int hi = digit(text[2 * k]), lo = digit(text[2 * k + 1]);
        if (hi < 0 || lo < 0) {
            return std::nullopt;
        }
        bytes[k] = static_cast<uint8_t>(hi * 16 + lo);
    }
    return bytes;
}

// ASCII letters lowered; every other byte as it is (no locale).
inline char lowerAscii(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// `s` with its ASCII capitals in lower case (keywords of headers written in any case).
inline std::string lowerAsciiText(std::string s) {
    for (char& c : s) {
        c = lowerAscii(c);
    }
    return s;
}

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
