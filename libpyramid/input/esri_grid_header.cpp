#include "libpyramid/input/esri_grid_header.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "formats/error.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace fs = std::filesystem;

namespace {

constexpr uintmax_t kMaxHeaderBytes = 64 << 10;

// The header beside `path`, and its name; nothing when there is none.
std::optional<std::string> headerText(const std::string& path, std::string& name) {
    const std::string ext = lowerAsciiText(fs::path(path).extension().string());
    if (ext == ".hdr" || ext.empty()) {
        return std::nullopt;
    }
    for (const char* e : {".hdr", ".HDR"}) {
        name = fs::path(path).replace_extension(e).string();
        std::error_code ec;
        if (!fs::is_regular_file(name, ec)) {
            continue;
        }
        const uintmax_t size = fs::file_size(name, ec);
        if (ec || size > kMaxHeaderBytes) {
            return std::nullopt; // no ESRI header is that large: another format's
        }
        std::ifstream in(name, std::ios::binary);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (!in && !in.eof()) {
            fail(name, "cannot read");
        }
        return text;
    }
    return std::nullopt;
}

EsriKeys keysOf(const std::string& text) {
    EsriKeys keys;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        std::istringstream words(line);
        std::string key, value;
        if (words >> key >> value) {
            keys.emplace(lowerAsciiText(key), value);
        }
    }
    return keys;
}

int positiveInt(const EsriKeys& keys, const std::string& key, const std::string& where) {
    const std::optional<double> v = esriNumber(keys, key, where);
    if (!v || *v < 1 || *v > 2147483647.0 || *v != std::floor(*v)) {
        fail(where, key + " must be a whole number from 1, not " + (v ? numberText(*v) : "missing"));
    }
    return static_cast<int>(*v);
}

uint64_t byteCount(const EsriKeys& keys, const std::string& key, uint64_t otherwise, const std::string& where) {
    const std::optional<double> v = esriNumber(keys, key, where);
    if (!v) {
        return otherwise;
    }
    if (*v < 0 || *v > 9.0e15 || *v != std::floor(*v)) {
        fail(where, key + " must be a whole number of bytes, not " + numberText(*v));
    }
    return static_cast<uint64_t>(*v);
}

} // namespace

std::optional<double> esriNumber(const EsriKeys& keys, const std::string& key, const std::string& where) {
    const auto it = keys.find(key);
    if (it == keys.end()) {
        return std::nullopt;
    }
    const std::optional<double> v = tryParseNumber(it->second);
    if (!v || !std::isfinite(*v)) {
        fail(where, key + " \"" + printableText(it->second) + "\" is not a number");
    }
    return v;
}

std::optional<std::array<double, 6>> esriTransform(const EsriKeys& keys, int rows, const std::string& where) {
    double dx = 1.0, dy = 1.0;
    if (const std::optional<double> c = esriNumber(keys, "cellsize", where)) {
        dx = dy = *c;
    }
    for (const auto& [key, size] : {std::pair<const char*, double*>{"xdim", &dx}, {"ydim", &dy}, {"dx", &dx}, {"dy", &dy}}) {
        if (const std::optional<double> v = esriNumber(keys, key, where)) {
            *size = *v;
        }
    }
    if (!(dx > 0.0) || !(dy > 0.0)) {
        fail(where, "the cell size must be positive, not " + numberText(dx <= 0.0 ? dx : dy));
    }
    const bool corner = keys.count("xllcorner") || keys.count("yllcorner");
    std::optional<double> x = esriNumber(keys, corner ? "xllcorner" : "xllcenter", where);
    std::optional<double> y = esriNumber(keys, corner ? "yllcorner" : "yllcenter", where);
    if (x && y) { // the lower-left pixel's corner or centre, to the upper-left pixel's corner
        const double left = corner ? *x : *x - dx / 2;
        const double bottom = corner ? *y : *y - dy / 2;
        return std::array<double, 6>{left, dx, 0.0, bottom + rows * dy, 0.0, -dy};
    }
    x = esriNumber(keys, "ulxmap", where);
    y = esriNumber(keys, "ulymap", where);
    if (x && y) { // the upper-left pixel's centre
        return std::array<double, 6>{*x - dx / 2, dx, 0.0, *y + dy / 2, 0.0, -dy};
    }
    return std::nullopt;
}

