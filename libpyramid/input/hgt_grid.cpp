#include "libpyramid/input/hgt_grid.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>

#include "formats/error.hpp"

namespace pyramid {

namespace {

bool endsWithHgt(const std::string& name) {
    if (name.size() < 4) {
        return false;
    }
    std::string tail = name.substr(name.size() - 4);
    for (char& ch : tail) {
        ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    }
    return tail == ".hgt";
}

// The south-west corner the name gives: N|S two digits, E|W three digits, at the start of the
// stem and followed by its end or a dot. False when the name gives none.
bool cellOf(const std::string& stem, int& latitude, int& longitude) {
    if (stem.size() < 7 || (stem.size() > 7 && stem[7] != '.')) {
        return false;
    }
    const char ns = static_cast<char>(std::toupper(static_cast<unsigned char>(stem[0])));
    const char ew = static_cast<char>(std::toupper(static_cast<unsigned char>(stem[3])));
    const auto digits = [&](size_t from, size_t count, int& value) {
        value = 0;
        for (size_t k = from; k < from + count; ++k) {
            if (!std::isdigit(static_cast<unsigned char>(stem[k]))) {
                return false;
            }
            value = value * 10 + (stem[k] - '0');
        }
        return true;
    };
    int lat = 0, lon = 0;
    if ((ns != 'N' && ns != 'S') || (ew != 'E' && ew != 'W') || !digits(1, 2, lat) || !digits(4, 3, lon)) {
        return false;
    }
    latitude = ns == 'N' ? lat : -lat;
    longitude = ew == 'E' ? lon : -lon;
    return latitude >= -90 && latitude <= 89 && longitude >= -180 && longitude <= 179;
}

} // namespace

std::optional<RawGrid> hgtGrid(const std::string& path) {
    if (!endsWithHgt(path)) {
        return std::nullopt;
    }
    const std::string name = std::filesystem::path(path).filename().string();
    int latitude = 0, longitude = 0;
    if (!cellOf(name.substr(0, name.size() - 4), latitude, longitude)) {
        fail(path, "an SRTM height file's name must begin with its south-west corner, such as N46W122.hgt "
                   "(latitude N or S 00-89, longitude E or W 000-179)");
    }
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) {
        fail(path, "cannot read: " + ec.message());
    }
    const auto bytes = static_cast<uint64_t>(size);
    const auto side = static_cast<uint64_t>(std::llround(std::sqrt(static_cast<double>(bytes / 2))));
    if (bytes < 8 || side * side * 2 != bytes || side > 0x7fffffffu) {
        fail(path, "an SRTM height file holds a square of 16-bit heights (1201 x 1201 or 3601 x 3601): " +
                       std::to_string(bytes) + " bytes is none");
    }
    RawGrid grid;
    RasterInfo& info = grid.info;
    info.width = info.height = static_cast<int>(side);
    info.channels = 1;
    info.type = SampleType::Int16;
    info.formatName = "hgt";
    info.nodata = -32768.0;
    Georeference g;
    g.projected = false;
    g.epsg = 4326;
    g.name = "WGS 84";
    g.semiMajorAxis = 6378137.0;
    g.flattening = 1.0 / 298.257223563;
    const double step = 1.0 / static_cast<double>(side - 1);
    // PixelIsArea coordinates: sample (col, row) is the point (lon + col step, lat + 1 - row step).
    g.pixelToCrs = {longitude - step / 2, step, 0.0, latitude + 1 + step / 2, 0.0, -step};
    g.pixelIsPoint = true;
    info.georeference = g;
    grid.layout.rowBytes = side * 2;
    grid.layout.pixelBytes = 2;
    grid.layout.bigEndian = true;
    return grid;
}

} // namespace pyramid
