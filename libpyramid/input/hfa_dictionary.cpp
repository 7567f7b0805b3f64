#include "libpyramid/input/hfa_dictionary.hpp"

#include <cstring>

#include "formats/error.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

constexpr int kMaxDepth = 8; // objects within objects: the dictionaries nest two or three deep

uint32_t u32(std::span<const uint8_t> d, size_t at) {
    return uint32_t{d[at]} | (uint32_t{d[at + 1]} << 8) | (uint32_t{d[at + 2]} << 16) | (uint32_t{d[at + 3]} << 24);
}

uint16_t u16(std::span<const uint8_t> d, size_t at) { return static_cast<uint16_t>(d[at] | (d[at + 1] << 8)); }

// The bytes of one plain item; 0 for an object, base data or an unknown type.
size_t plainBytes(char type) {
    switch (type) {
    case 'c':
    case 'C':
        return 1;
    case 'e':
    case 's':
    case 'S':
        return 2;
    case 'l':
    case 'L':
    case 't':
    case 'f':
        return 4;
    case 'd':
        return 8;
    default:
        return 0;
    }
}

} // namespace

int hfaTypeBits(int64_t type) {
    static constexpr int kBits[] = {1, 2, 4, 8, 8, 16, 16, 32, 32, 32, 64, 64, 128};
    return type >= 0 && type < 13 ? kBits[type] : 0;
}

HfaDictionary::HfaDictionary(std::string_view text, std::string where) : where_(std::move(where)) {
    size_t at = 0;
    while (at < text.size() && text[at] != '.') {
        if (text[at] == '\n' || text[at] == '\r' || text[at] == ' ') {
            ++at;
            continue;
        }
        std::string name;
        at = parseType(text, at, 0, name);
    }
    if (types_.empty()) {
        damaged("its dictionary declares no type");
    }
}

size_t HfaDictionary::parseType(std::string_view text, size_t at, int depth, std::string& name) {
    const auto expect = [&](char c) {
        if (at >= text.size() || text[at] != c) {
            damaged(std::string("its dictionary lacks a '") + c + "' at byte " + std::to_string(at));
        }
        ++at;
    };
    const auto word = [&](char end) {
        const size_t stop = text.find(end, at);
        if (stop == std::string_view::npos) {
            damaged("its dictionary ends within a name");
        }
        std::string w(text.substr(at, stop - at));
        at = stop + 1;
        return w;
    };
    const auto number = [&] {
        int n = 0;
        const size_t start = at;
        while (at < text.size() && text[at] >= '0' && text[at] <= '9' && n < 1000000) {
            n = n * 10 + (text[at++] - '0');
        }
        if (at == start) {
            damaged("its dictionary lacks a count at byte " + std::to_string(at));
        }
        return n;
    };
    if (depth > kMaxDepth) {
        damaged("its dictionary nests types too deep");
    }
    expect('{');
    std::vector<HfaField> fields;
    while (at < text.size() && text[at] != '}') {
        HfaField f;
        f.count = number();
        expect(':');
        if (at < text.size() && (text[at] == 'p' || text[at] == '*')) {
            f.pointer = text[at++];
        }
        if (at >= text.size()) {
            damaged("its dictionary ends within a field");
        }
        f.type = text[at++];
        if (f.type == 'e') {
            const int values = number();
            expect(':');
            for (int k = 0; k < values; ++k) {
                word(',');
            }
        } else if (f.type == 'o') {
            f.object = word(',');
        } else if (f.type == 'x') {
            at = parseType(text, at, depth + 1, f.object);
        } else if (plainBytes(f.type) == 0 && f.type != 'b') {
            damaged("its dictionary names an unknown type '" + printableText(std::string_view(&text[at - 1], 1)) + "'");
        }
        f.name = word(',');
        fields.push_back(std::move(f));
    }
    expect('}');
    name = word(',');
    types_.emplace(name, std::move(fields)); // the first declaration of a name holds
    return at;
}

const std::vector<HfaField>& HfaDictionary::fieldsOf(const std::string& type) const {
    const auto it = types_.find(type);
    if (it == types_.end()) {
        damaged("its dictionary does not declare the type \"" + printableText(type) + "\"");
    }
    return it->second;
}

