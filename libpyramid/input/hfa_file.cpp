#include "libpyramid/input/hfa_file.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <set>

#include "formats/error.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

constexpr char kSignature[16] = "EHFA_HEADER_TAG";
constexpr uint32_t kMaxNodeBytes = uint32_t{64} << 20; // a node's data: a layer's block list is far less
constexpr uint64_t kMaxDictionaryBytes = uint64_t{1} << 20;
constexpr size_t kMaxNodes = 100000; // the children of one node
constexpr size_t kEntryBytes = 120;  // an Ehfa_Entry up to its type (its modTime is not read)

uint32_t le32(const uint8_t* b) {
    return uint32_t{b[0]} | (uint32_t{b[1]} << 8) | (uint32_t{b[2]} << 16) | (uint32_t{b[3]} << 24);
}

} // namespace

std::unique_ptr<HfaFile> HfaFile::open(const std::string& path, std::shared_ptr<const ByteSource> file) {
    std::array<char, 16> tag{};
    if (file->size() < 20) {
        return nullptr;
    }
    file->readAt(0, tag.data(), tag.size());
    if (std::memcmp(tag.data(), kSignature, sizeof kSignature) != 0) {
        return nullptr;
    }
    return std::unique_ptr<HfaFile>(new HfaFile(path, std::move(file)));
}

HfaFile::HfaFile(std::string path, std::shared_ptr<const ByteSource> file) : path_(std::move(path)), file_(std::move(file)) {
    std::array<uint8_t, 4> at{};
    file_->readAt(16, at.data(), at.size());
    std::array<uint8_t, 18> header{}; // Ehfa_File: version, freeList, rootEntryPtr, entryHeaderLength, dictionaryPtr
    const uint32_t headerAt = le32(at.data());
    if (uint64_t{headerAt} + header.size() > file_->size()) {
        fail(path_, "its ERDAS Imagine header lies beyond the end of the file: a file cut short or damaged");
    }
    file_->readAt(headerAt, header.data(), header.size());
    root_ = le32(&header[8]);
    const uint32_t dictionary = le32(&header[14]);
    if (dictionary >= file_->size()) {
        fail(path_, "its ERDAS Imagine dictionary lies beyond the end of the file: a file cut short or damaged");
    }
    std::string text(static_cast<size_t>(std::min<uint64_t>(kMaxDictionaryBytes, file_->size() - dictionary)), '\0');
    file_->readAt(dictionary, text.data(), text.size());
    dictionary_ = std::make_unique<HfaDictionary>(text, path_);
}

std::vector<HfaNode> HfaFile::children(const HfaNode& parent) const {
    std::vector<HfaNode> nodes;
    std::set<uint32_t> seen;
    for (uint32_t at = parent.child; at != 0; at = nodes.back().next) {
        if (!seen.insert(at).second || nodes.size() >= kMaxNodes) {
            fail(path_, "its ERDAS Imagine structure is damaged: the nodes under \"" + printableText(parent.name) +
                            "\" run in a loop");
        }
        nodes.push_back(node(at));
    }
    return nodes;
}

std::optional<HfaNode> HfaFile::child(const HfaNode& parent, const std::string& name) const {
    for (HfaNode& n : children(parent)) {
        if (n.name == name) {
            return std::move(n);
        }
    }
    return std::nullopt;
}

std::vector<uint8_t> HfaFile::data(const HfaNode& n) const {
    if (n.size > kMaxNodeBytes) {
        fail(path_, "its ERDAS Imagine node \"" + printableText(n.name) + "\" claims " + std::to_string(n.size) +
                        " bytes, more than 64 MB");
    }
    if (uint64_t{n.data} + n.size > file_->size()) {
        fail(path_, "its ERDAS Imagine node \"" + printableText(n.name) + "\" lies beyond the end of the file (" +
                        std::to_string(file_->size()) + " bytes): a file cut short or damaged");
    }
    std::vector<uint8_t> bytes(n.size);
    file_->readAt(n.data, bytes.data(), bytes.size());
    return bytes;
}

HfaNode HfaFile::node(uint32_t offset) const {
    if (uint64_t{offset} + kEntryBytes > file_->size()) {
        fail(path_, "its ERDAS Imagine node at byte " + std::to_string(offset) + " lies beyond the end of the file (" +
                        std::to_string(file_->size()) + " bytes): a file cut short or damaged");
    }
    std::array<uint8_t, kEntryBytes> e{};
    file_->readAt(offset, e.data(), e.size());
    HfaNode n;
    n.next = le32(&e[0]);
    n.child = le32(&e[12]);
    n.data = le32(&e[16]);
    n.size = le32(&e[20]);
    const auto* name = reinterpret_cast<const char*>(&e[24]);
    n.name.assign(name, strnlen(name, 64));
    n.type.assign(name + 64, strnlen(name + 64, 32));
    return n;
}

} // namespace pyramid
