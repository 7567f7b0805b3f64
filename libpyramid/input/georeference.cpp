#include "libpyramid/input/georeference.hpp"

#include <geotiff/geokeys.h>
#include <geotiff/geovalues.h>
#include <tiffio.h>

#include <cmath>
#include <cstdarg>
#include <memory>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "formats/error.hpp"
#include "formats/tiff_memory.hpp"
#include "libpyramid/input/geotiff_library.hpp"
#include "libpyramid/input/geotiff_projection.hpp"
#include "libpyramid/input/height_unit.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"
#include "libpyramid/input/tiff_raster_info.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

std::string Georeference::crsText() const {
    return epsg > 0 ? "EPSG:" + std::to_string(epsg) + " (" + name + ")" : name;
}

double Georeference::heightsToGround() const {
    if (!heightUnit || !(heightUnit->metres > 0.0)) {
        return 1.0;
    }
    // The same unit as two databases' values of it (US survey foot: 1200/3937, to an ulp) reads
    // as stored.
    const double ratio = heightUnit->metres / (projected ? unitInMetres : 1.0);
    return std::fabs(ratio - 1.0) < 1e-12 ? 1.0 : ratio;
}

namespace {

// libgeotiff reports malformed keys through this; the reader says what it cannot use instead.
void ignoreGeoTiffMessage(GTIF*, int, const char*, ...) {}

// The GeoTIFF tags (libtiff), read before libgeotiff is needed.
constexpr uint32_t kTagPixelScale = 33550, kTagTiepoints = 33922, kTagTransformation = 34264;
constexpr uint32_t kTagKeyDirectory = 34735, kTagDoubleParams = 34736, kTagAsciiParams = 34737;

struct GeoTiffTags {
    std::vector<uint16_t> keys;
    std::vector<double> doubles;
    std::optional<std::string> text;
    std::vector<double> matrix, ties, scale;
};

std::string asciiKey(const GeoTiffLibrary& lib, GTIF* gtif, geokey_t key) {
    int size = 0;
    tagtype_t type{};
    const int count = lib.keyInfo(gtif, key, &size, &type);
    if (count <= 0 || type != TYPE_ASCII) {
        return {};
    }
    std::vector<char> text(static_cast<size_t>(count) + 1, '\0');
    lib.keyGet(gtif, key, text.data(), 0, count);
    std::string s(text.data());
    while (!s.empty() && (s.back() == '|' || s.back() == ' ')) {
        s.pop_back(); // GDAL ends citations with '|'
    }
    return s;
}

// The projection a citation names: a WKT or ESRI PE string's PROJECTION["Name"], or a PROJ
// string's +proj=name; empty when it names none.
std::string citedProjection(const std::string& citation) {
    const size_t wkt = citation.find("PROJECTION[\"");
    if (wkt != std::string::npos) {
        const size_t from = wkt + 12, to = citation.find('"', from);
        if (to != std::string::npos && to > from) {
            return citation.substr(from, to - from);
        }
    }
    const size_t proj = citation.find("+proj=");
    if (proj != std::string::npos) {
        const size_t from = proj + 6, to = citation.find_first_of(" |", from);
        return "+proj=" + citation.substr(from, to == std::string::npos ? std::string::npos : to - from);
    }
    return {};
}

// The EPSG name of a CRS code, from PROJ's database through libgeotiff.
std::string epsgName(const GeoTiffLibrary& lib, int code, bool projected) {
    char* name = nullptr;
    const int found = projected ? lib.pcsInfo(code, &name, nullptr, nullptr, nullptr)
                                : lib.gcsInfo(code, &name, nullptr, nullptr, nullptr);
    std::string s = found && name ? name : "";
    if (name) {
        lib.freeMemory(name);
    }
    return s;
}

// pixelToCrs from the ModelTransformation tag, or from one tiepoint and the pixel scale.
std::string readTransform(const GeoTiffTags& tags, Georeference& g) {
    const std::vector<double>& matrix = tags.matrix;
    const std::vector<double>& ties = tags.ties;
    const std::vector<double>& scale = tags.scale;
    auto& t = g.pixelToCrs;
    if (matrix.size() >= 16) {
        t = {matrix[3], matrix[0], matrix[1], matrix[7], matrix[4], matrix[5]};
    } else if (ties.size() >= 6 && scale.size() >= 2) {
        if (ties.size() > 6) {
            return "has " + std::to_string(ties.size() / 6) +
                   " tie points (ground control points), which place no regular grid; warp it to one first";
        }
        // Rows go down while y goes up: ModelPixelScale's y is positive for north-up images.
        t = {ties[3] - ties[0] * scale[0], scale[0], 0.0, ties[4] + ties[1] * scale[1], 0.0, -scale[1]};
    } else if (ties.size() >= 6) {
        return "has " + std::to_string(ties.size() / 6) +
               " tie point(s) and no pixel scale (ground control points); warp it to a regular grid first";
    } else {
        return "has GeoKeys but neither a ModelTransformation nor a tie point and pixel scale";
    }
    if (g.pixelIsPoint) {
        // The file's (0, 0) is the first pixel's centre, half a pixel inside its corner.
        t[0] -= 0.5 * (t[1] + t[2]);
        t[3] -= 0.5 * (t[4] + t[5]);
    }
    const double det = t[1] * t[5] - t[2] * t[4];
    for (const double v : t) {
        if (!std::isfinite(v)) {
            return "has a pixel-to-model transform that is not finite";
        }
    }
    if (det == 0.0) {
        return "has a singular pixel-to-model transform (a zero pixel size)";
    }
    return {};
}

// What the tags say, interpreted by libgeotiff; nullopt when it finds no definition in them.
std::optional<Georeference> georeferenceOf(GeoTiffTags tags) {
    Georeference g;
    std::string why;
    const GeoTiffLibrary* lib = geoTiffLibrary(why);
    if (!lib) {
        g.name = "a GeoTIFF CRS";
        g.problem = "has GeoKeys, but libgeotiff cannot be loaded (" + why + ")";
        return g;
    }
    // libgeotiff reads the keys from memory ("simple tags"), so that it never registers its
    // tags with libtiff (a process-wide change) nor opens the file again.
    const std::unique_ptr<ST_TIFF, void (*)(ST_TIFF*)> st(lib->stCreate(), lib->stDestroy);
    lib->stSetKey(st.get(), kTagKeyDirectory, static_cast<int>(tags.keys.size()), STT_SHORT, tags.keys.data());
    if (!tags.doubles.empty()) {
        lib->stSetKey(st.get(), kTagDoubleParams, static_cast<int>(tags.doubles.size()), STT_DOUBLE, tags.doubles.data());
    }
    std::string text = tags.text.value_or("");
    if (tags.text) {
        lib->stSetKey(st.get(), kTagAsciiParams, static_cast<int>(text.size()) + 1, STT_ASCII, text.data());
    }
    TIFFMethod methods{};
    lib->setSimpleTagsMethods(&methods);
    const std::unique_ptr<GTIF, void (*)(GTIF*)> gtif(lib->newWithMethods(st.get(), &methods, ignoreGeoTiffMessage, nullptr),
                                                      lib->free);
    if (!gtif) {
        return std::nullopt;
    }
    const std::unique_ptr<GTIFDefn, void (*)(GTIFDefn*)> defn(lib->allocDefn(), lib->freeDefn);
    if (!defn || !lib->getDefn(gtif.get(), defn.get()) || !defn->DefnSet) {
        return std::nullopt;
    }
    const GTIFDefn& d = *defn;
    unsigned short rasterType = RasterPixelIsArea;
    lib->keyGet(gtif.get(), GTRasterTypeGeoKey, &rasterType, 0, 1);
    g.pixelIsPoint = rasterType == RasterPixelIsPoint;
    g.problem = readTransform(tags, g);

    // PCS is a short in GTIFDefn; read the key itself for codes above 32767 (900913).
    unsigned short pcsKey = 0;
    const int pcs = lib->keyGet(gtif.get(), ProjectedCSTypeGeoKey, &pcsKey, 0, 1) == 1 ? pcsKey : d.PCS;
    g.projected = d.Model == ModelTypeProjected;
    if (d.Model != ModelTypeProjected && d.Model != ModelTypeGeographic) {
        // A CRS the GeoKeys cannot say (GDAL writes one as a user-defined model with its WKT or
        // ESRI string in a citation): named by the projection the citation gives.
        const std::string named = citedProjection(asciiKey(*lib, gtif.get(), GTCitationGeoKey) + " " +
                                                  asciiKey(*lib, gtif.get(), PCSCitationGeoKey));
        g.problem = d.Model == ModelTypeGeocentric ? "is in a geocentric (X, Y, Z) model, which places no surface"
                    : !named.empty()
                        ? "is in the projection " + named +
                              " (a user-defined CRS its GeoKeys cannot express), which libpyramid cannot place: "
                              "reproject it to a geographic or supported projected CRS"
                        : "has GeoKeys without a model type (projected or geographic)";
    }
    const int code = g.projected ? pcs : d.GCS;
    g.epsg = code > 0 && code != KvUserDefined ? code : 0;
    if (g.epsg > 0) {
        g.name = epsgName(*lib, g.epsg, g.projected);
    }
    if (g.name.empty()) {
        g.name = asciiKey(*lib, gtif.get(), g.projected ? PCSCitationGeoKey : GeogCitationGeoKey);
    }
    if (g.name.empty()) {
        g.name = asciiKey(*lib, gtif.get(), GTCitationGeoKey);
    }
    if (g.name.empty()) {
        g.name = g.projected ? "a user-defined projected CRS" : "a user-defined geographic CRS";
    }
    g.semiMajorAxis = d.SemiMajor;
    g.flattening = d.SemiMajor > 0.0 ? 1.0 - d.SemiMinor / d.SemiMajor : 0.0;
    if (!(g.semiMajorAxis > 0.0) && g.problem.empty()) {
        g.problem = "names no ellipsoid for its datum";
    }
    g.unitInMetres = d.UOMLengthInMeters > 0.0 ? d.UOMLengthInMeters : 1.0;
    // The angular unit matters to geographic coordinates, and to the parameters of a projection
    // given by keys (ProjCoordTransGeoKey): those of an EPSG code come in degrees.
    unsigned short coordTrans = 0;
    const bool parametersByKeys = lib->keyGet(gtif.get(), ProjCoordTransGeoKey, &coordTrans, 0, 1) == 1;
    std::string unitProblem;
    g.unitInDegrees = angularUnit(*lib, gtif.get(), d, unitProblem);
    if (!unitProblem.empty() && g.problem.empty() && (!g.projected || parametersByKeys)) {
        g.problem = unitProblem;
    }
    const bool userDefinedUnit = d.UOMAngle == KvUserDefined;
    // libgeotiff converts an EPSG prime meridian, and a user-defined longitude in an EPSG unit.
    g.primeMeridian = d.PMLongToGreenwich * (d.PM == KvUserDefined && userDefinedUnit ? g.unitInDegrees : 1.0);
    if (g.projected) {
        // libgeotiff up to 1.7.3 returns the angular parameters of keys in the unit they are in
        // (later versions convert those of EPSG units), and never converts a user-defined unit.
        const bool raw = parametersByKeys && (userDefinedUnit || LIBGEOTIFF_VERSION <= 1730);
        g.projection = projectionOf(d, pcs, parametersByKeys, raw ? g.unitInDegrees : 1.0);
    }
    g.heightUnit = readHeightUnit(*lib, gtif.get());
    return g;
}

} // namespace

