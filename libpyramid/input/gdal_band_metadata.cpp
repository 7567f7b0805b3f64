#include "libpyramid/input/gdal_band_metadata.hpp"

#include <tiffio.h>

#include <cmath>
#include <optional>

#include "formats/error.hpp"
#include "libpyramid/input/input_list_text.hpp"
#include "libpyramid/input/tiff_raster_info.hpp"
#include "libpyramid/input/vrt_xml.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

using input_list_detail::trim; // the XML text rules VRTs are read by

const char* const kTag = "GDAL metadata (TIFF tag 42112)";

// The band an item is of (0-based), or -1 for the dataset's or a malformed sample.
int sampleOf(const XmlElement& item) {
    const std::string* sample = item.attribute("sample");
    if (!sample) {
        return -1;
    }
    const std::optional<double> n = tryParseNumber(trim(*sample));
    return n && *n >= 0.0 && *n < 65536.0 && *n == std::floor(*n) ? static_cast<int>(*n) : -1;
}

double numberOf(const std::string& text, const char* what, int band, const std::string& path,
                const std::string& source) {
    const std::optional<double> v = tryParseNumber(text);
    const bool scale = std::string_view(what) == "scale";
    if (!v || (scale && *v == 0.0)) {
        fail(path, source + "band " + std::to_string(band + 1) + "'s " + what + " '" + text + "' is not " +
                       (scale ? "a finite non-zero number" : "a finite number"));
    }
    return *v;
}

} // namespace

GdalBandMetadata bandMetadataOf(const std::vector<BandValueTexts>& bands, const std::string& path,
                                const std::string& source) {
    GdalBandMetadata m;
    std::vector<ValueScaling> scaling(bands.size());
    bool scaled = false;
    for (size_t b = 0; b < bands.size(); ++b) {
        const int band = static_cast<int>(b);
        if (!bands[b].scale.empty()) {
            scaling[b].scale = numberOf(bands[b].scale, "scale", band, path, source);
            scaled = true;
        }
        if (!bands[b].offset.empty()) {
            scaling[b].offset = numberOf(bands[b].offset, "offset", band, path, source);
            scaled = true;
        }
        if (m.unitType.empty()) {
            m.unitType = bands[b].unit;
        }
    }
    if (scaled) {
        m.scaling = std::move(scaling);
    }
    return m;
}

GdalBandMetadata parseGdalMetadata(std::string_view xml, int bands, const std::string& path) {
    const std::string source = std::string(kTag) + ": ";
    XmlElement root;
    try {
        root = parseXml(xml);
    } catch (const MalformedXml& e) {
        fail(path, source + "malformed XML (" + e.problem + ")");
    }
    std::vector<BandValueTexts> texts(static_cast<size_t>(std::max(bands, 0)));
    for (const XmlElement* item : root.childrenNamed("Item")) {
        const std::string* role = item->attribute("role");
        const int band = sampleOf(*item);
        if (!role || band < 0 || band >= bands) {
            continue;
        }
        BandValueTexts& t = texts[static_cast<size_t>(band)];
        std::string* into = equalNoCase(*role, "scale")      ? &t.scale
                            : equalNoCase(*role, "offset")   ? &t.offset
                            : equalNoCase(*role, "unittype") ? &t.unit
                                                             : nullptr;
        if (into) {
            *into = trim(item->text);
        }
    }
    return bandMetadataOf(texts, path, source);
}

GdalBandMetadata readGdalBandMetadata(void* tif, int bands, const std::string& path) {
    const std::optional<std::string> text = tiffText(tif, TIFFTAG_GDAL_METADATA);
    return text ? parseGdalMetadata(*text, bands, path) : GdalBandMetadata{};
}

HeightUnit heightUnitOfUnitType(const std::string& text) {
    struct Known {
        const char* spelling;
        const char* name;
        double metres;
    };
    static const Known known[] = {
        {"m", "metre", 1.0},
        {"metre", "metre", 1.0},
        {"meter", "metre", 1.0},
        {"metres", "metre", 1.0},
        {"meters", "metre", 1.0},
        {"km", "kilometre", 1000.0},
        {"kilometre", "kilometre", 1000.0},
        {"kilometer", "kilometre", 1000.0},
        {"dm", "decimetre", 0.1},
        {"cm", "centimetre", 0.01},
        {"centimetre", "centimetre", 0.01},
        {"centimeter", "centimetre", 0.01},
        {"mm", "millimetre", 0.001},
        {"millimetre", "millimetre", 0.001},
        {"millimeter", "millimetre", 0.001},
        {"ft", "foot", 0.3048},
        {"foot", "foot", 0.3048},
        {"feet", "foot", 0.3048},
        {"international foot", "foot", 0.3048},
        {"ftUS", "US survey foot", 1200.0 / 3937.0},
        {"us-ft", "US survey foot", 1200.0 / 3937.0},
        {"US survey foot", "US survey foot", 1200.0 / 3937.0},
        {"US survey feet", "US survey foot", 1200.0 / 3937.0},
    };
    HeightUnit u;
    u.source = "UNITTYPE \"" + text + "\" (GDAL metadata)";
    for (const Known& k : known) {
        if (equalNoCase(text, k.spelling)) {
            u.name = k.name;
            u.metres = k.metres;
            return u;
        }
    }
    u.source += ", not a unit of length this reader knows";
    return u;
}

} // namespace pyramid
