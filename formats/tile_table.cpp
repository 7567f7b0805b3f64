#include "formats/tile_table.hpp"

#include <libdeflate.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/file_io.hpp"

namespace pyramid {

namespace {

void readOrFail(int fd, uint64_t offset, void* out, size_t size, const std::string& path) {
    if (!readFully(fd, out, size, offset)) {
        fail(path, errno ? std::string("read failed: ") + std::strerror(errno) : "unexpected end of file");
    }
}

uint64_t loadLittleEndian(const uint8_t* p, int bytes) {
    uint64_t v = 0;
    for (int k = bytes - 1; k >= 0; --k) {
        v = (v << 8) | p[k];
    }
    return v;
}

void storeLittleEndian(uint8_t* p, uint64_t v, int bytes) {
    for (int k = 0; k < bytes; ++k) {
        p[k] = static_cast<uint8_t>(v >> (8 * k));
    }
}

} // namespace

std::unique_ptr<TileTable> TileTable::open(std::shared_ptr<const ByteSource> source, uint64_t tableStart,
                                           int64_t tileCount, int offsetBytes) {
    std::unique_ptr<TileTable> table(new TileTable());
    table->source_ = std::move(source);
    const std::string& path = table->source_->name();
    table->fileSize_ = table->source_->size();
    const uint64_t pairBytes = 2u * static_cast<uint64_t>(offsetBytes);
    // The table must fit in the file before anything is allocated for it.
    if (tileCount < 0 || table->fileSize_ < tableStart ||
        static_cast<uint64_t>(tileCount) > (table->fileSize_ - tableStart) / pairBytes) {
        fail(path, "file of " + std::to_string(table->fileSize_) + " bytes is too short for its header and offset table of " +
                       std::to_string(tileCount) + " tiles");
    }
    const uint64_t tableBytes = static_cast<uint64_t>(tileCount) * pairBytes;
    table->dataStart_ = tableStart + tableBytes;
    const uint64_t dataBytes = table->fileSize_ - table->dataStart_;
    table->tileCount_ = tileCount;
    table->offsetBytes_ = offsetBytes;
    table->table_.resize(static_cast<size_t>(tableBytes));
    table->source_->readAt(tableStart, table->table_.data(), table->table_.size());
    for (int64_t i = 0; i < tileCount; ++i) {
        const uint8_t* p = table->table_.data() + static_cast<size_t>(i) * pairBytes;
        const uint64_t begin = loadLittleEndian(p, offsetBytes);
        const uint64_t end = loadLittleEndian(p + offsetBytes, offsetBytes);
        if (offsetBytes == 8 && (static_cast<int64_t>(begin) < 0 || static_cast<int64_t>(end) < 0)) {
            fail(path, "negative offset for tile " + std::to_string(i));
        }
        if (begin > end) {
            fail(path, "offsets of tile " + std::to_string(i) + " are reversed (" + std::to_string(begin) + " > " +
                           std::to_string(end) + ")");
        }
        if (end > dataBytes) {
            fail(path, "tile " + std::to_string(i) + " ends at byte " + std::to_string(end) +
                           " past the end of the tile data (" + std::to_string(dataBytes) + " bytes)");
        }
    }
    return table;
}

std::unique_ptr<TileTable> TileTable::open(const std::string& path, uint64_t tableStart, int64_t tileCount,
                                           int offsetBytes) {
    return open(openFileSource(path), tableStart, tileCount, offsetBytes);
}

TileTable::Range TileTable::range(int64_t index) const {
    if (index < 0 || index >= tileCount_) {
        fail(path(), "tile index " + std::to_string(index) + " out of range");
    }
    const uint8_t* p = table_.data() + static_cast<size_t>(index) * 2u * static_cast<size_t>(offsetBytes_);
    return Range{loadLittleEndian(p, offsetBytes_), loadLittleEndian(p + offsetBytes_, offsetBytes_)};
}

TileTable::~TileTable() = default;

int64_t TileTable::storedTiles() const {
    int64_t stored = 0;
    for (int64_t i = 0; i < tileCount_; ++i) {
        stored += range(i).size() > 0 ? 1 : 0;
    }
    return stored;
}

int64_t TileTable::distinctRanges() const {
    std::vector<std::pair<uint64_t, uint64_t>> seen;
    seen.reserve(static_cast<size_t>(tileCount_));
    for (int64_t i = 0; i < tileCount_; ++i) {
        const Range r = range(i);
        if (r.size() > 0) {
            seen.emplace_back(r.begin, r.end);
        }
    }
    std::sort(seen.begin(), seen.end());
    return static_cast<int64_t>(std::unique(seen.begin(), seen.end()) - seen.begin());
}

std::vector<uint8_t> TileTable::read(int64_t index) const {
    const Range r = range(index);
    if (r.size() == 0) {
        throw MissingTileError(path() + ": tile " + std::to_string(index) + " is missing (empty byte range)");
    }
    std::vector<uint8_t> bytes(r.size());
    source_->readAt(dataStart_ + r.begin, bytes.data(), bytes.size());
    return bytes;
}

void TileTable::readAt(uint64_t offset, void* out, size_t size) const { source_->readAt(offset, out, size); }

// ---------------------------------------------------------------------------------------------

struct TileTableWriter::Impl {
    AtomicFile file;
    uint64_t tableStart = 0;
    int offsetBytes = 4;
    uint64_t maxOffset = 0;
    std::vector<TileTable::Range> ranges;
    std::vector<bool> written;
    std::unordered_multimap<size_t, int64_t> byHash; // content hash -> a tile holding those bytes
    uint64_t dataEnd = 0;
    int64_t shared = 0;
    // The bytes of the range shared last: runs of identical tiles (all-zero residuals over a
    // face a small map does not reach) are matched without reading the file back.
    std::vector<uint8_t> lastShared;
    TileTable::Range lastSharedRange{};
    bool finished = false; // the table is written and the file flushed: only the rename is left
    bool mayPassLimit = false;
    mutable std::mutex mutex;