namespace {

GeoTiffTags geoTiffTags(TIFF* tif) {
    GeoTiffTags tags;
    tags.keys = tiffShorts(tif, kTagKeyDirectory);
    tags.doubles = tiffDoubles(tif, kTagDoubleParams);
    tags.text = tiffText(tif, kTagAsciiParams);
    tags.matrix = tiffDoubles(tif, kTagTransformation);
    tags.ties = tiffDoubles(tif, kTagTiepoints);
    tags.scale = tiffDoubles(tif, kTagPixelScale);
    return tags;
}

std::optional<Georeference> georeferenceOfTags(GeoTiffTags tags) {
    if (tags.keys.size() < 4) {
        return std::nullopt; // no GeoKey directory: libgeotiff is not even loaded
    }
    return georeferenceOf(std::move(tags));
}

} // namespace

std::optional<Georeference> readGeoTiffGeoreference(const std::string& path) {
    GeoTiffTags tags;
    if (TIFF* tif = openTiffQuietly(path, "rm")) { // no map: only tags are read
        tags = geoTiffTags(tif);
        TIFFClose(tif);
    }
    return georeferenceOfTags(std::move(tags));
}

std::optional<Georeference> readGeoTiffGeoreference(const std::vector<uint8_t>& tiff) {
    MemoryStream stream;
    stream.data = tiff.data();
    stream.size = tiff.size();
    const TiffHandle handle(stream, "rm", static_cast<tmsize_t>(tiff.size()) + (1 << 16));
    return handle.get() ? georeferenceOfTags(geoTiffTags(handle.get())) : std::nullopt;
}

