// The reader of vrt_xml.hpp: the text in one pass, elements nested at most 256 deep.
#include "libpyramid/input/vrt_xml.hpp"

#include <cstdint>

#include "libpyramid/input/input_list_text.hpp"

namespace pyramid {

namespace {

using input_list_detail::isSpace;

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

} // namespace

XmlElement parseXml(std::string_view text) { return XmlParser(text).parseDocument(); }

} // namespace pyramid