    explicit Impl(const std::string& path) : file(path) {}

    // Tile `index` is in the table and not written yet (Error naming the file otherwise).
    void requireUnwritten(int64_t index) const {
        if (index < 0 || index >= static_cast<int64_t>(ranges.size())) {
            fail(file.path(), "tile index " + std::to_string(index) + " out of range");
        }
        if (written[static_cast<size_t>(index)]) {
            fail(file.path(), "tile " + std::to_string(index) + " written twice");
        }
    }

    bool sameBytes(const TileTable::Range& r, std::span<const uint8_t> blob) {
        if (r.size() != blob.size()) {
            return false;
        }
        std::vector<uint8_t> stored(r.size());
        readOrFail(file.fd(), tableStart + ranges.size() * 2u * offsetBytes + r.begin, stored.data(), stored.size(),
                  file.path());
        return std::memcmp(stored.data(), blob.data(), blob.size()) == 0;
    }
};

TileTableWriter::TileTableWriter(const std::string& path, std::span<const uint8_t> header, int64_t tileCount,
                                 int offsetBytes, uint64_t maxOffset)
    : impl_(std::make_unique<Impl>(path)) {
    if (tileCount <= 0 || tileCount > (int64_t{1} << 40)) {
        fail(path, "invalid tile count " + std::to_string(tileCount));
    }
    impl_->tableStart = header.size();
    impl_->offsetBytes = offsetBytes;
    impl_->maxOffset = maxOffset;
    impl_->ranges.resize(static_cast<size_t>(tileCount));
    impl_->written.assign(static_cast<size_t>(tileCount), false);
    impl_->file.writeAt(0, header.data(), header.size());
}

TileTableWriter::~TileTableWriter() = default;

void TileTableWriter::write(int64_t index, std::span<const uint8_t> blob) {
    Impl& w = *impl_;
    std::lock_guard<std::mutex> lock(w.mutex);
    w.requireUnwritten(index);
    if (blob.empty()) {
        fail(w.file.path(), "tile " + std::to_string(index) + " is empty");
    }
    if (!w.lastShared.empty() && w.lastShared.size() == blob.size() &&
        std::memcmp(w.lastShared.data(), blob.data(), blob.size()) == 0) {
        w.ranges[static_cast<size_t>(index)] = w.lastSharedRange;
        w.written[static_cast<size_t>(index)] = true;
        ++w.shared;
        return;
    }
    // CRC-32 (libdeflate's, vectorised) as the content hash: faster than std::hash over the
    // bytes (10 against 6 GB/s here) in this serial step, which sees every tile of the run; a
    // collision only costs the byte-for-byte comparison below.
    const size_t hash = libdeflate_crc32(0, blob.data(), blob.size());
    auto [first, last] = w.byHash.equal_range(hash);
    for (auto it = first; it != last; ++it) {
        const TileTable::Range r = w.ranges[static_cast<size_t>(it->second)];
        if (w.sameBytes(r, blob)) {
            w.lastShared.assign(blob.begin(), blob.end());
            w.lastSharedRange = r;
            w.ranges[static_cast<size_t>(index)] = r;
            w.written[static_cast<size_t>(index)] = true;
            ++w.shared;
            return;
        }
    }
    const uint64_t begin = w.dataEnd;
    const uint64_t end = begin + blob.size();
    if (end > w.maxOffset && !w.mayPassLimit) {
        fail(w.file.path(), "tile data passes " + std::to_string(w.maxOffset) +
                                " bytes, the limit of this file's offsets (split the pyramid into region files)");
    }
    const uint64_t tableBytes = w.ranges.size() * 2u * static_cast<uint64_t>(w.offsetBytes);
    w.file.writeAt(w.tableStart + tableBytes + begin, blob.data(), blob.size());
    w.dataEnd = end;
    w.ranges[static_cast<size_t>(index)] = TileTable::Range{begin, end};
    w.written[static_cast<size_t>(index)] = true;
    w.byHash.emplace(hash, index);
}

bool TileTableWriter::written(int64_t index) const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return index >= 0 && index < static_cast<int64_t>(impl_->written.size()) &&
           impl_->written[static_cast<size_t>(index)];
}

