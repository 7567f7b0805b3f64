#include "libpyramid/input/esri_prj.hpp"

#include <cctype>
#include <map>
#include <sstream>

#include "libpyramid/input/datum_epsg.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid {

namespace {

std::string upper(std::string s) {
    for (char& c : s) {
        c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    return s;
}

} // namespace

std::optional<OldStylePrj> readOldStylePrj(const std::string& text) {
    std::map<std::string, std::string> keys; // upper-case keyword -> its first value, upper case
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        std::istringstream words(line);
        std::string key, value;
        if (words >> key) {
            words >> value;
            keys.emplace(upper(key), upper(value));
        }
    }
    const auto projection = keys.find("PROJECTION");
    if (projection == keys.end()) {
        return std::nullopt;
    }
    const std::string datum = keys.count("DATUM") ? keys["DATUM"] : keys["SPHEROID"];
    OldStylePrj prj;
    if (projection->second == "GEOGRAPHIC") {
        prj.epsg = geographicEpsg(namedDatum(datum.c_str()));
        const std::string units = keys["UNITS"];
        if (units == "DS") {
            prj.unitsPerCrsUnit = 3600.0;
        } else if (units != "" && units != "DD") {
            prj.epsg = 0;
        }
    } else if (projection->second == "UTM") {
        const std::optional<double> zone = tryParseNumber(keys["ZONE"]);
        const std::optional<double> yshift = keys.count("YSHIFT") ? tryParseNumber(keys["YSHIFT"]) : 0.0;
        const std::string units = keys["UNITS"];
        if (!zone || *zone != static_cast<int>(*zone) || *zone == 0 || *zone < -60 || *zone > 60 || !yshift ||
            (units != "" && units != "METERS")) {
            return prj;
        }
        const int z = static_cast<int>(*zone < 0 ? -*zone : *zone);
        const bool south = *zone < 0 || *yshift == 10000000.0;
        prj.epsg = utmEpsg(z, south, namedDatum(datum.c_str()));
    }
    return prj;
}

} // namespace pyramid
