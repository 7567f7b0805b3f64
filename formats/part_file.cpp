#include "formats/part_file.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <string_view>

#include <unistd.h>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "formats/header_bytes.hpp"

namespace pyramid {

namespace {

using detail::loadU32;
using detail::storeU32;

constexpr char kMagic[8] = {'L', 'P', 'Y', 'R', 'P', 'A', 'R', 'T'};
constexpr char kEnd[8] = {'L', 'P', 'Y', 'R', 'P', 'E', 'N', 'D'};
constexpr uint32_t kVersion = 1;
constexpr uint64_t kHeaderBytes = 16;
constexpr uint64_t kRecordBytes = 32;
constexpr uint64_t kFooterBytes = 24;
constexpr size_t kBufferBytes = size_t{1} << 20;
// Blobs this small are looked up among the ones already stored; at most kSmallCount are kept.
constexpr size_t kSmallBlob = 1024;
constexpr size_t kSmallCount = 8192;

void storeU64(uint8_t* p, uint64_t v) {
    storeU32(p, static_cast<uint32_t>(v));
    storeU32(p + 4, static_cast<uint32_t>(v >> 32));
}

uint64_t loadU64(const uint8_t* p) { return uint64_t{loadU32(p)} | (uint64_t{loadU32(p + 4)} << 32); }

void append(std::vector<uint8_t>& out, const void* data, size_t size) {
    const auto* p = static_cast<const uint8_t*>(data);
    out.insert(out.end(), p, p + size);
}

} // namespace

PartFileWriter::PartFileWriter(const std::string& path) : file_(std::make_unique<AtomicFile>(path)) {
    uint8_t header[kHeaderBytes] = {};
    std::memcpy(header, kMagic, 8);
    storeU32(header + 8, kVersion);
    buffer_.reserve(kBufferBytes);
    append(buffer_, header, sizeof(header));
}

PartFileWriter::~PartFileWriter() = default;

const std::string& PartFileWriter::path() const { return file_->path(); }

void PartFileWriter::flushBuffer() {
    if (!buffer_.empty()) {
        file_->writeAt(position_, buffer_.data(), buffer_.size());
        position_ += buffer_.size();
        buffer_.clear();
    }
}

void PartFileWriter::add(uint32_t stream, int level, int tx, int ty, std::span<const uint8_t> extra,
                         std::span<const uint8_t> blob) {
    const uint64_t at = position();
    const uint64_t dataAt = at + kRecordBytes + extra.size();
    uint64_t blobAt = dataAt;
    uint64_t hash = 0;
    if (blob.size() <= kSmallBlob) {
        hash = std::hash<std::string_view>{}(
            std::string_view(reinterpret_cast<const char*>(blob.data()), blob.size()));
        if (auto it = small_.find(hash); it != small_.end()) {
            for (const Stored& s : it->second) {
                if (s.bytes.size() == blob.size() && std::equal(blob.begin(), blob.end(), s.bytes.begin())) {
                    blobAt = s.at;
                    break;
                }
            }
        }
    }
    uint8_t record[kRecordBytes];
    storeU32(record, stream);
    storeU32(record + 4, static_cast<uint32_t>(level));
    storeU32(record + 8, static_cast<uint32_t>(tx));
    storeU32(record + 12, static_cast<uint32_t>(ty));
    storeU32(record + 16, static_cast<uint32_t>(extra.size()));
    storeU32(record + 20, static_cast<uint32_t>(blob.size()));
    storeU64(record + 24, blobAt);
    append(buffer_, record, sizeof(record));
    append(buffer_, extra.data(), extra.size());
    if (blobAt == dataAt) {
        append(buffer_, blob.data(), blob.size());
        if (blob.size() <= kSmallBlob && smallCount_ < kSmallCount) {
            small_[hash].push_back(Stored{dataAt, std::vector<uint8_t>(blob.begin(), blob.end())});
            ++smallCount_;
        }
    }
    if (buffer_.size() >= kBufferBytes) {
        flushBuffer();
    }
}

void PartFileWriter::rewind(uint64_t to) {
    if (to < kHeaderBytes || to > position()) {
        fail(path(), "cannot rewind a part file to byte " + std::to_string(to));
    }
    if (to >= position_) {
        buffer_.resize(static_cast<size_t>(to - position_));
    } else {
        buffer_.clear();
        position_ = to; // the bytes past it are overwritten, or cut off at commit
        if (ftruncate(file_->fd(), static_cast<off_t>(to)) != 0) {
            fail(path(), "cannot truncate its temporary");
        }
    }
    for (auto it = small_.begin(); it != small_.end();) {
        auto& list = it->second;
        const size_t before = list.size();
        list.erase(std::remove_if(list.begin(), list.end(), [&](const Stored& s) { return s.at >= to; }), list.end());
        smallCount_ -= before - list.size();
        it = list.empty() ? small_.erase(it) : std::next(it);
    }
}

void PartFileWriter::commit(const std::string& trailer) {
    const uint64_t trailerAt = position();
    append(buffer_, trailer.data(), trailer.size());
    uint8_t footer[kFooterBytes];
    storeU64(footer, trailerAt);
    storeU64(footer + 8, trailer.size());
    std::memcpy(footer + 16, kEnd, 8);
    append(buffer_, footer, sizeof(footer));
    flushBuffer();
    file_->commit();
}

PartFileReader::PartFileReader(const std::string& path) : source_(openFileSource(path)) {
    const uint64_t size = source_->size();
    uint8_t header[kHeaderBytes];
    uint8_t footer[kFooterBytes];
    if (size < kHeaderBytes + kFooterBytes) {
        fail(path, "not a part file (too short)");
    }
    source_->readAt(0, header, sizeof(header));
    if (std::memcmp(header, kMagic, 8) != 0) {
        fail(path, "not a part file (no LPYRPART signature)");
    }
    if (loadU32(header + 8) != kVersion) {
        fail(path, "part file version " + std::to_string(loadU32(header + 8)) + " is not supported (1 is)");
    }
    source_->readAt(size - kFooterBytes, footer, sizeof(footer));
    if (std::memcmp(footer + 16, kEnd, 8) != 0) {
        fail(path, "incomplete part file (no end signature)");
    }
    trailerAt_ = loadU64(footer);
    const uint64_t trailerBytes = loadU64(footer + 8);
    if (trailerAt_ < kHeaderBytes || trailerAt_ > size - kFooterBytes || trailerBytes != size - kFooterBytes - trailerAt_) {
        fail(path, "corrupt part file (its trailer lies outside the file)");
    }
    trailer_.resize(static_cast<size_t>(trailerBytes));
    source_->readAt(trailerAt_, trailer_.data(), trailer_.size());
}

PartFileReader::Cursor PartFileReader::records(uint64_t begin, uint64_t end) const {
    if (begin < kHeaderBytes || begin > end || end > trailerAt_) {
        fail(path(), "corrupt part file (records [" + std::to_string(begin) + ", " + std::to_string(end) +
                         ") lie outside its " + std::to_string(trailerAt_) + " bytes of records)");
    }
    return Cursor(*this, begin, end);
}

PartFileReader::Cursor::Cursor(const PartFileReader& reader, uint64_t begin, uint64_t end)
    : reader_(reader), at_(begin), end_(end), bufferAt_(begin) {}

void PartFileReader::Cursor::read(uint64_t at, void* out, size_t size) {
    if (size == 0) {
        return; // an empty blob (a sparse build's empty subtree): nothing to read, maybe nowhere to put it
    }
    if (at < bufferAt_ || at + size > bufferAt_ + buffer_.size()) {
        if (size > kBufferBytes) {
            reader_.source_->readAt(at, out, size);
            return;
        }
        const uint64_t n = std::min<uint64_t>(kBufferBytes, reader_.trailerAt_ - at);
        buffer_.resize(static_cast<size_t>(n));
        reader_.source_->readAt(at, buffer_.data(), buffer_.size());
        bufferAt_ = at;
    }
    std::memcpy(out, buffer_.data() + (at - bufferAt_), size);
}

bool PartFileReader::Cursor::next(Record& r) {
    if (at_ == end_) {
        return false;
    }
    const auto corrupt = [&](const std::string& what) {
        fail(reader_.path(), "corrupt part file (record at byte " + std::to_string(at_) + ": " + what + ")");
    };
    if (end_ - at_ < kRecordBytes) {
        corrupt("truncated");
    }
    uint8_t head[kRecordBytes];
    read(at_, head, sizeof(head));
    r.stream = loadU32(head);
    const uint32_t level = loadU32(head + 4), tx = loadU32(head + 8), ty = loadU32(head + 12);
    // tx and ty are checked against the pyramid by whoever writes the tile; here only the level.
    if (level > static_cast<uint32_t>(kMaxLevel)) {
        corrupt("level " + std::to_string(level));
    }
    r.level = static_cast<int>(level);
    r.tx = static_cast<int>(tx);
    r.ty = static_cast<int>(ty);
    const uint64_t extraBytes = loadU32(head + 16), blobBytes = loadU32(head + 20), blobAt = loadU64(head + 24);
    const uint64_t dataAt = at_ + kRecordBytes + extraBytes;
    if (dataAt > end_) {
        corrupt("its bytes pass the end of its range");
    }
    r.extra.resize(static_cast<size_t>(extraBytes));
    read(at_ + kRecordBytes, r.extra.data(), r.extra.size());
    r.blob.resize(static_cast<size_t>(blobBytes));
    if (blobAt == dataAt) {
        if (blobBytes > end_ - dataAt) {
            corrupt("its bytes pass the end of its range");
        }
        read(dataAt, r.blob.data(), r.blob.size());
        at_ = dataAt + blobBytes;
    } else {
        if (blobAt < kHeaderBytes || blobAt > at_ || blobBytes > at_ - blobAt) {
            corrupt("its shared bytes are not an earlier record's");
        }
        read(blobAt, r.blob.data(), r.blob.size());
        at_ = dataAt;
    }
    return true;
}


std::string partFileName(const std::string& output, int index, int count) {
    return output + ".part-" + std::to_string(index) + "-of-" + std::to_string(count);
}

PartOutput::PartOutput(const std::string& path, std::string format, int index, int count, nlohmann::json job)
    : file_(path), format_(std::move(format)), index_(index), count_(count), job_(std::move(job)) {}

void PartOutput::addPyramid(nlohmann::json entry) { pyramids_.push_back(std::move(entry)); }

void PartOutput::commit() {
    const nlohmann::json trailer{{"format", format_}, {"version", 1},   {"part", index_},
                                 {"parts", count_},   {"job", job_},    {"pyramids", pyramids_}};
    file_.commit(trailer.dump());
}

std::string partFileFormat(const std::string& path) {
    const PartFileReader reader(path);
    try {
        return nlohmann::json::parse(reader.trailer()).at("format").get<std::string>();
    } catch (const nlohmann::json::exception& e) {
        fail(path, std::string("corrupt part file trailer (") + e.what() + ")");
    }
}

PartSet readPartSet(const std::vector<std::string>& paths, const std::string& format) {
    if (paths.empty()) {
        failOption("parts", "no part files to merge");
    }
    std::vector<PartSet::Part> parts;
    for (const std::string& path : paths) {
        PartSet::Part p;
        p.reader = std::make_unique<PartFileReader>(path);
        try {
            p.trailer = nlohmann::json::parse(p.reader->trailer());
            if (p.trailer.at("format").get<std::string>() != format || p.trailer.at("version").get<int>() != 1) {
                fail(path, "is a " + p.trailer.at("format").get<std::string>() + ", not a " + format);
            }
            (void)p.trailer.at("part").get<int>();
            (void)p.trailer.at("parts").get<int>();
            (void)p.trailer.at("pyramids").size();
        } catch (const nlohmann::json::exception& e) {
            fail(path, std::string("corrupt part file trailer (") + e.what() + ")");
        }
        parts.push_back(std::move(p));
    }
    std::sort(parts.begin(), parts.end(), [](const PartSet::Part& a, const PartSet::Part& b) {
        return a.trailer["part"].get<int>() < b.trailer["part"].get<int>();
    });
    const int count = parts[0].trailer["parts"].get<int>();
    std::vector<const PartSet::Part*> byIndex(static_cast<size_t>(std::max(count, 0)), nullptr);
    for (const PartSet::Part& p : parts) {
        const std::string& where = p.reader->path();
        if (p.trailer["parts"].get<int>() != count) {
            fail(where, "is a part of " + std::to_string(p.trailer["parts"].get<int>()) + ", the others of " +
                            std::to_string(count));
        }
        if (p.trailer["job"] != parts[0].trailer["job"]) {
            fail(where, "is a part of another build than " + parts[0].reader->path() + " (" +
                            p.trailer["job"].dump() + " against " + parts[0].trailer["job"].dump() + ")");
        }
        const int index = p.trailer["part"].get<int>();
        if (index < 0 || index >= count) {
            fail(where, "corrupt part file trailer (part " + std::to_string(index) + " of " + std::to_string(count) + ")");
        }
        if (byIndex[static_cast<size_t>(index)]) {
            fail(where, "part " + std::to_string(index) + " of " + std::to_string(count) + " is given twice (also " +
                            byIndex[static_cast<size_t>(index)]->reader->path() + ")");
        }
        byIndex[static_cast<size_t>(index)] = &p;
    }
    for (int i = 0; i < count; ++i) {
        if (!byIndex[static_cast<size_t>(i)]) {
            fail(parts[0].reader->path(), "part " + std::to_string(i) + " of " + std::to_string(count) +
                                               " is missing: every part of the build is needed");
        }
    }

    // Each pyramid's shares, in order.
    PartSet set;
    set.count = count;
    set.parts = std::move(parts);
    std::map<int, std::vector<PartSet::Share>>& runs = set.shares;
    int pyramids = -1;
    int64_t totalTiles = 0;
    for (const PartSet::Part& p : set.parts) {
        const std::string& where = p.reader->path();
        try {
            for (const nlohmann::json& e : p.trailer["pyramids"]) {
                const int k = e.at("pyramid").get<int>();
                const int of = e.at("pyramids").get<int>();
                if (pyramids < 0) {
                    pyramids = of;
                }
                if (of != pyramids || k < 0 || k >= pyramids) {
                    fail(where, "corrupt part file trailer (pyramid " + std::to_string(k) + " of " + std::to_string(of) + ")");
                }
                (void)e.at("begin").get<int64_t>();
                (void)e.at("end").get<int64_t>();
                (void)e.at("top").get<bool>();
                (void)e.at("name").get<std::string>();
                (void)e.at("units").get<int64_t>();
                (void)e.at("records").at(1).get<uint64_t>();
                totalTiles += e.at("tiles").get<int64_t>();
                runs[k].push_back(PartSet::Share{&p, &e});
            }
        } catch (const nlohmann::json::exception& e) {
            fail(where, std::string("corrupt part file trailer (") + e.what() + ")");
        }
    }
    if (pyramids <= 0) {
        fail(set.parts[0].reader->path(), "the parts hold no pyramid");
    }
    for (int k = 0; k < pyramids; ++k) {
        std::vector<PartSet::Share>& list = runs[k];
        if (list.empty()) {
            fail(set.parts[0].reader->path(), "no part holds pyramid " + std::to_string(k + 1) + " of " + std::to_string(pyramids));
        }
        const nlohmann::json& first = *list[0].entry;
        const int64_t units = first.at("units").get<int64_t>();
        int64_t next = 0;
        for (size_t i = 0; i < list.size(); ++i) {
            const PartSet::Share& r = list[i];
            const std::string& where = r.part->reader->path();
            const nlohmann::json& e = *r.entry;
            const int64_t begin = e["begin"].get<int64_t>(), end = e["end"].get<int64_t>();
            const bool top = e["top"].get<bool>();
            if (e.at("name") != first.at("name") || e.at("header") != first.at("header") || e.at("units") != first.at("units") ||
                e.value("max_file_bytes", nlohmann::json()) != first.value("max_file_bytes", nlohmann::json())) {
                fail(where, "its pyramid " + e.at("name").get<std::string>() + " differs from " +
                                list[0].part->reader->path() + "'s (header, scale or split)");
            }
            // The top levels come first, or (a walk that writes them after its subtrees) last.
            const size_t topShare = first.value("top_last", false) ? list.size() - 1 : 0;
            if (top != (i == topShare) || begin != next || end < begin || end > units) {
                fail(where, "its share of " + e.at("name").get<std::string>() + " (subtrees " + std::to_string(begin) +
                                " to " + std::to_string(end) + ") does not follow the part before it (which ends at " +
                                std::to_string(next) + ")");
            }
            next = end;
        }
        if (next != units) {
            fail(list.back().part->reader->path(), "the parts of " + first.at("name").get<std::string>() +
                                                       " end at subtree " + std::to_string(next) + " of " +
                                                       std::to_string(units));
        }
    }
    set.pyramids = pyramids;
    set.tiles = totalTiles;
    return set;
}

} // namespace pyramid
