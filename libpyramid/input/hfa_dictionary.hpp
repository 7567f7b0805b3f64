// The data dictionary of an ERDAS Imagine file (HFA, `.img`): the text that declares the layout
// of every type its nodes hold, and the reading of fields out of a node's bytes by it.
//
// A dictionary is a list of types, each `{FIELDS}NAME,`, ended by `.`. A field is
// `COUNT:[p|*]TYPE NAME,`: COUNT items of TYPE, inline, or behind a pointer (`p` or `*`: a count
// and an offset, 4 bytes each, then the items themselves, which follow at once). The item types:
// `c`/`C` 8-bit, `e` an enum (16 bits; `e3:a,b,c,` lists its names), `s`/`S` 16-bit, `l`/`L`/`t`
// 32-bit signed, unsigned and time, `f` float32, `d` float64, `o` an object of a type named next
// (`oEprj_Coordinate,`), `x` an object of a type declared in place (`x{...}NAME,`), `b` a block
// of base data (rows, columns, a pixel type and an object type, then the values). Everything is
// little-endian.
//
// Reading is bounded: every field is checked against the bytes that hold it, and a layout that
// runs past them, nests without end or names an unknown type is an error naming `where`.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pyramid {

struct HfaField {
    int count = 1;
    char pointer = 0; // 0: inline; 'p' or '*': a count and an offset, then the items
    char type = 0;
    std::string object; // the type of an 'o' or 'x' item
    std::string name;
};

// One field of an instance: its items' bytes and their count.
struct HfaValue {
    const HfaField* field = nullptr;
    std::span<const uint8_t> bytes; // from the first item to the end of the instance's bytes
    int count = 0;
};

class HfaDictionary {
public:
    // Parses `text` up to its final '.' (or its end). Throws Error naming `where` when it is no
    // dictionary.
    HfaDictionary(std::string_view text, std::string where);

    bool has(const std::string& type) const { return types_.count(type) != 0; }

    // Field `name` of the instance of `type` held in `data`; nothing when the type has no such
    // field. Throws naming `where` when the instance's bytes do not hold its layout.
    std::optional<HfaValue> field(const std::string& type, std::span<const uint8_t> data, const std::string& name) const;

    // Item `k` of a value, as a signed integer (c, C, e, s, S, l, L, t), a number (also f, d),
    // text (the value's c or C items up to the first NUL), or the bytes of an object (o, x).
    int64_t integer(const HfaValue& v, int k = 0) const;
    double number(const HfaValue& v, int k = 0) const;
    std::string text(const HfaValue& v) const;
    // Field `name` of `type` as a string: an Emif_String object (`x{0:pcstring,}Emif_String` or
    // `oEmif_String`); empty when there is none.
    std::string stringField(const std::string& type, std::span<const uint8_t> data, const std::string& name) const;
    std::span<const uint8_t> object(const HfaValue& v, int k = 0) const;
    // The bytes of an object item of fixed size (no pointer or base data inside), else nothing.
    std::optional<size_t> fixedSize(const std::string& type) const;

    // Base data (a `b` item): rows x columns values of a pixel type (0 u1 ... 10 f64), the
    // first of which is returned as a number; nothing for an empty one.
    std::optional<double> firstBaseValue(const HfaValue& v) const;

private:
    size_t parseType(std::string_view text, size_t at, int depth, std::string& name);
    size_t itemBytes(const HfaField& f, std::span<const uint8_t> data, size_t at, int depth) const;
    size_t fieldBytes(const HfaField& f, std::span<const uint8_t> data, size_t at, int depth) const;
    size_t objectBytes(const std::string& type, std::span<const uint8_t> data, size_t at, int depth) const;
    const std::vector<HfaField>& fieldsOf(const std::string& type) const;
    [[noreturn]] void damaged(const std::string& what) const;

    std::string where_;
    std::map<std::string, std::vector<HfaField>> types_;
};

// The bits of a pixel type (HFA's order: u1 u2 u4 u8 s8 u16 s16 u32 s32 f32 f64 c64 c128); 0 for
// another value.
int hfaTypeBits(int64_t type);

} // namespace pyramid