void HfaDictionary::damaged(const std::string& what) const {
    fail(where_, "its ERDAS Imagine structure is damaged: " + what);
}

size_t HfaDictionary::itemBytes(const HfaField& f, std::span<const uint8_t> data, size_t at, int depth) const {
    if (const size_t bytes = plainBytes(f.type)) {
        return bytes;
    }
    if (f.type == 'o' || f.type == 'x') {
        return objectBytes(f.object, data, at, depth + 1);
    }
    // Base data: rows, columns, pixel type, object type, then the values.
    if (at + 12 > data.size()) {
        damaged("a block of base data runs past its node");
    }
    const uint64_t values = uint64_t{u32(data, at)} * uint64_t{u32(data, at + 4)};
    const int bits = hfaTypeBits(u16(data, at + 8));
    if (bits == 0 || values > data.size() * uint64_t{8}) {
        damaged("a block of base data has an unknown type or more values than its node holds");
    }
    return 12 + static_cast<size_t>((values * static_cast<uint64_t>(bits) + 7) / 8);
}

size_t HfaDictionary::fieldBytes(const HfaField& f, std::span<const uint8_t> data, size_t at, int depth) const {
    size_t count = static_cast<size_t>(f.count);
    size_t pos = at;
    if (f.pointer) {
        if (at + 8 > data.size()) {
            damaged("field " + f.name + " runs past its node");
        }
        count = u32(data, at);
        pos += 8;
    }
    if (count > data.size() - std::min(pos, data.size())) { // every item takes a byte or more
        damaged("field " + f.name + " holds more items than its node has bytes");
    }
    for (size_t k = 0; k < count; ++k) {
        pos += itemBytes(f, data, pos, depth);
        if (pos > data.size()) {
            damaged("field " + f.name + " runs past its node");
        }
    }
    return pos - at;
}

size_t HfaDictionary::objectBytes(const std::string& type, std::span<const uint8_t> data, size_t at, int depth) const {
    if (depth > kMaxDepth) {
        damaged("its objects nest too deep");
    }
    size_t pos = at;
    for (const HfaField& f : fieldsOf(type)) {
        pos += fieldBytes(f, data, pos, depth);
    }
    return pos - at;
}

std::optional<size_t> HfaDictionary::fixedSize(const std::string& type) const {
    size_t bytes = 0;
    for (const HfaField& f : fieldsOf(type)) {
        const size_t item = plainBytes(f.type);
        if (f.pointer || item == 0) {
            return std::nullopt;
        }
        bytes += item * static_cast<size_t>(f.count);
    }
    return bytes;
}

std::optional<HfaValue> HfaDictionary::field(const std::string& type, std::span<const uint8_t> data,
                                             const std::string& name) const {
    size_t at = 0;
    for (const HfaField& f : fieldsOf(type)) {
        if (f.name == name) {
            HfaValue v;
            v.field = &f;
            v.count = f.count;
            size_t start = at;
            if (f.pointer) {
                if (at + 8 > data.size()) {
                    damaged("field " + name + " runs past its node");
                }
                const uint32_t count = u32(data, at);
                if (count > data.size()) {
                    damaged("field " + name + " holds more items than its node has bytes");
                }
                v.count = static_cast<int>(count);
                start += 8;
            }
            v.bytes = data.subspan(std::min(start, data.size()));
            return v;
        }
        at += fieldBytes(f, data, at, 0);
    }
    return std::nullopt;
}

int64_t HfaDictionary::integer(const HfaValue& v, int k) const {
    const size_t size = plainBytes(v.field->type);
    const size_t at = static_cast<size_t>(k) * size;
    if (k < 0 || k >= v.count || size == 0 || size > 4 || v.field->type == 'f' || at + size > v.bytes.size()) {
        damaged("field " + v.field->name + " is no integer, or runs past its node");
    }
    switch (v.field->type) {
    case 'c':
        return static_cast<int8_t>(v.bytes[at]);
    case 'C':
        return v.bytes[at];
    case 's':
        return static_cast<int16_t>(u16(v.bytes, at));
    case 'e':
    case 'S':
        return u16(v.bytes, at);
    case 'l':
        return static_cast<int32_t>(u32(v.bytes, at));
    default:
        return u32(v.bytes, at);
    }
}

