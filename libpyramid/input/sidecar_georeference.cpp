#include "libpyramid/input/sidecar_georeference.hpp"

#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/esri_prj.hpp"
#include "libpyramid/input/gdal_band_metadata.hpp"
#include "libpyramid/input/geotiff_library.hpp"
#include "libpyramid/input/input_list_text.hpp"
#include "libpyramid/input/nodata_text.hpp"
#include "libpyramid/input/tiff_raster_info.hpp"
#include "libpyramid/input/vrt_xml.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

namespace fs = std::filesystem;
using input_list_detail::isSpace;
using input_list_detail::trim;

constexpr uintmax_t kMaxSidecarBytes = uintmax_t{16} << 20; // a PAM file with histograms stays far below

// The text of the sidecar at `path`, or nothing when there is no such regular file.
std::optional<std::string> readSidecar(const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        return std::nullopt;
    }
    const uintmax_t size = fs::file_size(path, ec);
    if (ec || size > kMaxSidecarBytes) {
        fail(path, ec ? "cannot read: " + ec.message() : "too large for a sidecar (" + std::to_string(size) + " bytes)");
    }
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in && !in.eof()) {
        fail(path, "cannot read");
    }
    return text;
}

// The names a world file of `path` may have, in the order they are tried.
std::vector<std::string> worldFileNames(const std::string& path) {
    const fs::path p(path);
    const std::string ext = p.extension().string(); // ".tif"
    const std::string stem = (p.parent_path() / p.stem()).string();
    std::vector<std::string> names;
    if (ext.size() >= 3) {
        const std::string shortName = std::string(1, ext[1]) + ext.back() + "w"; // "tfw"
        const std::string longName = ext.substr(1) + "w";                       // "tifw"
        for (const std::string& n : {shortName, longName}) {
            std::string lower = n, upper = n;
            for (char& c : lower) {
                c = lowerAscii(c);
            }
            for (char& c : upper) {
                c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
            }
            names.push_back(stem + "." + lower);
            names.push_back(stem + "." + upper);
        }
    }
    names.push_back(stem + ".wld");
    names.push_back(stem + ".WLD");
    return names;
}

// Numbers separated by white space (a world file) or commas (a PAM GeoTransform).
std::vector<double> numbersIn(const std::string& text, const std::string& where, const char* what) {
    std::vector<double> numbers;
    size_t k = 0;
    while (k < text.size()) {
        while (k < text.size() && (isSpace(text[k]) || text[k] == ',')) {
            ++k;
        }
        size_t end = k;
        while (end < text.size() && !isSpace(text[end]) && text[end] != ',') {
            ++end;
        }
        if (end > k) {
            const std::string token = text.substr(k, end - k);
            const std::optional<double> v = tryParseNumber(token);
            if (!v) {
                fail(where, std::string(what) + ": '" + token + "' is not a finite number");
            }
            numbers.push_back(*v);
        }
        k = end;
    }
    return numbers;
}

// ESRI's world file: x size, y rotation, x rotation, y size, then the centre of the top-left
// pixel; as a transform of pixel corners (PixelIsArea).
std::array<double, 6> worldFileTransform(const std::string& text, const std::string& where) {
    const std::vector<double> v = numbersIn(text, where, "world file");
    if (v.size() != 6) {
        fail(where, "a world file holds 6 numbers, not " + std::to_string(v.size()));
    }
    const double a = v[0], d = v[1], b = v[2], e = v[3], c = v[4], f = v[5];
    return {c - 0.5 * a - 0.5 * b, a, b, f - 0.5 * d - 0.5 * e, d, e};
}

struct PamBand {
    std::string nodata, scale, offset, unit;
};

struct Pam {
    std::string srs;
    std::optional<std::array<double, 6>> transform;
    std::vector<PamBand> bands; // by band number from 1 (index 0: band 1)
};

Pam readPam(const std::string& text, const std::string& where, int channels) {
    XmlElement root;
    try {
        root = parseXml(text);
    } catch (const MalformedXml& e) {
        fail(where, "malformed XML (" + e.problem + ")");
    }
    Pam pam;
    const auto textOf = [](const XmlElement& parent, const char* child) {
        const std::vector<const XmlElement*> found = parent.childrenNamed(child);
        return found.empty() ? std::string() : trim(found.front()->text);
    };
    pam.srs = textOf(root, "SRS");
    if (const std::string t = textOf(root, "GeoTransform"); !t.empty()) {
        const std::vector<double> v = numbersIn(t, where, "<GeoTransform>");
        if (v.size() != 6) {
            fail(where, "<GeoTransform> holds 6 numbers, not " + std::to_string(v.size()));
        }
        pam.transform = std::array<double, 6>{v[0], v[1], v[2], v[3], v[4], v[5]};
    }
    pam.bands.resize(static_cast<size_t>(std::max(channels, 0)));
    for (const XmlElement* band : root.childrenNamed("PAMRasterBand")) {
        const std::string* number = band->attribute("band");
        const std::optional<double> n = number ? tryParseNumber(trim(*number)) : std::optional<double>(1.0);
        if (!n || *n < 1.0 || *n > static_cast<double>(channels) || *n != static_cast<double>(static_cast<int>(*n))) {
            continue; // another band than the raster's, as GDAL ignores it
        }
        PamBand& b = pam.bands[static_cast<size_t>(*n) - 1];
        b.nodata = textOf(*band, "NoDataValue");
        b.scale = textOf(*band, "Scale");
        b.offset = textOf(*band, "Offset");
        b.unit = textOf(*band, "UnitType");
    }
    return pam;
}

