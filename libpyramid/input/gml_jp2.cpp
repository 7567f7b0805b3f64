#include "libpyramid/input/gml_jp2.hpp"

#include <array>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string_view>

#include "formats/error.hpp"
#include "libpyramid/input/geotiff_library.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "libpyramid/input/vrt_xml.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid {

namespace {

// An element's name without its namespace prefix.
std::string_view localName(const XmlElement& e) {
    const std::string_view name = e.name;
    const size_t colon = name.rfind(':');
    return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

const XmlElement* findElement(const XmlElement& e, std::string_view name) {
    if (equalNoCase(localName(e), name)) {
        return &e;
    }
    for (const XmlElement& child : e.children) {
        if (const XmlElement* found = findElement(child, name)) {
            return found;
        }
    }
    return nullptr;
}

std::vector<const XmlElement*> childrenCalled(const XmlElement& e, std::string_view name) {
    std::vector<const XmlElement*> found;
    for (const XmlElement& child : e.children) {
        if (equalNoCase(localName(child), name)) {
            found.push_back(&child);
        }
    }
    return found;
}

// Two numbers separated by white space (or a comma, as gml:coordinates writes them).
std::optional<std::array<double, 2>> twoNumbers(std::string text) {
    for (char& c : text) {
        if (c == ',') {
            c = ' ';
        }
    }
    std::istringstream in(text);
    std::string a, b, rest;
    if (!(in >> a >> b) || (in >> rest)) {
        return std::nullopt;
    }
    const std::optional<double> x = tryParseNumber(a), y = tryParseNumber(b);
    if (!x || !y) {
        return std::nullopt;
    }
    return std::array<double, 2>{*x, *y};
}

// The EPSG code a srsName gives, and whether it gives the database's axis order (a URN or URL).
struct NamedCrs {
    int epsg = 0;
    bool authorityOrder = false;
};

NamedCrs crsOfName(std::string_view name) {
    NamedCrs crs;
    std::string_view code;
    if (startsWithNoCase(name, "urn:ogc:def:crs:EPSG:")) {
        code = name.substr(name.rfind(':') + 1); // urn:ogc:def:crs:EPSG:[version]:code
        crs.authorityOrder = true;
    } else if (name.find("opengis.net/def/crs/EPSG/") != std::string_view::npos) {
        code = name.substr(name.rfind('/') + 1);
        crs.authorityOrder = true;
    } else if (startsWithNoCase(name, "EPSG:")) {
        code = name.substr(5);
    }
    crs.epsg = readWholeNumber<int>(code).value_or(0);
    return crs;
}

// Whether the EPSG database's CRS `epsg` puts its north (or south) axis first: latitude and
// longitude, northing and easting.
bool northFirst(int epsg) {
    std::string why;
    const GeoTiffLibrary* lib = geoTiffLibrary(why);
    if (!lib) {
        return false;
    }
    const std::unique_ptr<PJ_CONTEXT, decltype(lib->projContextDestroy)> ctx(lib->projContextCreate(),
                                                                             lib->projContextDestroy);
    auto destroy = [lib](PJ* p) { lib->projDestroy(p); };
    const std::string code = std::to_string(epsg);
    const std::unique_ptr<PJ, decltype(destroy)> crs(
        ctx ? lib->projCreateFromDatabase(ctx.get(), "EPSG", code.c_str(), PJ_CATEGORY_CRS, 0, nullptr) : nullptr,
        destroy);
    const std::unique_ptr<PJ, decltype(destroy)> cs(crs ? lib->projCrsGetCoordinateSystem(ctx.get(), crs.get()) : nullptr,
                                                    destroy);
    const char* direction = nullptr;
    if (!cs || !lib->projCsGetAxisInfo(ctx.get(), cs.get(), 0, nullptr, nullptr, &direction, nullptr, nullptr, nullptr,
                                       nullptr)) {
        return false;
    }
    const std::string_view d = direction ? direction : "";
    return equalNoCase(d, "north") || equalNoCase(d, "south");
}

} // namespace

std::optional<Georeference> gmlJp2Placement(const std::string& gml, const std::string& path) {
    XmlElement root;
    try {
        root = parseXml(gml);
    } catch (const MalformedXml& e) {
        fail(path, "its GMLJP2 document is not well-formed XML (byte " + std::to_string(e.offset) + ": " + e.problem +
                       ")");
    }
    const XmlElement* grid = findElement(root, "RectifiedGrid");
    if (!grid) {
        return std::nullopt;
    }
    const std::vector<const XmlElement*> origins = childrenCalled(*grid, "origin");
    const std::vector<const XmlElement*> vectors = childrenCalled(*grid, "offsetVector");
    const XmlElement* point = origins.size() == 1 ? findElement(*origins[0], "Point") : nullptr;
    const XmlElement* pos = point ? findElement(*point, "pos") : nullptr;
    if (point && !pos) {
        pos = findElement(*point, "coordinates");
    }
    std::optional<std::array<double, 2>> origin = pos ? twoNumbers(pos->text) : std::nullopt;
    std::optional<std::array<double, 2>> column = vectors.size() == 2 ? twoNumbers(vectors[0]->text) : std::nullopt;
    std::optional<std::array<double, 2>> row = vectors.size() == 2 ? twoNumbers(vectors[1]->text) : std::nullopt;
    if (!origin || !column || !row) {
        fail(path, "its GMLJP2 RectifiedGrid needs an origin point and two offset vectors, each of two numbers");
    }
    const std::string* srs = point->attribute("srsName");
    for (const XmlElement* e : {grid, vectors[0]}) {
        if (!srs) {
            srs = e->attribute("srsName");
        }
    }
    const NamedCrs crs = crsOfName(srs ? *srs : "");
    if (crs.epsg <= 0) {
        return std::nullopt;
    }
    if (crs.authorityOrder && northFirst(crs.epsg)) {
        for (std::array<double, 2>* p : {&*origin, &*column, &*row}) {
            std::swap((*p)[0], (*p)[1]);
        }
    }
    // The origin is the first pixel's centre: its corner lies half a column and half a row back.
    const std::array<double, 6> t = {(*origin)[0] - 0.5 * ((*column)[0] + (*row)[0]), (*column)[0], (*row)[0],
                                     (*origin)[1] - 0.5 * ((*column)[1] + (*row)[1]), (*column)[1], (*row)[1]};
    return placedInEpsgCrs(crs.epsg, t, path);
}

} // namespace pyramid
