#include "formats/residual_file.hpp"

#include <cmath>
#include <cstdint>
#include <utility>

#include "formats/error.hpp"
#include "formats/header_bytes.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_shadow.hpp"
#include "formats/residual_tiff_plain.hpp"
#include "formats/tiff_tile.hpp"

namespace pyramid {

using detail::quadtreeTiles;
using detail::tileName;

int64_t ResidualHeader::tileCount() const { return minLevel + quadtreeTiles(maxLevel - minLevel); }

int64_t ResidualHeader::tilesPerSide(int level) const {
    return level < minLevel ? 1 : (int64_t{1} << (level - minLevel));
}

bool ResidualHeader::contains(int level, int tx, int ty) const {
    if (level < 0 || level > maxLevel) {
        return false;
    }
    const int64_t side = tilesPerSide(level);
    return tx >= 0 && ty >= 0 && tx < side && ty < side;
}

int64_t ResidualHeader::tileIndex(int level, int tx, int ty) const {
    if (level < minLevel) {
        return level;
    }
    const int l = level - minLevel;
    return minLevel + tx + static_cast<int64_t>(ty) * (int64_t{1} << l) + ((int64_t{1} << (2 * l)) - 1) / 3;
}

int ResidualHeader::tileSamples(int level) const {
    return (level < minLevel ? (tileSize >> (minLevel - level)) : tileSize) + 5;
}

void ResidualHeader::validate(const std::string& where) const {
    if (minLevel < 0 || maxLevel < minLevel || maxLevel > kMaxLevel) {
        fail(where, "invalid levels (minLevel " + std::to_string(minLevel) + ", maxLevel " + std::to_string(maxLevel) +
                        "; 0 <= minLevel <= maxLevel <= 30 expected)");
    }
    if (tileSize < 1 || tileSize > kMaxTileSize) {
        fail(where, "invalid tileSize " + std::to_string(tileSize) + " (1 to 8192 expected)");
    }
    if (minLevel > 13 || (tileSize % (1 << minLevel)) != 0) {
        fail(where, "tileSize " + std::to_string(tileSize) + " is not divisible by 2^minLevel (minLevel " +
                        std::to_string(minLevel) + ")");
    }
    if (rootLevel < 0 || rootLevel > kMaxLevel || rootTx < 0 || rootTy < 0 ||
        rootTx >= (int64_t{1} << rootLevel) || rootTy >= (int64_t{1} << rootLevel)) {
        fail(where, "invalid root tile (" + std::to_string(rootLevel) + "," + std::to_string(rootTx) + "," +
                        std::to_string(rootTy) + ")");
    }
    if (rootLevel > 0 && minLevel != 0) {
        fail(where, "a region file (rootLevel > 0) must have minLevel 0, not " + std::to_string(minLevel));
    }
    if (!std::isfinite(scale) || scale <= 0.0f) {
        fail(where, "invalid scale " + std::to_string(scale) + " (a finite positive number expected)");
    }
}

ResidualHeader ResidualFileReader::readHeader(const ByteSource& source) {
    uint8_t raw[ResidualHeader::kBytes];
    detail::requireHeader(source.name(), source.size(), sizeof raw);
    source.readAt(0, raw, sizeof raw);
    ResidualHeader h;
    h.minLevel = detail::loadI32(raw + 0);
    h.maxLevel = detail::loadI32(raw + 4);
    h.tileSize = detail::loadI32(raw + 8);
    h.rootLevel = detail::loadI32(raw + 12);
    h.rootTx = detail::loadI32(raw + 16);
    h.rootTy = detail::loadI32(raw + 20);
    h.scale = detail::loadF32(raw + 24);
    h.validate(source.name());
    return h;
}

ResidualHeader ResidualFileReader::readHeader(const std::string& path) { return readHeader(*openFileSource(path)); }

std::unique_ptr<ResidualFileReader> ResidualFileReader::open(std::shared_ptr<const ByteSource> source) {
    std::unique_ptr<ResidualFileReader> reader(new ResidualFileReader());
    reader->path_ = source->name();
    reader->header_ = readHeader(*source);
    reader->table_ = TileTable::open(std::move(source), ResidualHeader::kBytes, reader->header_.tileCount(), 4);
    return reader;
}

std::unique_ptr<ResidualFileReader> ResidualFileReader::open(const std::string& path) {
    return open(openFileSource(path));
}

ResidualFileReader::~ResidualFileReader() = default;

TileTable::Range ResidualFileReader::tileRange(int level, int tx, int ty) const {
    if (!header_.contains(level, tx, ty)) {
        detail::throwMissingTile(path_, level, tx, ty);
    }
    return table_->range(header_.tileIndex(level, tx, ty));
}

std::vector<uint8_t> ResidualFileReader::readTileBytes(int level, int tx, int ty) const {
    tileRange(level, tx, ty); // throws for a tile outside the file
    return table_->read(header_.tileIndex(level, tx, ty));
}

std::vector<int16_t> ResidualFileReader::readTile(int level, int tx, int ty) const {
    std::vector<int16_t> out(static_cast<size_t>(header_.tileSamples(level)) * static_cast<size_t>(header_.tileSamples(level)));
    readTileInto(level, tx, ty, out);
    return out;
}

namespace {

// A few levels' worth: a reader walking the quadtree down asks for each tile's parent, and for
// the same parent four times.
constexpr size_t kRecentTiles = 32;

// The tile's entry, moved to the front; null if it is not kept. Under the reader's mutex.
template <class T>
std::shared_ptr<const std::vector<T>> findRecent(RecentTiles<T>& recent, int64_t index) {
    for (auto k = recent.begin(); k != recent.end(); ++k) {
        if (k->first == index) {
            recent.splice(recent.begin(), recent, k);
            return recent.front().second;
        }
    }
    return nullptr;
}

template <class T>
void keepRecent(RecentTiles<T>& recent, int64_t index, std::shared_ptr<const std::vector<T>> kept) {
    if (findRecent(recent, index)) {
        recent.front().second = std::move(kept);
        return;
    }
    recent.emplace_front(index, std::move(kept));
    if (recent.size() > kRecentTiles) {
        recent.pop_back();
    }
}

} // namespace

void ResidualFileReader::readTileInto(int level, int tx, int ty, std::span<int16_t> out) const {
    const std::vector<uint8_t> blob = readTileBytes(level, tx, ty);
    const int size = header_.tileSamples(level);
    const std::string where = tileName(path_, level, tx, ty);
    const int64_t index = header_.tileIndex(level, tx, ty);
    if (!contextBlobNeedsParent(blob)) {
        decodeResidualBlobInto(blob, size, where, out);
        if (level < header_.maxLevel && isContextResidualBlob(blob)) { // its children may be in the parent mode
            auto kept = std::make_shared<const std::vector<int16_t>>(out.begin(), out.end());
            const std::lock_guard lock(recentMutex_);
            keepRecent(residuals_, index, std::move(kept));
        }
        return;
    }
    const std::vector<int32_t> plane = parentPlane(level, tx, ty);
    decodeResidualBlobInto(blob, size, where, out, plane);
    // Its children will ask for it.
    auto kept = std::make_shared<const std::vector<int32_t>>(shadowOf(plane, out));
    const std::lock_guard lock(recentMutex_);
    keepRecent(shadows_, index, std::move(kept));
}

std::vector<int32_t> ResidualFileReader::parentPlane(int level, int tx, int ty) const {
    tileRange(level, tx, ty); // throws for a tile outside the file
    const int size = header_.tileSamples(level);
    if (level == 0) {
        return std::vector<int32_t>(static_cast<size_t>(size) * static_cast<size_t>(size), 0);
    }
    const ShadowParent p = shadowParentOf(header_, level, tx, ty);
    const std::shared_ptr<const std::vector<int32_t>> above = shadow(p.level, p.tx, p.ty);
    return upsampleShadow(*above, header_.tileSamples(p.level), size, p.px, p.py);
}

std::shared_ptr<const std::vector<int32_t>> ResidualFileReader::shadow(int level, int tx, int ty) const {
    tileRange(level, tx, ty);
    const int64_t index = header_.tileIndex(level, tx, ty);
    std::shared_ptr<const std::vector<int16_t>> residuals;
    {
        const std::lock_guard lock(recentMutex_);
        if (auto kept = findRecent(shadows_, index)) {
            return kept;
        }
        residuals = findRecent(residuals_, index);
    }
    const std::vector<int32_t> plane = parentPlane(level, tx, ty);
    if (!residuals) { // not read lately: decoded here
        const int size = header_.tileSamples(level);
        auto decoded = std::make_shared<std::vector<int16_t>>(static_cast<size_t>(size) * static_cast<size_t>(size));
        decodeResidualBlobInto(readTileBytes(level, tx, ty), size, tileName(path_, level, tx, ty), *decoded, plane);
        residuals = std::move(decoded);
    }
    auto kept = std::make_shared<const std::vector<int32_t>>(shadowOf(plane, *residuals));
    const std::lock_guard lock(recentMutex_);
    keepRecent(shadows_, index, kept);
    return kept;
}

std::vector<uint8_t> packResidualHeader(const ResidualHeader& h) {
    std::vector<uint8_t> raw(ResidualHeader::kBytes);
    detail::storeU32(raw.data() + 0, static_cast<uint32_t>(h.minLevel));
    detail::storeU32(raw.data() + 4, static_cast<uint32_t>(h.maxLevel));
    detail::storeU32(raw.data() + 8, static_cast<uint32_t>(h.tileSize));
    detail::storeU32(raw.data() + 12, static_cast<uint32_t>(h.rootLevel));
    detail::storeU32(raw.data() + 16, static_cast<uint32_t>(h.rootTx));
    detail::storeU32(raw.data() + 20, static_cast<uint32_t>(h.rootTy));
    detail::storeF32(raw.data() + 24, h.scale);
    return raw;
}

ResidualFileWriter::ResidualFileWriter(const std::string& path, const ResidualHeader& header)
    : path_(path), header_(header) {
    header_.validate(path);
    const std::vector<uint8_t> raw = packResidualHeader(header_);
    table_ = std::make_unique<TileTableWriter>(path, raw, header_.tileCount(), 4, UINT32_MAX);
}

ResidualFileWriter::~ResidualFileWriter() = default;

void ResidualFileWriter::writeTile(int level, int tx, int ty, std::span<const int16_t> residuals) {
    const int size = header_.tileSamples(level);
    if (residuals.size() != static_cast<size_t>(size) * static_cast<size_t>(size)) {
        fail(path_, "tile " + tileCoordinates(level, tx, ty) + " needs " + std::to_string(size) + "x" +
                        std::to_string(size) + " residuals");
    }
    const std::vector<uint8_t> blob = encodeResidualTiff(residuals, size);
    writeTileBytes(level, tx, ty, blob);
}

void ResidualFileWriter::writeTileBytes(int level, int tx, int ty, std::span<const uint8_t> blob) {
    if (!header_.contains(level, tx, ty)) {
        fail(path_, "no tile " + tileCoordinates(level, tx, ty) + " in this pyramid");
    }
    table_->write(header_.tileIndex(level, tx, ty), blob);
}

void ResidualFileWriter::commit() {
    finish();
    table_->commit();
}

void ResidualFileWriter::finish() {
    detail::requireEveryTileWritten(header_, *table_, path_);
    table_->finish();
}

uint64_t ResidualFileWriter::bytesWritten() const { return table_->bytesWritten(); }

int64_t ResidualFileWriter::sharedTiles() const { return table_->sharedTiles(); }

} // namespace pyramid