// The text of FILE.prj (or FILE.PRJ) beside `path`, trimmed, and its name in `where`; nothing
// when there is none.
std::optional<std::string> prjText(const std::string& path, std::string& where) {
    for (const char* ext : {".prj", ".PRJ"}) {
        where = fs::path(path).replace_extension(ext).string();
        if (const std::optional<std::string> text = readSidecar(where)) {
            return trim(*text);
        }
    }
    return std::nullopt;
}

// The raster placed by `t` in the CRS that `wkt` (or an old-style .prj: esri_prj.hpp) names, read
// from `where`; nothing for a CRS of no
// EPSG code, or one that is not a projected or geographic CRS (the file is then unplaced, as it
// was without its sidecars: a planet's map of the Moon in an IAU CRS is still a whole globe).
std::optional<Georeference> placed(const std::string& wkt, std::array<double, 6> t, const std::string& where) {
    if (t[1] * t[5] - t[2] * t[4] == 0.0) {
        fail(where, "its transform is singular: it places no pixel");
    }
    int epsg = 0;
    if (const std::optional<OldStylePrj> old = readOldStylePrj(wkt)) {
        epsg = old->epsg;
        for (double& v : t) {
            v /= old->unitsPerCrsUnit;
        }
    } else {
        epsg = epsgOfWkt(wkt);
    }
    return placedInEpsgCrs(epsg, t, where);
}

} // namespace

namespace {
int identifiedByProj(const std::string& wkt);
} // namespace

int epsgOfWkt(const std::string& wkt) {
    // The root's own AUTHORITY["EPSG", "N"] (WKT1) or ID["EPSG", N] (WKT2): the last one at depth 1.
    int found = 0, depth = 0;
    for (size_t i = 0; i < wkt.size(); ++i) {
        const char c = wkt[i];
        if (c == '"') {
            const size_t close = wkt.find('"', i + 1);
            if (close == std::string::npos) {
                break;
            }
            i = close;
        } else if (c == '[' || c == '(') {
            ++depth;
        } else if (c == ']' || c == ')') {
            --depth;
        } else if (depth == 1 && std::isalpha(static_cast<unsigned char>(c)) &&
                   (i == 0 || !std::isalnum(static_cast<unsigned char>(wkt[i - 1])))) {
            size_t end = i;
            while (end < wkt.size() && (std::isalnum(static_cast<unsigned char>(wkt[end])) || wkt[end] == '_')) {
                ++end;
            }
            const std::string_view word(wkt.data() + i, end - i);
            if ((equalNoCase(word, "AUTHORITY") || equalNoCase(word, "ID")) && end < wkt.size() &&
                (wkt[end] == '[' || wkt[end] == '(')) {
                const size_t close = wkt.find_first_of("])", end);
                const std::string inside = wkt.substr(end + 1, close == std::string::npos ? 0 : close - end - 1);
                const size_t comma = inside.find(','); // the name, the code, then maybe a version or a URI
                const size_t next = comma == std::string::npos ? comma : inside.find(',', comma + 1);
                std::string name = trim(inside.substr(0, comma));
                std::string code = comma == std::string::npos ? "" : trim(inside.substr(comma + 1, next - comma - 1));
                const auto unquote = [](std::string& s) {
                    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') {
                        s = s.substr(1, s.size() - 2);
                    }
                };
                unquote(name);
                unquote(code);
                const std::optional<double> n = tryParseNumber(code);
                if (equalNoCase(name, "EPSG") && n && *n > 0.0 && *n < 1e6 && *n == static_cast<double>(static_cast<int>(*n))) {
                    found = static_cast<int>(*n);
                }
            }
            i = end - 1;
        }
    }
    if (found != 0) {
        return found;
    }
    // PROJ's identification, once per text in a process: a mosaic of a thousand tiles has a
    // thousand copies of one .prj, and each file is described before it is opened.
    static std::mutex mutex;
    static std::map<std::string, int> identified;
    const std::lock_guard lock(mutex);
    if (const auto it = identified.find(wkt); it != identified.end()) {
        return it->second;
    }
    const int code = identifiedByProj(wkt);
    identified.emplace(wkt, code);
    return code;
}