std::optional<RawGrid> esriHeaderGrid(const std::string& path) {
    std::string where;
    const std::optional<std::string> text = headerText(path, where);
    if (!text || lowerAsciiText(text->substr(0, 4)) == "envi") {
        return std::nullopt;
    }
    const EsriKeys keys = keysOf(*text);
    if (!keys.count("ncols") || !keys.count("nrows")) {
        return std::nullopt;
    }
    RawGrid grid;
    RasterInfo& info = grid.info;
    info.formatName = "ehdr";
    info.width = positiveInt(keys, "ncols", where);
    info.height = positiveInt(keys, "nrows", where);
    info.channels = keys.count("nbands") ? positiveInt(keys, "nbands", where) : 1;
    if (const std::optional<double> nodata = esriNumber(keys, "nodata", where)) {
        info.nodata = nodata;
    } else if (const std::optional<double> value = esriNumber(keys, "nodata_value", where)) {
        info.nodata = value;
    }
    // The type: NBITS and PIXELTYPE, else GDAL's guesses.
    std::optional<double> nbits = esriNumber(keys, "nbits", where);
    char pixelType = keys.count("pixeltype") ? static_cast<char>(std::toupper(static_cast<unsigned char>(keys.at("pixeltype")[0]))) : 'N';
    const double samples = static_cast<double>(info.width) * info.height * info.channels;
    if (!nbits && pixelType == 'N') {
        std::error_code ec;
        const auto perSample = static_cast<uint64_t>(static_cast<double>(fs::file_size(path, ec)) / samples);
        if (!ec && perSample > 0 && perSample != 3) {
            nbits = static_cast<double>(perSample * 8);
            pixelType = perSample == 4 ? 'F' : pixelType;
        }
    }
    if (pixelType == 'N' && lowerAsciiText(fs::path(path).extension().string()) == ".flt") {
        pixelType = 'F';
    }
    if (pixelType == 'N' && info.nodata && *info.nodata < 0) {
        pixelType = 'S';
    }
    const int bits = nbits ? static_cast<int>(*nbits) : (pixelType == 'F' ? 32 : 8);
    if (bits == 8) {
        info.type = pixelType == 'S' ? SampleType::Int8 : SampleType::UInt8;
    } else if (bits == 16) {
        info.type = pixelType == 'S' ? SampleType::Int16 : SampleType::UInt16;
    } else if (bits == 32) {
        info.type = pixelType == 'F' ? SampleType::Float32 : pixelType == 'S' ? SampleType::Int32 : SampleType::UInt32;
    } else if (bits == 64 && pixelType == 'F') {
        info.type = SampleType::Float64;
    } else {
        fail(where, "NBITS " + (nbits ? numberText(*nbits) : std::string("?")) + " with PIXELTYPE " +
                        (keys.count("pixeltype") ? keys.at("pixeltype") : std::string("unset")) +
                        ": samples of 8, 16 or 32 bits (64 for floats) are read");
    }
    // Where each sample lies.
    const uint64_t size = static_cast<uint64_t>(bits / 8);
    const auto width = static_cast<uint64_t>(info.width), bands = static_cast<uint64_t>(info.channels);
    const std::string layout = keys.count("layout") ? lowerAsciiText(keys.at("layout")) : "bil";
    RawGridLayout& l = grid.layout;
    l.offset = byteCount(keys, "skipbytes", 0, where);
    const std::string order = keys.count("byteorder") ? lowerAsciiText(keys.at("byteorder")) : "m";
    l.bigEndian = !(order[0] == 'i' || order[0] == 'l');
    if (layout == "bil") {
        l.pixelBytes = size;
        l.bandBytes = byteCount(keys, "bandrowbytes", width * size, where);
        l.rowBytes = byteCount(keys, "totalrowbytes", l.bandBytes * bands, where);
    } else if (layout == "bip") {
        l.bandBytes = size;
        l.pixelBytes = size * bands;
        l.rowBytes = byteCount(keys, "totalrowbytes", width * l.pixelBytes, where);
    } else if (layout == "bsq") {
        l.pixelBytes = size;
        l.rowBytes = byteCount(keys, "bandrowbytes", width * size, where);
        l.bandBytes = l.rowBytes * static_cast<uint64_t>(info.height) + byteCount(keys, "bandgapbytes", 0, where);
    } else {
        fail(where, "LAYOUT " + keys.at("layout") + ": BIL, BIP or BSQ are read");
    }
    const uint64_t rowSpan = layout == "bil" ? (bands - 1) * l.bandBytes + width * size : width * l.pixelBytes;
    if (l.rowBytes < rowSpan || (layout == "bil" && l.bandBytes < width * size)) {
        fail(where, "its row sizes (BANDROWBYTES, TOTALROWBYTES) are smaller than its rows' samples");
    }
    if (const std::optional<std::array<double, 6>> t = esriTransform(keys, info.height, where)) {
        info.georeference = sidecarCrsPlacement(path, *t);
    }
    return grid;
}

} // namespace pyramid
