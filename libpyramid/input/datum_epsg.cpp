#include "libpyramid/input/datum_epsg.hpp"

#include <string>

#include "libpyramid/support/text.hpp"

namespace pyramid {

NamedDatum namedDatum(const char* name) {
    std::string key;
    for (const char* c = name; *c; ++c) {
        if (*c != ' ' && *c != '-' && *c != '_') {
            key += lowerAscii(*c);
        }
    }
    if (key == "wgs84") {
        return NamedDatum::Wgs84;
    }
    if (key == "nad83" || key == "northamerica1983" || key == "northamerican1983") {
        return NamedDatum::Nad83;
    }
    if (key == "nad27" || key == "northamerica1927" || key == "northamerican1927") {
        return NamedDatum::Nad27;
    }
    return NamedDatum::Other;
}

int geographicEpsg(NamedDatum datum) {
    switch (datum) {
    case NamedDatum::Wgs84:
        return 4326;
    case NamedDatum::Nad83:
        return 4269;
    case NamedDatum::Nad27:
        return 4267;
    default:
        return 0;
    }
}

int utmEpsg(int zone, bool south, NamedDatum datum) {
    if (zone < 1 || zone > 60) {
        return 0;
    }
    if (datum == NamedDatum::Wgs84) {
        return (south ? 32700 : 32600) + zone;
    }
    if (datum == NamedDatum::Nad83 && !south && zone <= 23) {
        return 26900 + zone;
    }
    if (datum == NamedDatum::Nad27 && !south && zone <= 22) {
        return 26700 + zone;
    }
    return 0;
}

} // namespace pyramid