namespace {

// The EPSG code PROJ identifies a WKT CRS as (its first candidate, at a confidence of 70 % or
// more), or 0.
int identifiedByProj(const std::string& wkt) {
    std::string why;
    const GeoTiffLibrary* lib = geoTiffLibrary(why);
    if (!lib) {
        return 0;
    }
    const std::unique_ptr<PJ_CONTEXT, decltype(lib->projContextDestroy)> ctx(lib->projContextCreate(),
                                                                             lib->projContextDestroy);
    if (!ctx) {
        return 0;
    }
    auto destroy = [lib](PJ* p) { lib->projDestroy(p); };
    const std::unique_ptr<PJ, decltype(destroy)> crs(lib->projCreate(ctx.get(), wkt.c_str()), destroy);
    if (!crs) {
        return 0;
    }
    int* confidence = nullptr;
    PJ_OBJ_LIST* list = lib->projIdentify(ctx.get(), crs.get(), "EPSG", nullptr, &confidence);
    int code = 0;
    if (list && confidence && lib->projListGetCount(list) > 0 && confidence[0] >= 70) {
        const std::unique_ptr<PJ, decltype(destroy)> best(lib->projListGet(ctx.get(), list, 0), destroy);
        const char* text = best ? lib->projGetIdCode(best.get(), 0) : nullptr;
        const std::optional<double> n = text ? tryParseNumber(text) : std::nullopt;
        code = n && *n > 0.0 && *n < 1e6 ? static_cast<int>(*n) : 0;
    }
    if (list) {
        lib->projListDestroy(list);
    }
    if (confidence) {
        lib->projIntListDestroy(confidence);
    }
    return code;
}

} // namespace

std::optional<Georeference> placedInEpsgCrs(int epsg, const std::array<double, 6>& transform, const std::string& where) {
    if (transform[1] * transform[5] - transform[2] * transform[4] == 0.0) {
        fail(where, "its transform is singular: it places no pixel");
    }
    if (epsg == 0) {
        return std::nullopt;
    }
    Georeference g;
    try {
        g = georeferenceOfCrs("EPSG:" + std::to_string(epsg));
    } catch (const OptionError&) {
        return std::nullopt;
    }
    g.pixelToCrs = transform;
    g.pixelIsPoint = false;
    return g;
}

std::optional<Georeference> placedInWktCrs(const std::string& wkt, const std::array<double, 6>& transform,
                                           const std::string& where) {
    return placed(wkt, transform, where);
}

std::optional<Georeference> sidecarCrsPlacement(const std::string& path, const std::array<double, 6>& transform) {
    std::string where;
    if (const std::optional<std::string> prj = prjText(path, where)) {
        return placed(*prj, transform, where);
    }
    const std::string pamPath = path + ".aux.xml";
    const std::optional<std::string> pamText = readSidecar(pamPath);
    const Pam pam = pamText ? readPam(*pamText, pamPath, 1) : Pam{};
    return pam.srs.empty() ? std::nullopt : placed(pam.srs, transform, pamPath);
}

void addSidecarDescription(RasterInfo& info, const std::string& path) {
    const std::string pamPath = path + ".aux.xml";
    const std::optional<std::string> pamText = readSidecar(pamPath);
    const Pam pam = pamText ? readPam(*pamText, pamPath, info.channels) : Pam{};
    if (!info.georeference) {
        std::optional<std::array<double, 6>> transform = pam.transform;
        std::string where = pamPath, wkt = pam.srs;
        if (!transform) {
            for (const std::string& name : worldFileNames(path)) {
                if (const std::optional<std::string> text = readSidecar(name)) {
                    transform = worldFileTransform(*text, name);
                    where = name;
                    break;
                }
            }
        }
        if (transform && where != pamPath) {
            std::string prjName;
            if (const std::optional<std::string> prj = prjText(path, prjName)) {
                wkt = *prj;
            }
        }
        if (transform && !wkt.empty()) {
            info.georeference = placed(wkt, *transform, where);
        }
    }
    // The values' description, where the file gives none itself.
    if (pam.bands.empty()) {
        return;
    }
    if (!info.nodata && !pam.bands[0].nodata.empty()) {
        info.nodata = parseDeclaredNodata(pam.bands[0].nodata, pamPath, "NoDataValue");
    }
    if (info.scaling.empty()) {
        std::vector<BandValueTexts> texts;
        for (const PamBand& b : pam.bands) {
            texts.push_back({b.scale, b.offset, b.unit});
        }
        GdalBandMetadata m = bandMetadataOf(texts, pamPath, "");
        info.scaling = std::move(m.scaling);
        addUnitType(info, m.unitType);
    }
}

} // namespace pyramid
