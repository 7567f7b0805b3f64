// The XML a GDAL VRT is written in (vrt_sources.hpp): elements, attributes in either quote,
// character data (with the five named entities and numeric references decoded, CDATA sections
// taken as they are); comments, processing instructions and a DOCTYPE without an internal
// subset skipped. Anything else that is not well-formed throws MalformedXml.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "libpyramid/support/text.hpp"

namespace pyramid {

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

// The root element of the whole text.
XmlElement parseXml(std::string_view text);

} // namespace pyramid
