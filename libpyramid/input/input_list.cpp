#include "libpyramid/input/input_list.hpp"

#include <glob.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <string_view>
#include <utility>

#include "formats/error.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Text

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

std::string trim(std::string_view text) {
    size_t begin = 0, end = text.size();
    while (begin < end && isSpace(text[begin])) {
        ++begin;
    }
    while (end > begin && isSpace(text[end - 1])) {
        --end;
    }
    return std::string(text.substr(begin, end - begin));
}

bool isVrtName(const std::string& path) { return endsWithNoCase(path, ".vrt"); }

bool hasGlobCharacters(const std::string& text) { return text.find_first_of("*?[") != std::string::npos; }

// TEXT with glob(3)'s special characters escaped, so that it matches only itself.
std::string escapeGlob(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '*' || c == '?' || c == '[' || c == ']' || c == '\\') {
            out += '\\';
        }
        out += c;
    }
    return out;
}

// "ORIGIN: WHERE", or WHERE alone for a command-line argument (no origin).
std::string within(const std::string& origin, const std::string& where) {
    return origin.empty() ? where : origin + ": " + where;
}

// What PATH is (symlinks followed): not_found when nothing is there. Throws naming WHERE when
// the file system cannot tell (a directory on the way that cannot be searched).
fs::file_status statusOf(const std::string& path, const std::string& where) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (status.type() == fs::file_type::none) {
        fail(where, "cannot read: " + ec.message());
    }
    return status;
}

// PATH joined to DIRECTORY unless absolute; DIRECTORY empty leaves it as it is.
std::string resolveAgainst(const std::string& directory, const std::string& path) {
    return fs::path(path).is_absolute() ? path : (fs::path(directory) / path).string();
}

// ---------------------------------------------------------------------------------------------
// The XML a VRT is written in: elements, attributes in either quote, character data (with the
// five named entities and numeric references decoded, CDATA sections taken as they are);
// comments, processing instructions and a DOCTYPE without an internal subset skipped. Anything
// else that is not well-formed throws MalformedXml.

struct MalformedXml {
    size_t offset; // where in the text
    std::string problem;
};

struct XmlElement {
    std::string name;
    std::vector<std::pair<std::string, std::string>> attributes;
    std::vector<XmlElement> children;
    std::string text; // the character data directly inside it, concatenated

    // The attribute named NAME (ignoring case), or null.
    const std::string* attribute(std::string_view attributeName) const {
        for (const auto& [key, value] : attributes) {
            if (equalNoCase(key, attributeName)) {
                return &value;
            }
        }
        return nullptr;
    }
    // The children named NAME (ignoring case), in order.
    std::vector<const XmlElement*> childrenNamed(std::string_view childName) const {
        std::vector<const XmlElement*> found;
        for (const XmlElement& child : children) {
            if (equalNoCase(child.name, childName)) {
                found.push_back(&child);
            }
        }
        return found;
    }
};

class XmlParser {
public:
    explicit XmlParser(std::string_view text) : s_(text) {}

    // The root element of the whole text.
    XmlElement parseDocument() {
        if (s_.substr(0, 3) == "\xEF\xBB\xBF") {
            i_ = 3; // a UTF-8 byte order mark
        }
        skipMisc(true);
        if (i_ >= s_.size() || s_[i_] != '<') {
            failHere(i_ >= s_.size() ? "no root element" : "text before the root element");
        }
        XmlElement root = parseElement(0);
        skipMisc(false);
        if (i_ < s_.size()) {
            failHere("content after the root element");
        }
        return root;
    }

private:
    static constexpr int kMaxDepth = 256;

    [[noreturn]] void failAt(size_t offset, std::string problem) const {
        throw MalformedXml{offset, std::move(problem)};
    }
    [[noreturn]] void failHere(std::string problem) const { failAt(i_, std::move(problem)); }

    bool startsWith(std::string_view token) const { return s_.substr(i_, token.size()) == token; }

    void skipSpace() {
        while (i_ < s_.size() && isSpace(s_[i_])) {
            ++i_;
        }
    }

