// A nodata value written as text ("-9999", "nan"), as GDAL writes it in a GeoTIFF's
// GDAL_NODATA tag and OpenImageIO passes it on. Header-only: the image I/O module uses it too.
#pragma once
#include <limits>
#include <optional>
#include <string>

namespace pyramid {

inline std::optional<double> parseNodataText(const std::string& text) {
    if (text == "nan" || text == "NaN" || text == "-nan") {
        return std::numeric_limits<double>::quiet_NaN();
    }
    try {
        return std::stod(text);
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

} // namespace pyramid
