#include "libpyramid/input/vrt_sources.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>

#include "formats/error.hpp"
#include "libpyramid/input/gdal_band_metadata.hpp"
#include "libpyramid/input/input_list_text.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/input/vrt_xml.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

namespace fs = std::filesystem;
using input_list_detail::resolveAgainst;
using input_list_detail::trim;

// Files larger than this are not VRTs (a raster named .vrt by mistake is not read whole).
constexpr uintmax_t kMaxVrtBytes = uintmax_t{1} << 30;

std::string readVrtText(const std::string& path, const std::string& where) {
    std::error_code ec;
    const uintmax_t size = fs::file_size(path, ec);
    if (ec) {
        fail(where, "cannot read: " + ec.message());
    }
    if (size > kMaxVrtBytes) {
        fail(where, "too large for a VRT (" + std::to_string(size) + " bytes)");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        fail(where, "cannot read");
    }
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) {
        fail(where, "cannot read");
    }
    return text;
}

// A source of a VRT band, checked: the file it names, resolved.
std::string sourceFile(const XmlElement& source, const std::string& vrtDirectory, const std::string& where,
                       const std::string& band, int bandNumber) {
    const std::string kind = "<" + source.name + ">";
    const std::vector<const XmlElement*> names = source.childrenNamed("SourceFilename");
    if (names.empty()) {
        fail(where, band + ": a " + kind + " without <SourceFilename>");
    }
    if (names.size() > 1) {
        fail(where, band + ": a " + kind + " with " + std::to_string(names.size()) + " <SourceFilename>");
    }
    const XmlElement& element = *names.front();
    const std::string name = trim(element.text);
    if (name.empty()) {
        fail(where, band + ": a " + kind + " with an empty <SourceFilename>");
    }
    if (startsWithNoCase(name, "/vsi") || name.find("://") != std::string::npos) {
        fail(where, band + ": source '" + name +
                        "' is not a plain file (GDAL virtual file systems and URLs are not read)");
    }
    bool relative = false;
    if (const std::string* flag = element.attribute("relativeToVRT")) {
        const std::string value = trim(*flag);
        if (value != "0" && value != "1") {
            fail(where, band + ": source '" + name + "' has relativeToVRT=\"" + *flag + "\", neither 0 nor 1");
        }
        relative = value == "1";
    }
    // The file is read as it is: its own band as the VRT's, all its pixels (a mosaic places
    // it by its georeferencing, so a <DstRect> of another size, as gdalbuildvrt writes for
    // files of other resolutions, changes nothing).
    const std::string of = band + ": the <" + source.name + "> of '" + name + "' ";
    for (const XmlElement* e : source.childrenNamed("SourceBand")) {
        const std::string value = trim(e->text);
        const std::optional<double> v = tryParseNumber(value);
        if (!v || *v != bandNumber) {
            fail(where, of + "takes its band " + value + " as band " + std::to_string(bandNumber) +
                            "; only bands as they are in the files are read (choose a DEM's band with --band)");
        }
    }
    const auto rectangle = [&](const char* child, const char* attribute) -> std::optional<double> {
        const std::vector<const XmlElement*> found = source.childrenNamed(child);
        if (found.empty()) {
            return std::nullopt;
        }
        const std::string* value = found.front()->attribute(attribute);
        return value ? tryParseNumber(trim(*value)) : std::nullopt;
    };
    // gdalbuildvrt trims a source's rectangle by less than a pixel where the file reaches past the
    // VRT's extent (rounded to whole VRT pixels): such a rectangle is the whole file, read whole.
    const auto offX = rectangle("SrcRect", "xOff"), offY = rectangle("SrcRect", "yOff");
    const auto withinAPixel = [](const std::optional<double>& off) { return !off || (*off >= 0.0 && *off < 1.0); };
    if (!withinAPixel(offX) || !withinAPixel(offY)) {
        fail(where, of + "starts at pixel (" + numberText(offX.value_or(0.0)) + ", " + numberText(offY.value_or(0.0)) +
                        ") of the file (<SrcRect>); only whole files are read");
    }
    const auto sizeX = rectangle("SrcRect", "xSize"), sizeY = rectangle("SrcRect", "ySize");
    const auto fileX = rectangle("SourceProperties", "RasterXSize"), fileY = rectangle("SourceProperties", "RasterYSize");
    const auto whole = [](const std::optional<double>& off, const std::optional<double>& size,
                          const std::optional<double>& file) {
        return !size || !file || (*size <= *file && off.value_or(0.0) + *size > *file - 1.0);
    };
    if (!whole(offX, sizeX, fileX) || !whole(offY, sizeY, fileY)) {
        fail(where, of + "takes " + numberText(sizeX.value_or(0.0)) + " x " + numberText(sizeY.value_or(0.0)) +
                        " of its " + numberText(fileX.value_or(0.0)) + " x " + numberText(fileY.value_or(0.0)) +
                        " pixels (<SrcRect>); only whole files are read");
    }
    if (equalNoCase(source.name, "ComplexSource")) {
        const auto numberIn = [&](const char* child, double expected) {
            for (const XmlElement* e : source.childrenNamed(child)) {
                const std::string value = trim(e->text);
                const std::optional<double> v = tryParseNumber(value);
                if (!v || *v != expected) {
                    fail(where,
                         of + "changes its values (" + child + " " + value + "); only unscaled sources are read");
                }
            }
        };
        numberIn("ScaleRatio", 1.0);
        numberIn("ScaleOffset", 0.0);
        for (const char* child : {"LUT", "Exponent", "ColorTableComponent"}) {
            if (!source.childrenNamed(child).empty()) {
                fail(where,
                     of + "changes its values (<" + std::string(child) + ">); only unscaled sources are read");
            }
        }
    }
    return relative ? resolveAgainst(vrtDirectory, name) : name;
}

