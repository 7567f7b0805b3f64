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

uint64_t parseByteSize(const std::string& text, const std::string& where) {
    std::string_view digits(text);
    int shift = 0;
    if (!digits.empty()) {
        switch (digits.back()) {
        case 'K': case 'k': shift = 10; break;
        case 'M': case 'm': shift = 20; break;
        case 'G': case 'g': shift = 30; break;
        case 'T': case 't': shift = 40; break;
        default: break;
        }
        if (shift) {
            digits.remove_suffix(1);
        }
    }
    uint64_t v = 0;
    const char* end = digits.data() + digits.size();
    const auto [ptr, ec] = std::from_chars(digits.data(), end, v);
    if (digits.empty() || ec != std::errc() || ptr != end || v == 0 || v > (uint64_t{1} << (63 - shift))) {
        fail(where, "'" + text + "' is not a size in bytes (a whole number, optionally with K, M, G or T)");
    }
    return v << shift;
}

} // namespace pyramid