    // Moves past the next END; throws naming WHAT when there is none.
    void skipPast(std::string_view end, const char* what) {
        const size_t start = i_;
        const size_t at = s_.find(end, i_);
        if (at == std::string_view::npos) {
            failAt(start, std::string("unterminated ") + what);
        }
        i_ = at + end.size();
    }

    // Whitespace, comments and processing instructions (and, before the root, one DOCTYPE).
    void skipMisc(bool prolog) {
        for (;;) {
            skipSpace();
            if (startsWith("<!--")) {
                i_ += 4;
                skipPast("-->", "comment");
            } else if (startsWith("<?")) {
                i_ += 2;
                skipPast("?>", "processing instruction");
            } else if (prolog && startsWith("<!DOCTYPE")) {
                const size_t start = i_;
                while (i_ < s_.size() && s_[i_] != '>') {
                    if (s_[i_] == '[') {
                        failHere("a DOCTYPE with an internal subset is not read");
                    }
                    ++i_;
                }
                if (i_ >= s_.size()) {
                    failAt(start, "unterminated DOCTYPE");
                }
                ++i_;
            } else {
                return;
            }
        }
    }

    static bool isNameStart(char c) {
        const auto u = static_cast<unsigned char>(c);
        return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == ':' || u >= 0x80;
    }
    static bool isNameChar(char c) { return isNameStart(c) || (c >= '0' && c <= '9') || c == '-' || c == '.'; }

    std::string parseName(const char* what) {
        const size_t start = i_;
        if (i_ >= s_.size() || !isNameStart(s_[i_])) {
            failHere(std::string("expected ") + what);
        }
        while (i_ < s_.size() && isNameChar(s_[i_])) {
            ++i_;
        }
        return std::string(s_.substr(start, i_ - start));
    }