// A band's <Scale>, <Offset> and <UnitType> (gdalbuildvrt copies its sources' scale and offset
// there) against what each of its source files declares itself, which the file's heights are read
// by (RasterSource::readFloat): a band that declares other values than a source is refused, since
// its heights would not be read as it says. Files are described only for a band that declares some.
void checkDeclaredValues(const XmlElement& band, const std::vector<std::string>& files, int bandNumber,
                         const std::string& where, const std::string& bandName) {
    const auto number = [&](const char* child, double none) {
        const std::vector<const XmlElement*> found = band.childrenNamed(child);
        if (found.empty()) {
            return none;
        }
        const std::string text = trim(found.front()->text);
        const std::optional<double> v = tryParseNumber(text);
        if (!v || (none == 1.0 && *v == 0.0)) {
            fail(where, bandName + ": <" + child + ">" + text + "</" + child + "> is not a " +
                            (none == 1.0 ? "finite non-zero number" : "finite number"));
        }
        return *v;
    };
    const ValueScaling declared{number("Scale", 1.0), number("Offset", 0.0)};
    const std::vector<const XmlElement*> units = band.childrenNamed("UnitType");
    const std::string unitText = units.empty() ? std::string() : trim(units.front()->text);
    const HeightUnit unit = heightUnitOfUnitType(unitText);
    if (declared.identity() && !(unit.metres > 0.0)) {
        return;
    }
    const auto b = static_cast<size_t>(bandNumber - 1);
    for (const std::string& file : files) {
        std::error_code ec;
        if (endsWithNoCase(file, ".vrt") || !fs::is_regular_file(file, ec)) {
            continue; // checked as it is expanded; refused where its caller finds it missing
        }
        const RasterInfo info = RasterSource::describe(file);
        const ValueScaling own = b < info.scaling.size() ? info.scaling[b] : ValueScaling{};
        if (!(own == declared)) {
            fail(where, bandName + " declares scale " + numberText(declared.scale) + " and offset " +
                            numberText(declared.offset) + " (<Scale>, <Offset>), but " + file + " declares scale " +
                            numberText(own.scale) + " and offset " + numberText(own.offset) +
                            ": only sources that declare the band's own are read");
        }
        if (unit.metres > 0.0) {
            const std::optional<Georeference>& g = info.georeference;
            const double metres = g && g->heightUnit && g->heightUnit->metres > 0.0 ? g->heightUnit->metres
                                  : g && g->projected                             ? g->unitInMetres
                                                                                  : 1.0;
            if (std::fabs(metres / unit.metres - 1.0) > 1e-12) {
                fail(where, bandName + " declares heights in " + unit.name + " (<UnitType>" + unitText + "</UnitType>), but " +
                                file + "'s are in units of " + numberText(metres) +
                                " m: only sources of the band's own unit are read");
            }
        }
    }
}

} // namespace

std::vector<std::string> vrtSourceFiles(const std::string& path, const std::string& where) {
    const std::string text = readVrtText(path, where);
    XmlElement root;
    try {
        root = parseXml(text);
    } catch (const MalformedXml& e) {
        const size_t offset = std::min(e.offset, text.size());
        const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n');
        fail(where, "malformed XML (line " + std::to_string(line) + ": " + e.problem + ")");
    }
    if (!equalNoCase(root.name, "VRTDataset")) {
        fail(where, "the root element is <" + root.name + ">, not <VRTDataset>");
    }
    if (const std::string* subClass = root.attribute("subClass")) {
        fail(where, "a " + *subClass + " (subClass): only plain VRTDatasets are read");
    }
    const std::string directory = fs::path(path).parent_path().string();
    std::vector<std::string> files;
    int bandNumber = 0;
    for (const XmlElement& child : root.children) {
        if (equalNoCase(child.name, "MaskBand")) {
            fail(where, "a <MaskBand>: masks are not read");
        }
        if (!equalNoCase(child.name, "VRTRasterBand")) {
            continue;
        }
        const std::string band = "band " + std::to_string(++bandNumber);
        if (const std::string* subClass = child.attribute("subClass")) {
            fail(where, band + " is a " + *subClass + " (subClass): derived and warped bands are not read");
        }
        const size_t first = files.size();
        for (const XmlElement& source : child.children) {
            if (equalNoCase(source.name, "SimpleSource") || equalNoCase(source.name, "ComplexSource")) {
                files.push_back(sourceFile(source, directory, where, band, bandNumber));
            } else if (equalNoCase(source.name, "MaskBand")) {
                fail(where, band + ": a <MaskBand>: masks are not read");
            } else if (endsWithNoCase(source.name, "Source")) {
                fail(where, band + ": a <" + source.name + ">: only <SimpleSource> and <ComplexSource> are read");
            }
        }
        checkDeclaredValues(child, std::vector<std::string>(files.begin() + static_cast<std::ptrdiff_t>(first), files.end()),
                            bandNumber, where, band);
    }
    if (files.empty()) {
        fail(where, "no source file (no <SimpleSource> or <ComplexSource> in a <VRTRasterBand>)");
    }
    return files;
}

} // namespace pyramid
