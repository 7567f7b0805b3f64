// Numbers given as text (options, body parameters, extents): the whole text must be one finite
// number, so that "12abc", "", "inf" and "nan" are refused instead of read as a prefix.
#pragma once
#include <array>
#include <optional>
#include <string>

namespace pyramid {

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

} // namespace pyramid