    static void appendUtf8(std::string& out, uint32_t c) {
        if (c < 0x80) {
            out += static_cast<char>(c);
        } else if (c < 0x800) {
            out += static_cast<char>(0xC0 | (c >> 6));
            out += static_cast<char>(0x80 | (c & 0x3F));
        } else if (c < 0x10000) {
            out += static_cast<char>(0xE0 | (c >> 12));
            out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (c & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (c >> 18));
            out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (c & 0x3F));
        }
    }

    // At '&': appends the character the reference stands for.
    void parseReference(std::string& out) {
        const size_t start = i_;
        const size_t semicolon = s_.find(';', i_);
        if (semicolon == std::string_view::npos || semicolon - i_ > 12) {
            failAt(start, "'&' that starts no entity (write &amp;)");
        }
        const std::string_view name = s_.substr(i_ + 1, semicolon - i_ - 1);
        i_ = semicolon + 1;
        if (name == "amp") {
            out += '&';
        } else if (name == "lt") {
            out += '<';
        } else if (name == "gt") {
            out += '>';
        } else if (name == "quot") {
            out += '"';
        } else if (name == "apos") {
            out += '\'';
        } else if (name.size() >= 2 && name[0] == '#') {
            const bool hex = name[1] == 'x';
            const std::string_view digits = name.substr(hex ? 2 : 1);
            uint32_t code = 0;
            bool valid = !digits.empty();
            for (char c : digits) {
                uint32_t d = 0;
                if (c >= '0' && c <= '9') {
                    d = static_cast<uint32_t>(c - '0');
                } else if (hex && c >= 'a' && c <= 'f') {
                    d = static_cast<uint32_t>(c - 'a' + 10);
                } else if (hex && c >= 'A' && c <= 'F') {
                    d = static_cast<uint32_t>(c - 'A' + 10);
                } else {
                    valid = false;
                    break;
                }
                code = code * (hex ? 16u : 10u) + d;
                if (code > 0x10FFFF) {
                    valid = false;
                    break;
                }
            }
            // The characters XML allows: tab, line feed, carriage return, and from space up,
            // without surrogates and U+FFFE, U+FFFF.
            valid = valid && (code == 0x9 || code == 0xA || code == 0xD || code >= 0x20) &&
                    !(code >= 0xD800 && code <= 0xDFFF) && code != 0xFFFE && code != 0xFFFF;
            if (!valid) {
                failAt(start, "'&" + std::string(name) + ";' is not a character XML allows");
            }
            appendUtf8(out, code);
        } else {
            failAt(start, "unknown entity '&" + std::string(name) + ";'");
        }
    }

    // At '<' of a start tag: the element, through its end tag.
    XmlElement parseElement(int depth) {
        if (depth >= kMaxDepth) {
            failHere("elements nested deeper than " + std::to_string(kMaxDepth));
        }
        const size_t open = i_;
        ++i_; // '<'
        XmlElement element;
        element.name = parseName("an element name");
        for (;;) {
            const size_t beforeSpace = i_;
            skipSpace();
            if (startsWith("/>")) {
                i_ += 2;
                return element;
            }
            if (startsWith(">")) {
                ++i_;
                break;
            }
            if (i_ >= s_.size()) {
                failAt(open, "<" + element.name + "> has an unterminated start tag");
            }
            if (i_ == beforeSpace) {
                failHere("expected whitespace, '>' or '/>' in <" + element.name + ">");
            }
            std::string key = parseName("an attribute name");
            skipSpace();
            if (!startsWith("=")) {
                failHere("attribute " + key + " of <" + element.name + "> has no '=' and value");
            }
            ++i_;
            skipSpace();
            if (i_ >= s_.size() || (s_[i_] != '"' && s_[i_] != '\'')) {
                failHere("attribute " + key + " of <" + element.name + "> has no quoted value");
            }
            const char quote = s_[i_++];
            const size_t valueStart = i_;
            std::string value;
            while (i_ < s_.size() && s_[i_] != quote) {
                if (s_[i_] == '<') {
                    failHere("'<' in the value of attribute " + key);
                }
                if (s_[i_] == '&') {
                    parseReference(value);
                } else {
                    value += s_[i_++];
                }
            }
            if (i_ >= s_.size()) {
                failAt(valueStart, "unterminated value of attribute " + key);
            }
            ++i_;                         // closing quote
            if (element.attribute(key)) { // names compared ignoring case, as they are read
                failAt(valueStart, "attribute " + key + " given twice in <" + element.name + ">");
            }
            element.attributes.emplace_back(std::move(key), std::move(value));
        }
        // Content, through the matching end tag.
        for (;;) {
            if (i_ >= s_.size()) {
                failAt(open, "<" + element.name + "> is never closed");
            }
            if (startsWith("</")) {
                const size_t close = i_;
                i_ += 2;
                const std::string name = parseName("an element name after '</'");
                skipSpace();
                if (!startsWith(">")) {
                    failHere("expected '>' to end </" + name + ">");
                }
                ++i_;
                if (name != element.name) {
                    failAt(close, "</" + name + "> closes <" + element.name + ">");
                }
                return element;
            }
            if (startsWith("<!--")) {
                i_ += 4;
                skipPast("-->", "comment");
            } else if (startsWith("<![CDATA[")) {
                i_ += 9;
                const size_t start = i_;
                skipPast("]]>", "CDATA section");
                element.text.append(s_.substr(start, i_ - 3 - start));
            } else if (startsWith("<?")) {
                i_ += 2;
                skipPast("?>", "processing instruction");
            } else if (startsWith("<!")) {
                failHere("unexpected '<!' in <" + element.name + ">");
            } else if (startsWith("<")) {
                element.children.push_back(parseElement(depth + 1));
            } else if (s_[i_] == '&') {
                parseReference(element.text);
            } else {
                element.text += s_[i_++];
            }
        }
    }

    std::string_view s_;
    size_t i_ = 0;
};

// ---------------------------------------------------------------------------------------------
// The expansion

// Files larger than this are not VRTs (a raster named .vrt by mistake is not read whole).
constexpr uintmax_t kMaxVrtBytes = uintmax_t{1} << 30;

class Expansion {
public:
    InputList result;

