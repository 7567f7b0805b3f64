#include "libpyramid/support/parse_number.hpp"

#include "formats/error.hpp"

namespace pyramid {

std::optional<double> tryParseNumber(const std::string& text) {
    return readNumberText(text);
}

double parseNumber(const std::string& text, const std::string& where, const std::string& what) {
    const std::optional<double> v = tryParseNumber(text);
    if (!v) {
        fail(where, "'" + text + "' is not " + what);
    }
    return *v;
}

double parseOptionNumber(const std::string& text, const std::string& option, const std::string& what) {
    const std::optional<double> v = tryParseNumber(text);
    if (!v) {
        failOption(option, "'" + text + "' is not " + what);
    }
    return *v;
}

} // namespace pyramid