Georeference georeferenceOfCrs(const std::string& text) {
    const std::string_view prefix = "EPSG:";
    const std::optional<int> parsed = startsWithNoCase(text, prefix)
                                          ? readWholeNumber<int>(std::string_view(text).substr(prefix.size()))
                                          : std::nullopt;
    const int code = parsed.value_or(0);
    if (code <= 0 || code > 65534) {
        throw OptionError("crs", "'" + text + "' is not a CRS: give an EPSG code as EPSG:N (EPSG:4326, EPSG:32610)");
    }
    std::string why;
    const GeoTiffLibrary* lib = geoTiffLibrary(why);
    if (!lib) {
        throw OptionError("crs", text + " cannot be looked up: libgeotiff cannot be loaded (" + why + ")");
    }
    // The code's definition as a GeoTIFF would carry it: a key directory naming it alone, over
    // an identity pixel-to-CRS transform (one tie point at the origin, unit pixels).
    const bool projected = !epsgName(*lib, code, true).empty();
    if (!projected && epsgName(*lib, code, false).empty()) {
        throw OptionError("crs", text + " is neither a projected nor a geographic CRS of the EPSG database");
    }
    GeoTiffTags tags;
    const auto value = static_cast<uint16_t>(code);
    tags.keys = {1, 1, 0, 3,
                 GTModelTypeGeoKey, 0, 1, static_cast<uint16_t>(projected ? ModelTypeProjected : ModelTypeGeographic),
                 GTRasterTypeGeoKey, 0, 1, RasterPixelIsArea,
                 static_cast<uint16_t>(projected ? ProjectedCSTypeGeoKey : GeographicTypeGeoKey), 0, 1, value};
    tags.ties = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    tags.scale = {1.0, 1.0, 0.0};
    std::optional<Georeference> g = georeferenceOf(tags);
    if (!g || !g->problem.empty()) {
        throw OptionError("crs", text + " cannot be used: " + (g ? g->problem : "the EPSG database does not define it"));
    }
    return *g;
}

bool sameCrs(const Georeference& a, const Georeference& b) {
    return a.projected == b.projected && a.crsText() == b.crsText();
}

} // namespace pyramid