    // An argument or a list file's line: PATH as resolved; PATTERN the glob to expand when PATH
    // does not exist and holds glob characters (PATH with its resolved prefix escaped).
    void addArgument(const std::string& path, const std::string& pattern, const std::string& origin) {
        if (path.empty()) {
            fail(origin, "an empty argument names no file");
        }
        const fs::file_status status = statusOf(path, within(origin, path));
        if (fs::exists(status)) {
            addExisting(path, origin, true);
        } else if (hasGlobCharacters(path)) {
            addGlob(pattern, path, origin);
        } else {
            fail(within(origin, path), "no such file");
        }
    }

private:
    std::set<std::string> seenFiles_;
    std::set<std::string> seenVrtArguments_;
    std::set<std::string> readVrts_;
    std::vector<std::string> vrtsBeingRead_;

    // The key duplicates are found by: the path made absolute, normalised lexically.
    static std::string normalKey(const std::string& path) {
        fs::path p(path);
        if (p.is_relative()) {
            std::error_code ec;
            const fs::path cwd = fs::current_path(ec);
            if (!ec) {
                p = cwd / p;
            }
        }
        return p.lexically_normal().string();
    }

    // PATH exists (as named, or as a glob match): a directory, a VRT or a file.
    void addExisting(const std::string& path, const std::string& origin, bool named) {
        if (fs::is_directory(statusOf(path, within(origin, path)))) {
            addDirectory(path, origin);
        } else if (isVrtName(path)) {
            addVrt(path, origin, named);
        } else {
            addFile(path, origin);
        }
    }

    void addFile(const std::string& path, const std::string& origin) {
        const fs::file_status status = statusOf(path, within(origin, path));
        if (!fs::exists(status)) {
            fail(within(origin, path), "no such file");
        }
        if (!fs::is_regular_file(status)) {
            fail(within(origin, path), "not a regular file");
        }
        if (seenFiles_.insert(normalKey(path)).second) {
            result.paths.push_back(path);
        }
    }

    // The directory's .tif, .tiff and .hgt entries (no hidden ones, no subdirectories), by name.
    void addDirectory(const std::string& path, const std::string& origin) {
        const std::string where = within(origin, path);
        std::vector<std::string> names;
        std::error_code ec;
        fs::directory_iterator it(path, ec);
        if (ec) {
            fail(where, "cannot list the directory: " + ec.message());
        }
        for (; it != fs::directory_iterator(); it.increment(ec)) {
            const std::string name = it->path().filename().string();
            if (name.empty() || name[0] == '.' || !(endsWithNoCase(name, ".tif") || endsWithNoCase(name, ".tiff") ||
                                                     endsWithNoCase(name, ".hgt"))) {
                continue;
            }
            std::error_code typeError;
            if (it->is_directory(typeError)) {
                continue;
            }
            names.push_back(name);
        }
        if (ec) {
            fail(where, "cannot list the directory: " + ec.message());
        }
        if (names.empty()) {
            fail(where, "the directory holds no .tif, .tiff or .hgt file");
        }
        std::sort(names.begin(), names.end());
        for (const std::string& name : names) {
            addFile((fs::path(path) / name).string(), origin);
        }
    }

    void addGlob(const std::string& pattern, const std::string& shown, const std::string& origin) {
        glob_t matches{};
        const int rc = ::glob(pattern.c_str(), GLOB_NOSORT, nullptr, &matches);
        std::vector<std::string> found;
        if (rc == 0) {
            for (size_t k = 0; k < matches.gl_pathc; ++k) {
                found.emplace_back(matches.gl_pathv[k]);
            }
        }
        globfree(&matches);
        if (rc == GLOB_NOMATCH) {
            fail(within(origin, shown), "no file matches the pattern");
        }
        if (rc != 0) {
            fail(within(origin, shown), rc == GLOB_NOSPACE ? "out of memory expanding the pattern"
                                                           : "cannot read the directories of the pattern");
        }
        std::sort(found.begin(), found.end());
        for (const std::string& match : found) {
            addExisting(match, origin, true);
        }
    }

