// Numbers given as text (options, body parameters, extents, nodata values): the whole text must
// be one number, so that "12abc", "-9999abc", "" and " 1" are refused instead of read as a
// prefix. Read with std::from_chars: the decimal point is '.', whatever the process's locale.
// Header-only core (readNumberText), so that the image I/O module can use it too.
#pragma once
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

namespace pyramid {

// The whole of `text` as a decimal number: an optional sign ('+' or '-'), digits with an
// optional '.' fraction, an optional exponent. With `nonFinite`, also "nan", "inf" and
// "infinity" (any case, signed). Out-of-range numbers ("1e999") are refused.
inline std::optional<double> readNumberText(std::string_view text, bool nonFinite = false) {
    if (text.size() > 1 && text[0] == '+' && text[1] != '-' && text[1] != '+') {
        text.remove_prefix(1); // from_chars takes '-' only
    }
    double v = 0.0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v, std::chars_format::general);
    if (text.empty() || ec != std::errc() || ptr != end || (!nonFinite && !std::isfinite(v))) {
        return std::nullopt;
    }
    return v;
}

// The whole of `text` as a whole number of type Int: decimal digits, with a leading '-' for a
// negative one; nothing for anything else, or a number Int cannot hold.
template <class Int>
std::optional<Int> readWholeNumber(std::string_view text) {
    Int v{};
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (text.empty() || ec != std::errc() || ptr != end) {
        return std::nullopt;
    }
    return v;
}

// A finite number, or nothing.
std::optional<double> tryParseNumber(const std::string& text);

// Throws Error("WHERE: 'TEXT' is not WHAT").
double parseNumber(const std::string& text, const std::string& where, const std::string& what = "a number");
// The same for the value of a library option: throws OptionError(option, "'TEXT' is not WHAT").
double parseOptionNumber(const std::string& text, const std::string& option, const std::string& what = "a number");
// Four comma-separated numbers ("A,B,C,D", an extent) as the value of a library option: throws
// OptionError(option, "'TEXT' is not FORM") for another count, and as parseOptionNumber (each
// part WHAT) for a part that is not a number.
std::array<double, 4> parseOptionNumbers4(const std::string& text, const std::string& option, const std::string& form,
                                          const std::string& what);

// A size in bytes: a whole number with an optional suffix K, M, G or T (powers of 1024; "4G" is
// 4294967296). Throws Error("WHERE: 'TEXT' is not a size in bytes") for anything else, zero,
// or a size past 2^63.
uint64_t parseByteSize(const std::string& text, const std::string& where);

} // namespace pyramid
