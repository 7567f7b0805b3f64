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

std::array<double, 4> parseOptionNumbers4(const std::string& text, const std::string& option, const std::string& form,
                                          const std::string& what) {
    std::array<double, 4> v{};
    size_t start = 0;
    for (size_t k = 0; k < v.size(); ++k) {
        const size_t comma = k + 1 < v.size() ? text.find(',', start) : text.size();
        if (comma == std::string::npos) {
            failOption(option, "'" + text + "' is not " + form);
        }
        v[k] = parseOptionNumber(text.substr(start, comma - start), option, what);
        start = comma + 1;
    }
    return v;
}

} // namespace pyramid