    static std::string readVrtText(const std::string& path, const std::string& where) {
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
    static std::string sourceFile(const XmlElement& source, const std::string& vrtDirectory, const std::string& where,
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
        const auto offX = rectangle("SrcRect", "xOff"), offY = rectangle("SrcRect", "yOff");
        if ((offX && *offX != 0.0) || (offY && *offY != 0.0)) {
            fail(where, of + "starts at pixel (" + numberText(offX.value_or(0.0)) + ", " + numberText(offY.value_or(0.0)) +
                            ") of the file (<SrcRect>); only whole files are read");
        }
        const auto sizeX = rectangle("SrcRect", "xSize"), sizeY = rectangle("SrcRect", "ySize");
        const auto fileX = rectangle("SourceProperties", "RasterXSize"), fileY = rectangle("SourceProperties", "RasterYSize");
        if ((sizeX && fileX && *sizeX != *fileX) || (sizeY && fileY && *sizeY != *fileY)) {
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

    // The files of a VRT's plain sources, in order of first appearance. NAMED: the VRT was named
    // by an argument, a list file's line or their glob (not found as another VRT's source).
    void addVrt(const std::string& path, const std::string& origin, bool named) {
        const std::string where = within(origin, path);
        const std::string key = normalKey(path);
        if (named && seenVrtArguments_.insert(key).second) {
            result.vrtSources.push_back(path);
        }
        if (std::find(vrtsBeingRead_.begin(), vrtsBeingRead_.end(), key) != vrtsBeingRead_.end()) {
            fail(where, "the VRT is, through its sources, a source of itself");
        }
        if (readVrts_.count(key)) {
            return; // its files are in the list already
        }
        const fs::file_status status = statusOf(path, where);
        if (!fs::exists(status)) {
            fail(where, "no such file");
        }
        if (!fs::is_regular_file(status)) {
            fail(where, "not a regular file");
        }
        const std::string text = readVrtText(path, where);
        XmlElement root;
        try {
            root = XmlParser(text).parseDocument();
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
            for (const XmlElement& source : child.children) {
                if (equalNoCase(source.name, "SimpleSource") || equalNoCase(source.name, "ComplexSource")) {
                    files.push_back(sourceFile(source, directory, where, band, bandNumber));
                } else if (equalNoCase(source.name, "MaskBand")) {
                    fail(where, band + ": a <MaskBand>: masks are not read");
                } else if (endsWithNoCase(source.name, "Source")) {
                    fail(where, band + ": a <" + source.name + ">: only <SimpleSource> and <ComplexSource> are read");
                }
            }
        }
        if (files.empty()) {
            fail(where, "no source file (no <SimpleSource> or <ComplexSource> in a <VRTRasterBand>)");
        }
        vrtsBeingRead_.push_back(key);
        for (const std::string& file : files) {
            if (isVrtName(file)) {
                addVrt(file, where, false);
            } else {
                addFile(file, where);
            }
        }
        vrtsBeingRead_.pop_back();
        readVrts_.insert(key);
    }
};

} // namespace

InputList expandInputs(const std::vector<std::string>& arguments, const std::string& listFile) {
    Expansion expansion;
    for (const std::string& argument : arguments) {
        expansion.addArgument(argument, argument, "");
    }
    if (!listFile.empty()) {
        const fs::file_status status = statusOf(listFile, listFile);
        if (!fs::exists(status)) {
            fail(listFile, "no such file");
        }
        if (!fs::is_regular_file(status)) {
            fail(listFile, "not a regular file (a list file names one input a line)");
        }
        std::ifstream in(listFile, std::ios::binary);
        if (!in) {
            fail(listFile, "cannot read");
        }
        const std::string directory = fs::path(listFile).parent_path().string();
        const std::string patternDirectory = escapeGlob(directory);
        std::string line;
        for (int number = 1; std::getline(in, line); ++number) {
            const std::string entry = trim(line);
            if (entry.empty() || entry[0] == '#') {
                continue;
            }
            const bool absolute = fs::path(entry).is_absolute();
            expansion.addArgument(absolute ? entry : resolveAgainst(directory, entry),
                                  absolute ? entry : resolveAgainst(patternDirectory, entry),
                                  listFile + ":" + std::to_string(number));
        }
        if (in.bad()) {
            fail(listFile, "cannot read");
        }
    }
    if (expansion.result.paths.empty()) {
        if (listFile.empty()) {
            throw Error("no input file given");
        }
        fail(listFile, "lists no file, and no other input is given");
    }
    return std::move(expansion.result);
}

} // namespace pyramid
