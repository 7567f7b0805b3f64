// A nodata value written as text: as GDAL writes it in a GeoTIFF's GDAL_NODATA tag ("-9999",
// "nan", "inf", "-inf"), and OpenImageIO passes it on, or as a command line gives it. The whole
// text is one number, NaN or an infinity (support/parse_number.hpp: '.' is the decimal point
// whatever the locale); anything else ("-9999abc") is refused rather than read as a prefix.
// Header-only: the image I/O module uses it too.
#pragma once
#include <optional>
#include <string>
#include <string_view>

#include "formats/error.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid {

inline std::optional<double> tryParseNodataText(std::string_view text) {
    return readNumberText(text, true);
}

// The nodata value a file declares in its text `tag`: spaces and NULs around the text (which
// some writers pad with) are ignored. Throws Error("PATH: TAG 'TEXT' is not ...") for any other
// text: a declared value the reader cannot read must not silently become heights.
inline double parseDeclaredNodata(std::string_view text, const std::string& path, const char* tag) {
    const std::string_view blank(" \t\r\n\0", 5);
    const size_t first = text.find_first_not_of(blank);
    const std::string_view trimmed =
        first == std::string_view::npos ? std::string_view() : text.substr(first, text.find_last_not_of(blank) - first + 1);
    const std::optional<double> v = tryParseNodataText(trimmed);
    if (!v) {
        fail(path, std::string(tag) + " '" + std::string(trimmed) + "' is not a number, nan or inf (the nodata value)");
    }
    return *v;
}

} // namespace pyramid
