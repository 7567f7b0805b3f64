#include "formats/ortho_file.hpp"

#include <utility>

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"
#include "formats/header_bytes.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "formats/tiff_tile.hpp"

namespace pyramid {

using detail::quadtreeTiles;
using detail::tileName;

int64_t OrthoHeader::tileCount() const { return quadtreeTiles(maxLevel); }

int64_t OrthoHeader::tileIndex(int level, int tx, int ty) const {
    return tx + static_cast<int64_t>(ty) * (int64_t{1} << level) + ((int64_t{1} << (2 * level)) - 1) / 3;
}

int64_t OrthoHeader::tilesPerSide(int level) const { return int64_t{1} << level; }

bool OrthoHeader::contains(int level, int tx, int ty) const {
    const int64_t side = level >= 0 && level <= maxLevel ? tilesPerSide(level) : 0;
    return tx >= 0 && ty >= 0 && tx < side && ty < side;
}

void OrthoHeader::validate(const std::string& where) const {
    if (maxLevel < 0 || maxLevel > kMaxLevel) {
        fail(where, "invalid maxLevel " + std::to_string(maxLevel) + " (0 to 30 expected)");
    }
    if (tileSize < 1 || tileSize > kMaxTileSize) {
        fail(where, "invalid tileSize " + std::to_string(tileSize) + " (1 to 8192 expected)");
    }
    if (channels < 1 || channels > 4) {
        fail(where, "invalid channel count " + std::to_string(channels) + " (1 to 4 expected)");
    }
    if ((flags & ~(kFlagDxt | kFlagNoBorder)) != 0) {
        fail(where, "unknown flags " + std::to_string(flags) + " (only bits 0 and 1 are defined)");
    }
    if (dxt() && channels < 3) {
        fail(where, "DXT file with " + std::to_string(channels) + " channels (3 or 4 expected)");
    }
    if (dxt() && tilePixels() % 4 != 0) {
        fail(where, "DXT tiles of " + std::to_string(tilePixels()) + " pixels (a multiple of 4 expected)");
    }
    if (rootLevel < 0 || rootLevel > kMaxLevel || rootTx < 0 || rootTy < 0 ||
        rootTx >= (int64_t{1} << rootLevel) || rootTy >= (int64_t{1} << rootLevel)) {
        fail(where, "invalid root tile (" + std::to_string(rootLevel) + "," + std::to_string(rootTx) + "," +
                        std::to_string(rootTy) + ")");
    }
}

std::unique_ptr<OrthoFileReader> OrthoFileReader::open(const std::string& path) {
    return open(openFileSource(path));
}

std::unique_ptr<OrthoFileReader> OrthoFileReader::open(std::shared_ptr<const ByteSource> source) {
    std::unique_ptr<OrthoFileReader> reader(new OrthoFileReader());
    const std::string& path = source->name();
    reader->path_ = path;
    uint8_t raw[OrthoHeader::kBytes];
    detail::requireHeader(path, source->size(), sizeof raw);
    source->readAt(0, raw, sizeof raw);
    OrthoHeader& h = reader->header_;
    h.maxLevel = detail::loadI32(raw + 0);
    h.tileSize = detail::loadI32(raw + 4);
    h.channels = detail::loadI32(raw + 8);
    h.rootLevel = detail::loadI32(raw + 12);
    h.rootTx = detail::loadI32(raw + 16);
    h.rootTy = detail::loadI32(raw + 20);
    h.flags = detail::loadU32(raw + 24);
    h.validate(path);
    reader->table_ = TileTable::open(std::move(source), OrthoHeader::kBytes, h.tileCount(), 8);
    return reader;
}

OrthoFileReader::~OrthoFileReader() = default;

TileTable::Range OrthoFileReader::tileRange(int level, int tx, int ty) const {
    if (!header_.contains(level, tx, ty)) {
        detail::throwMissingTile(path_, level, tx, ty);
    }
    return table_->range(header_.tileIndex(level, tx, ty));
}

std::vector<uint8_t> OrthoFileReader::readTileBytes(int level, int tx, int ty) const {
    tileRange(level, tx, ty); // throws for a tile outside the file
    return table_->read(header_.tileIndex(level, tx, ty));
}

std::vector<uint8_t> OrthoFileReader::readTile(int level, int tx, int ty) const {
    const std::vector<uint8_t> blob = readTileBytes(level, tx, ty);
    const std::string where = tileName(path_, level, tx, ty);
    const int size = header_.tilePixels();
    if (header_.dxt()) {
        return decodeDxt(blob, size, size, dxtFormatOf(header_), where);
    }
    return decodeOrthoTiff(blob, size, header_.channels, where);
}

std::vector<uint8_t> packOrthoHeader(const OrthoHeader& h) {
    std::vector<uint8_t> raw(OrthoHeader::kBytes);
    detail::storeU32(raw.data() + 0, static_cast<uint32_t>(h.maxLevel));
    detail::storeU32(raw.data() + 4, static_cast<uint32_t>(h.tileSize));
    detail::storeU32(raw.data() + 8, static_cast<uint32_t>(h.channels));
    detail::storeU32(raw.data() + 12, static_cast<uint32_t>(h.rootLevel));
    detail::storeU32(raw.data() + 16, static_cast<uint32_t>(h.rootTx));
    detail::storeU32(raw.data() + 20, static_cast<uint32_t>(h.rootTy));
    detail::storeU32(raw.data() + 24, h.flags);
    return raw;
}

OrthoFileWriter::OrthoFileWriter(const std::string& path, const OrthoHeader& header) : path_(path), header_(header) {
    header_.validate(path);
    const std::vector<uint8_t> raw = packOrthoHeader(header_);
    table_ = std::make_unique<TileTableWriter>(path, raw, header_.tileCount(), 8, static_cast<uint64_t>(INT64_MAX));
}

OrthoFileWriter::~OrthoFileWriter() = default;

void OrthoFileWriter::writeTileBytes(int level, int tx, int ty, std::span<const uint8_t> blob) {
    if (!header_.contains(level, tx, ty)) {
        fail(path_, "no tile " + tileCoordinates(level, tx, ty) + " in this pyramid");
    }
    table_->write(header_.tileIndex(level, tx, ty), blob);
}

void OrthoFileWriter::writeTileSameAs(int level, int tx, int ty, const std::array<int, 3>& earlier) {
    for (const auto& [l, x, y] : {std::array<int, 3>{level, tx, ty}, earlier}) {
        if (!header_.contains(l, x, y)) {
            fail(path_, "no tile " + tileCoordinates(l, x, y) + " in this pyramid");
        }
    }
    table_->writeSameAs(header_.tileIndex(level, tx, ty), header_.tileIndex(earlier[0], earlier[1], earlier[2]));
}

void OrthoFileWriter::commit() {
    finish();
    table_->commit();
}

void OrthoFileWriter::finish() {
    detail::requireEveryTileWritten(header_, *table_, path_);
    table_->finish();
}

uint64_t OrthoFileWriter::bytesWritten() const { return table_->bytesWritten(); }

int64_t OrthoFileWriter::sharedTiles() const { return table_->sharedTiles(); }

} // namespace pyramid
