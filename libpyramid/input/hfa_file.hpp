// The tree of an ERDAS Imagine file (HFA): the signature `EHFA_HEADER_TAG`, a header giving the
// root node and the dictionary (hfa_dictionary.hpp), and nodes (Ehfa_Entry: the next sibling,
// the first child, the data's place and size, a name of 64 bytes and a type of 32), each holding
// an instance of its type. Every place is checked against the file's size before it is read, and
// siblings that run in a loop are an error, each naming the file.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "formats/byte_source.hpp"
#include "libpyramid/input/hfa_dictionary.hpp"

namespace pyramid {

struct HfaNode {
    uint32_t next = 0, child = 0, data = 0, size = 0;
    std::string name, type;
};

class HfaFile {
public:
    // Null when `file` does not begin with the signature. Throws Error naming `path` when its
    // header or dictionary cannot be read.
    static std::unique_ptr<HfaFile> open(const std::string& path, std::shared_ptr<const ByteSource> file);

    const HfaDictionary& dictionary() const { return *dictionary_; }
    HfaNode root() const { return node(root_); }
    std::vector<HfaNode> children(const HfaNode& parent) const;
    std::optional<HfaNode> child(const HfaNode& parent, const std::string& name) const; // the first so named
    std::vector<uint8_t> data(const HfaNode& n) const; // at most 64 MB

private:
    HfaFile(std::string path, std::shared_ptr<const ByteSource> file);
    HfaNode node(uint32_t offset) const;

    std::string path_;
    std::shared_ptr<const ByteSource> file_;
    uint32_t root_ = 0;
    std::unique_ptr<HfaDictionary> dictionary_;
};

} // namespace pyramid
