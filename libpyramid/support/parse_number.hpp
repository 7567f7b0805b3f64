// Numbers given as text (options, body parameters, extents): the whole text must be one finite
// number, so that "12abc", "", "inf" and "nan" are refused instead of read as a prefix.
#pragma once
#include <optional>
#include <string>

namespace pyramid {

std::optional<double> tryParseNumber(const std::string& text);

// Throws Error("WHERE: 'TEXT' is not WHAT").
double parseNumber(const std::string& text, const std::string& where, const std::string& what = "a number");
// The same for the value of a library option: throws OptionError(option, "'TEXT' is not WHAT").
double parseOptionNumber(const std::string& text, const std::string& option, const std::string& what = "a number");

} // namespace pyramid
