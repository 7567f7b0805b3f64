// A part file: one share of a build split across processes (`--part I/N`, the ranks of an MPI
// run). It holds the tiles the process encoded, in the order it encoded them, each with a few
// bytes of its encoder's own (the tile's statistics), and a JSON trailer that says which build
// and which share they are. Merging replays the parts in order into the pyramid writers, so the
// files come out as a single process writes them (doc/planet-scale.md, doc/format.md 1.7).
//
// Layout, little-endian:
//   "LPYRPART" u32 version (1) u32 0
//   records, each: u32 stream, u32 level, u32 tx, u32 ty, u32 extraBytes, u32 blobBytes,
//                  u64 blobAt, then the extra bytes, then the blob's bytes when blobAt is the
//                  offset right after the extra bytes (else the blob is an earlier record's,
//                  stored once: blobAt points at it)
//   the trailer (UTF-8 JSON)
//   u64 trailer offset, u64 trailer bytes, "LPYRPEND"
// `stream` tells the pyramids of one part apart (the six faces of a planet).
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/byte_source.hpp"

namespace pyramid {

class AtomicFile;

// Writes a part file atomically (formats/atomic_file.hpp): records as they come, the trailer at
// commit(). Small identical blobs (empty tiles) are stored once.
class PartFileWriter {
public:
    explicit PartFileWriter(const std::string& path);
    ~PartFileWriter();
    PartFileWriter(const PartFileWriter&) = delete;
    PartFileWriter& operator=(const PartFileWriter&) = delete;

    void add(uint32_t stream, int level, int tx, int ty, std::span<const uint8_t> extra,
             std::span<const uint8_t> blob);
    // Where the next record starts: a stream's records are the range between two positions.
    uint64_t position() const { return position_ + buffer_.size(); }
    // Drops every record from `position` on (a pyramid started over at another scale).
    void rewind(uint64_t position);
    // Writes the trailer, flushes and renames the file into place.
    void commit(const std::string& trailer);
    const std::string& path() const;

private:
    void flushBuffer();
    std::unique_ptr<AtomicFile> file_;
    uint64_t position_ = 0;       // bytes on disk
    std::vector<uint8_t> buffer_; // bytes not yet written
    struct Stored {
        uint64_t at;
        std::vector<uint8_t> bytes;
    };
    std::unordered_map<uint64_t, std::vector<Stored>> small_; // content hash -> blobs stored
    size_t smallCount_ = 0;
};

// Reads a part file; every size and offset is checked against the file. Errors name the file.
class PartFileReader {
public:
    explicit PartFileReader(const std::string& path); // checks the framing, reads the trailer
    const std::string& path() const { return source_->name(); }
    const std::string& trailer() const { return trailer_; }
    uint64_t recordsEnd() const { return trailerAt_; }

    struct Record {
        uint32_t stream = 0;
        int level = 0, tx = 0, ty = 0;
        std::vector<uint8_t> extra;
        std::vector<uint8_t> blob;
    };
    // Reads the records of [begin, end) in order, buffered.
    class Cursor {
    public:
        bool next(Record& record); // false at `end`
    private:
        friend class PartFileReader;
        Cursor(const PartFileReader& reader, uint64_t begin, uint64_t end);
        void read(uint64_t at, void* out, size_t size);
        const PartFileReader& reader_;
        uint64_t at_, end_;
        std::vector<uint8_t> buffer_;
        uint64_t bufferAt_ = 0;
    };
    Cursor records(uint64_t begin, uint64_t end) const; // throws unless 16 <= begin <= end <= recordsEnd()

private:
    std::shared_ptr<const ByteSource> source_;
    uint64_t trailerAt_ = 0;
    std::string trailer_;
};

// The name of part `index` of `count` of a build whose output is `output` (a file, or a
// directory and a name prefix): OUTPUT.part-I-of-N.
std::string partFileName(const std::string& output, int index, int count);

// The part file one share writes: its records, then a trailer that says which kind of build
// (`format`), which build (`job`, the same JSON in every part of it), which part, and what each
// pyramid's records are (the encoder's entries; see readPartSet for the fields every entry has).
class PartOutput {
public:
    PartOutput(const std::string& path, std::string format, int index, int count, nlohmann::json job);
    PartFileWriter& file() { return file_; }
    void addPyramid(nlohmann::json entry);
    void commit();
    const std::string& path() const { return file_.path(); }

private:
    PartFileWriter file_;
    std::string format_;
    int index_, count_;
    nlohmann::json job_;
    nlohmann::json pyramids_ = nlohmann::json::array();
};

// Every part of one build, checked: each part 0..N-1 once, of one format and one job; each
// pyramid's shares (entries with "pyramid", "pyramids", "name", "header", "units", "begin",
// "end", "top", "records", "tiles") the same pyramid, following each other from the first unit to
// the last, the top levels in the first share (or the last, when the entries say "top_last"). Throws Error naming the part file and the problem.
struct PartSet {
    struct Part {
        std::unique_ptr<PartFileReader> reader;
        nlohmann::json trailer;
    };
    struct Share {
        const Part* part = nullptr;
        const nlohmann::json* entry = nullptr;
    };
    int count = 0;
    int pyramids = 0;
    int64_t tiles = 0;                       // records of every share
    std::vector<Part> parts;                 // by part number
    std::map<int, std::vector<Share>> shares; // each pyramid's, in order
};
PartSet readPartSet(const std::vector<std::string>& paths, const std::string& format);
// The format a part file's trailer names ("libpyramid residual part", ...).
std::string partFileFormat(const std::string& path);

} // namespace pyramid
