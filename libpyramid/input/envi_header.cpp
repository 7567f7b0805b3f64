#include "libpyramid/input/envi_header.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/datum_epsg.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace fs = std::filesystem;

namespace {

constexpr uintmax_t kMaxHeaderBytes = 1 << 20; // wavelength lists of hyperspectral bands stay below

std::string trimmed(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t\r\n");
    const size_t b = s.find_last_not_of(" \t\r\n");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// The header of `path` (FILE.hdr, else PATH.hdr) when it is ENVI's, and its name.
std::optional<std::string> headerText(const std::string& path, std::string& name) {
    if (lowerAsciiText(fs::path(path).extension().string()) == ".hdr") {
        return std::nullopt;
    }
    for (const std::string& candidate : {fs::path(path).replace_extension(".hdr").string(), path + ".hdr"}) {
        std::error_code ec;
        if (!fs::is_regular_file(candidate, ec) || fs::file_size(candidate, ec) > kMaxHeaderBytes || ec) {
            continue;
        }
        std::ifstream in(candidate, std::ios::binary);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (text.rfind("ENVI", 0) == 0) {
            name = candidate;
            return text;
        }
    }
    return std::nullopt;
}

// `text` on one line (a braced value may span several), for a message.
std::string oneLine(std::string text) {
    for (char& c : text) {
        c = (c == '\n' || c == '\r' || c == '\t') ? ' ' : c;
    }
    return text;
}

// key (lower case, spaces kept) -> value (braces removed, on one line), a braced value across lines.
std::map<std::string, std::string> keysOf(const std::string& text) {
    std::map<std::string, std::string> keys;
    size_t at = text.find('\n');
    while (at != std::string::npos && at < text.size()) {
        const size_t eq = text.find('=', at);
        const size_t lineEnd = text.find('\n', at + 1);
        if (eq == std::string::npos) {
            break;
        }
        if (lineEnd != std::string::npos && lineEnd < eq) { // a line without a key
            at = lineEnd;
            continue;
        }
        const std::string key = lowerAsciiText(trimmed(text.substr(at, eq - at)));
        size_t valueStart = text.find_first_not_of(" \t", eq + 1);
        size_t end = 0;
        std::string value;
        if (valueStart != std::string::npos && text[valueStart] == '{') {
            end = text.find('}', valueStart);
            value = text.substr(valueStart + 1, (end == std::string::npos ? text.size() : end) - valueStart - 1);
            end = end == std::string::npos ? text.size() : text.find('\n', end);
        } else {
            end = text.find('\n', eq);
            value = text.substr(eq + 1, (end == std::string::npos ? text.size() : end) - eq - 1);
        }
        keys[key] = trimmed(oneLine(value));
        at = end;
    }
    return keys;
}

std::vector<std::string> items(const std::string& list) {
    std::vector<std::string> out;
    size_t start = 0;
    for (;;) {
        const size_t comma = list.find(',', start);
        out.push_back(trimmed(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
        if (comma == std::string::npos) {
            return out;
        }
        start = comma + 1;
    }
}

// The key's whole number, at least `least`; `otherwise` where it is not given (nothing: it must be).
uint64_t whole(const std::map<std::string, std::string>& keys, const std::string& key,
               std::optional<uint64_t> otherwise, uint64_t least, const std::string& where) {
    const auto it = keys.find(key);
    if (it == keys.end()) {
        if (!otherwise) {
            fail(where, "an ENVI header needs \"" + key + "\"");
        }
        return *otherwise;
    }
    const std::optional<double> v = tryParseNumber(it->second);
    if (!v || *v < static_cast<double>(least) || *v > 9.0e15 || *v != std::floor(*v)) {
        fail(where, key + " = " + it->second + " is no whole number from " + std::to_string(least));
    }
    return static_cast<uint64_t>(*v);
}

// The EPSG code of map info's own CRS (its projection name, zone, hemisphere and datum); 0 for another.
int epsgOfMapInfo(const std::vector<std::string>& m) {
    const std::string projection = lowerAsciiText(m[0]);
    const auto datumAt = [&](size_t k) { return k < m.size() ? lowerAsciiText(m[k]) : std::string(); };
    if (projection == "geographic lat/lon") {
        return geographicEpsg(namedDatum(datumAt(7).c_str()));
    }
    if (projection == "utm" && m.size() >= 10) {
        const std::optional<double> zone = tryParseNumber(m[7]);
        if (!zone || *zone < 1 || *zone > 60 || *zone != std::floor(*zone)) {
            return 0;
        }
        const int z = static_cast<int>(*zone);
        const bool south = lowerAsciiText(m[8]) == "south";
        return utmEpsg(z, south, namedDatum(datumAt(9).c_str()));
    }
    return 0;
}

} // namespace

std::optional<RawGrid> enviGrid(const std::string& path) {
    std::string where;
    const std::optional<std::string> text = headerText(path, where);
    if (!text) {
        return std::nullopt;
    }
    const std::map<std::string, std::string> keys = keysOf(*text);
    RawGrid grid;
    RasterInfo& info = grid.info;
    info.formatName = "envi";
    const uint64_t width = whole(keys, "samples", std::nullopt, 1, where);
    const uint64_t height = whole(keys, "lines", std::nullopt, 1, where);
    const uint64_t bands = whole(keys, "bands", 1, 1, where);
    if (width > 2147483647u || height > 2147483647u || bands > 65535u) {
        fail(where, "its size is beyond what is read (2^31 - 1 samples and lines, 65535 bands)");
    }
    info.width = static_cast<int>(width);
    info.height = static_cast<int>(height);
    info.channels = static_cast<int>(bands);
    const uint64_t type = whole(keys, "data type", std::nullopt, 1, where);
    const std::map<uint64_t, std::pair<SampleType, uint64_t>> types = {
        {1, {SampleType::UInt8, 1}},   {2, {SampleType::Int16, 2}},   {3, {SampleType::Int32, 4}},
        {4, {SampleType::Float32, 4}}, {5, {SampleType::Float64, 8}}, {12, {SampleType::UInt16, 2}},
        {13, {SampleType::UInt32, 4}}};
    const auto t = types.find(type);
    if (t == types.end()) {
        fail(where, "data type = " + std::to_string(type) +
                        ": 1, 2, 3, 4, 5, 12 and 13 are read (complex and 64-bit integer samples are not)");
    }
    info.type = t->second.first;
    const uint64_t size = t->second.second;
    RawGridLayout& l = grid.layout;
    l.offset = whole(keys, "header offset", 0, 0, where);
    const uint64_t order = whole(keys, "byte order", 0, 0, where);
    if (order > 1) {
        fail(where, "byte order = " + std::to_string(order) + ": 0 (little-endian) or 1 (big-endian)");
    }
    l.bigEndian = order == 1;
    const std::string interleave = keys.count("interleave") ? lowerAsciiText(keys.at("interleave")) : "bsq";
    if (interleave == "bsq") {
        l.pixelBytes = size;
        l.rowBytes = width * size;
        l.bandBytes = l.rowBytes * height;
    } else if (interleave == "bil") {
        l.pixelBytes = size;
        l.bandBytes = width * size;
        l.rowBytes = l.bandBytes * bands;
    } else if (interleave == "bip") {
        l.bandBytes = size;
        l.pixelBytes = size * bands;
        l.rowBytes = l.pixelBytes * width;
    } else {
        fail(where, "interleave = " + keys.at("interleave") + ": bsq, bil or bip are read");
    }
    if (const auto nodata = keys.find("data ignore value"); nodata != keys.end()) {
        const std::optional<double> v = tryParseNumber(nodata->second);
        if (!v) {
            fail(where, "data ignore value = " + nodata->second + " is not a number");
        }
        info.nodata = v;
    }
    if (const auto map = keys.find("map info"); map != keys.end()) {
        const std::vector<std::string> m = items(map->second);
        std::array<double, 7> n{}; // reference x, y, easting, northing, x size, y size
        for (size_t k = 1; k < 7; ++k) {
            const std::optional<double> v = k < m.size() ? tryParseNumber(m[k]) : std::nullopt;
            if (!v) {
                fail(where, "map info = {" + map->second + "}: items 2 to 7 must be numbers");
            }
            n[k] = *v;
        }
        for (const std::string& item : m) {
            if (lowerAsciiText(item).rfind("rotation", 0) == 0) {
                fail(where, "map info's rotation is not read: give the raster unrotated");
            }
        }
        const std::array<double, 6> transform = {n[3] - (n[1] - 1.0) * n[5], n[5], 0.0,
                                                 n[4] + (n[2] - 1.0) * n[6], 0.0, -n[6]};
        if (const auto wkt = keys.find("coordinate system string"); wkt != keys.end()) {
            info.georeference = placedInWktCrs(wkt->second, transform, where);
        } else if (const int epsg = epsgOfMapInfo(m); epsg != 0) {
            info.georeference = placedInEpsgCrs(epsg, transform, where);
        }
    }
    return grid;
}

} // namespace pyramid
