#include "libpyramid/input/hfa_spill.hpp"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>

#include "formats/byte_source.hpp"
#include "formats/error.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

constexpr char kSignature[] = "ERDAS_IMG_EXTERNAL_RASTER"; // and its NUL
constexpr uint64_t kMapHeader = 20;                         // bytes before the validity map's rows

} // namespace

HfaSpillBlocks readHfaSpill(const HfaFile& f, const HfaNode& dms, const std::string& path, const std::string& where,
                            HfaPixel pixel, int across, int down, size_t blockPixels) {
    const HfaDictionary& d = f.dictionary();
    const std::vector<uint8_t> data = f.data(dms);
    const auto value = [&](const char* name, int count) {
        const std::optional<HfaValue> v = d.field(dms.type, data, name);
        if (!v || v->count < count) {
            fail(path, where + "'s spill file node (ExternalRasterDMS) has no " + name);
        }
        return *v;
    };
    // The 64-bit offsets are two 32-bit words, the low one first.
    const auto offset = [&](const char* name) {
        const HfaValue v = value(name, 2);
        return static_cast<uint64_t>(static_cast<uint32_t>(d.integer(v, 0))) |
               (static_cast<uint64_t>(static_cast<uint32_t>(d.integer(v, 1))) << 32);
    };
    const std::string name = d.stringField(dms.type, data, "fileName");
    if (name.empty()) {
        fail(path, where + "'s spill file node (ExternalRasterDMS) names no file");
    }
    const uint64_t mapOffset = offset("layerStackValidFlagsOffset");
    const uint64_t dataOffset = offset("layerStackDataOffset");
    const int64_t layers = d.integer(value("layerStackCount", 1));
    const int64_t index = d.integer(value("layerStackIndex", 1));
    if (layers < 1 || index < 0 || index >= layers || layers > 4096) {
        fail(path, where + "'s spill file node gives it place " + std::to_string(index) + " among " +
                       std::to_string(layers) + " stacked layers");
    }

    HfaSpillBlocks spill;
    spill.path = (std::filesystem::path(path).parent_path() / std::filesystem::path(name).filename()).string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(spill.path, ec)) {
        fail(path, where + " keeps its pixels in the spill file " + spill.path + ", which is missing");
    }
    const std::shared_ptr<const ByteSource> file = openFileSource(spill.path); // throws naming it
    char signature[sizeof kSignature] = {};
    if (file->size() < sizeof signature) {
        fail(spill.path, "is no ERDAS Imagine spill file: it is shorter than its signature");
    }
    file->readAt(0, signature, sizeof signature);
    if (std::memcmp(signature, kSignature, sizeof kSignature) != 0) {
        fail(spill.path, "is no ERDAS Imagine spill file: it does not begin with ERDAS_IMG_EXTERNAL_RASTER");
    }

    const uint64_t rowBytes = (static_cast<uint64_t>(across) + 7) / 8;
    const uint64_t mapBytes = rowBytes * static_cast<uint64_t>(down);
    if (mapOffset > file->size() || file->size() - mapOffset < kMapHeader + mapBytes) {
        fail(spill.path, "is too short for the block validity map of " + where.substr(4) +
                             " at byte " + std::to_string(mapOffset) + ": a file cut short or damaged");
    }
    std::vector<uint8_t> map(static_cast<size_t>(mapBytes));
    file->readAt(mapOffset + kMapHeader, map.data(), map.size());

    const uint64_t blockBytes = hfaStoredBytes(pixel, blockPixels);
    const uint64_t blocks = static_cast<uint64_t>(across) * static_cast<uint64_t>(down);
    // The last block of the last layer must end within 2^64: checked here, its end against the
    // file's size as each block is read.
    if (blockBytes != 0 && (blocks * static_cast<uint64_t>(layers)) > (std::numeric_limits<uint64_t>::max() - dataOffset) / blockBytes) {
        fail(path, where + "'s spill file node places its blocks beyond any file");
    }
    spill.blocks.resize(static_cast<size_t>(blocks));
    for (uint64_t k = 0; k < blocks; ++k) {
        const uint64_t row = k / static_cast<uint64_t>(across), column = k % static_cast<uint64_t>(across);
        HfaBlockPlace& b = spill.blocks[static_cast<size_t>(k)];
        b.offset = dataOffset + (k * static_cast<uint64_t>(layers) + static_cast<uint64_t>(index)) * blockBytes;
        b.size = static_cast<uint32_t>(blockBytes);
        b.valid = ((map[static_cast<size_t>(row * rowBytes + column / 8)] >> (column % 8)) & 1u) != 0;
        b.compressed = false;
    }
    return spill;
}

} // namespace pyramid