void TileTableWriter::leaveOut(int64_t index) {
    Impl& w = *impl_;
    std::lock_guard<std::mutex> lock(w.mutex);
    w.requireUnwritten(index);
    w.ranges[static_cast<size_t>(index)] = TileTable::Range{0, 0};
    w.written[static_cast<size_t>(index)] = true;
}

void TileTableWriter::writeSameAs(int64_t index, int64_t earlier) {
    Impl& w = *impl_;
    std::lock_guard<std::mutex> lock(w.mutex);
    const auto count = static_cast<int64_t>(w.ranges.size());
    if (index < 0 || index >= count || earlier < 0 || earlier >= count) {
        fail(w.file.path(), "tile index " + std::to_string(index < 0 || index >= count ? index : earlier) +
                                " out of range");
    }
    if (w.written[static_cast<size_t>(index)]) {
        fail(w.file.path(), "tile " + std::to_string(index) + " written twice");
    }
    if (!w.written[static_cast<size_t>(earlier)]) {
        fail(w.file.path(), "tile " + std::to_string(index) + " given the bytes of tile " + std::to_string(earlier) +
                                ", which is not written");
    }
    w.ranges[static_cast<size_t>(index)] = w.ranges[static_cast<size_t>(earlier)];
    w.written[static_cast<size_t>(index)] = true;
    ++w.shared;
}

void TileTableWriter::finish() {
    Impl& w = *impl_;
    std::lock_guard<std::mutex> lock(w.mutex);
    if (w.finished) {
        return;
    }
    for (size_t i = 0; i < w.written.size(); ++i) {
        if (!w.written[i]) {
            fail(w.file.path(), "tile " + std::to_string(i) + " was never written");
        }
    }
    if (w.dataEnd > w.maxOffset) {
        fail(w.file.path(), "tile data passes " + std::to_string(w.maxOffset) +
                                " bytes, the limit of this file's offsets (split the pyramid into region files)");
    }
    // In pieces of 64 Ki entries: a pyramid of millions of tiles does not hold its table twice.
    constexpr size_t kEntries = size_t{1} << 16;
    const size_t entry = 2u * static_cast<size_t>(w.offsetBytes);
    std::vector<uint8_t> piece;
    for (size_t first = 0; first < w.ranges.size(); first += kEntries) {
        const size_t count = std::min(kEntries, w.ranges.size() - first);
        piece.resize(count * entry);
        for (size_t i = 0; i < count; ++i) {
            uint8_t* p = piece.data() + i * entry;
            storeLittleEndian(p, w.ranges[first + i].begin, w.offsetBytes);
            storeLittleEndian(p + w.offsetBytes, w.ranges[first + i].end, w.offsetBytes);
        }
        w.file.writeAt(w.tableStart + first * entry, piece.data(), piece.size());
    }
    w.file.flush();
    w.finished = true;
}

void TileTableWriter::commit() {
    finish();
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->file.commit();
}

uint64_t TileTableWriter::bytesWritten() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->dataEnd;
}

void TileTableWriter::allowPastLimit() {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->mayPassLimit = true;
}

bool TileTableWriter::pastLimit() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->dataEnd > impl_->maxOffset;
}

TileTable::Range TileTableWriter::range(int64_t index) const {
    const Impl& w = *impl_;
    std::lock_guard<std::mutex> lock(w.mutex);
    if (index < 0 || index >= static_cast<int64_t>(w.ranges.size()) || !w.written[static_cast<size_t>(index)]) {
        fail(w.file.path(), "tile " + std::to_string(index) + " was never written");
    }
    return w.ranges[static_cast<size_t>(index)];
}

std::vector<uint8_t> TileTableWriter::read(int64_t index) const {
    const TileTable::Range r = range(index);
    const Impl& w = *impl_;
    std::vector<uint8_t> bytes(r.size());
    readOrFail(w.file.fd(), w.tableStart + w.ranges.size() * 2u * static_cast<uint64_t>(w.offsetBytes) + r.begin,
               bytes.data(), bytes.size(), w.file.path());
    return bytes;
}

int64_t TileTableWriter::sharedTiles() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->shared;
}

} // namespace pyramid