double HfaDictionary::number(const HfaValue& v, int k) const {
    const size_t at = static_cast<size_t>(k) * plainBytes(v.field->type);
    if (v.field->type == 'f' && k >= 0 && k < v.count && at + 4 <= v.bytes.size()) {
        float f;
        const uint32_t bits = u32(v.bytes, at);
        std::memcpy(&f, &bits, 4);
        return f;
    }
    if (v.field->type == 'd' && k >= 0 && k < v.count && at + 8 <= v.bytes.size()) {
        const uint64_t bits = uint64_t{u32(v.bytes, at)} | (uint64_t{u32(v.bytes, at + 4)} << 32);
        double d;
        std::memcpy(&d, &bits, 8);
        return d;
    }
    return static_cast<double>(integer(v, k));
}

std::string HfaDictionary::text(const HfaValue& v) const {
    if (v.field->type != 'c' && v.field->type != 'C') {
        damaged("field " + v.field->name + " is no text");
    }
    const size_t n = std::min(static_cast<size_t>(v.count), v.bytes.size());
    const auto* begin = reinterpret_cast<const char*>(v.bytes.data());
    return std::string(begin, strnlen(begin, n));
}

std::span<const uint8_t> HfaDictionary::object(const HfaValue& v, int k) const {
    if ((v.field->type != 'o' && v.field->type != 'x') || k < 0 || k >= v.count) {
        damaged("field " + v.field->name + " has no object " + std::to_string(k));
    }
    size_t at = 0;
    if (const std::optional<size_t> size = fixedSize(v.field->object)) {
        at = static_cast<size_t>(k) * *size;
    } else {
        for (int j = 0; j < k; ++j) {
            at += objectBytes(v.field->object, v.bytes, at, 1);
        }
    }
    if (at > v.bytes.size()) {
        damaged("field " + v.field->name + " runs past its node");
    }
    return v.bytes.subspan(at);
}

std::optional<double> HfaDictionary::firstBaseValue(const HfaValue& v) const {
    if (v.field->type != 'b' || v.count < 1 || v.bytes.size() < 12) {
        damaged("field " + v.field->name + " holds no base data");
    }
    const std::span<const uint8_t> d = v.bytes;
    const uint32_t rows = u32(d, 0), columns = u32(d, 4);
    const int type = u16(d, 8);
    const int bits = hfaTypeBits(type);
    if (rows == 0 || columns == 0) {
        return std::nullopt;
    }
    if (bits == 0 || 12 + static_cast<size_t>((bits + 7) / 8) > d.size()) {
        damaged("field " + v.field->name + "'s base data runs past its node");
    }
    const uint32_t w = bits >= 32 ? u32(d, 12) : 0;
    switch (type) {
    case 0:
    case 1:
    case 2:
        return d[12] & ((1 << bits) - 1);
    case 3:
        return d[12];
    case 4:
        return static_cast<int8_t>(d[12]);
    case 5:
        return u16(d, 12);
    case 6:
        return static_cast<int16_t>(u16(d, 12));
    case 7:
        return w;
    case 8:
        return static_cast<int32_t>(w);
    case 9: {
        float f;
        std::memcpy(&f, &w, 4);
        return f;
    }
    case 10: {
        const uint64_t bits64 = uint64_t{w} | (uint64_t{u32(d, 16)} << 32);
        double x;
        std::memcpy(&x, &bits64, 8);
        return x;
    }
    default:
        return std::nullopt; // complex: no nodata this reader takes
    }
}

std::string HfaDictionary::stringField(const std::string& type, std::span<const uint8_t> data,
                                       const std::string& name) const {
    const std::optional<HfaValue> v = field(type, data, name);
    if (!v || v->count < 1 || (v->field->type != 'x' && v->field->type != 'o')) {
        return {};
    }
    const std::optional<HfaValue> s = field(v->field->object, object(*v), "string");
    return s ? text(*s) : std::string();
}

} // namespace pyramid
