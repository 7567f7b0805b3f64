// Where a residual pyramid's tiles go while they are encoded, and how the pyramid is put in
// place at the end: one file, or (with a file size cap) a region set and its index
// (formats/residual_set.hpp), with the files that go beside it (a georeference sidecar). The
// one owner of that rule for the encoder and for the merge of a split build (residual_parts.hpp).
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"

namespace pyramid {

class SparseTileLog;
class StagingDirectory;
struct ResidualPyramidReport;

// A text file written beside a pyramid, in place together with it: `name` is relative to the
// pyramid's directory.
struct CompanionFile {
    std::string name;
    std::string text;
};

class ResidualOutput {
public:
    // `maxFileBytes` 0: one file, `output`, written atomically. Otherwise the pyramid is staged
    // whole beside `output` (past 4 GiB if need be) and becomes a set of files of at most that
    // many bytes each, which appear together with the index. `levelOrder` (one file): the tiles
    // are staged as they come and written into `output` level by level, row by row, when it is
    // put in place: the order the set splitter gives a region file, so that a region built alone
    // (options.region) is byte for byte the file of a set.
    // `parentModes` set: the tiles are context-coded, and each file, once final, takes the parent
    // mode where it is smaller (residual_parent_pass.hpp), with that many threads (0: all cores);
    // the pyramid is then staged.
    ResidualOutput(const std::string& output, const ResidualHeader& header, uint64_t maxFileBytes,
                   bool levelOrder = false, std::optional<int> parentModes = std::nullopt);
    // A sparse output (formats/sparse_set.hpp): the tiles and empty subtrees go to log(), and
    // place() writes the files that hold the data (at most `maxFileBytes` each, when not 0) and
    // the set's index; `zeroBlob` is a full-size tile of residual 0.
    struct Sparse {
        std::vector<uint8_t> zeroBlob;
        std::optional<int> parentModes; // as above
    };
    ResidualOutput(const std::string& output, const ResidualHeader& header, uint64_t maxFileBytes, Sparse sparse);
    ~ResidualOutput();
    ResidualOutput(const ResidualOutput&) = delete;
    ResidualOutput& operator=(const ResidualOutput&) = delete;

    ResidualFileWriter& writer() { return *writer_; }
    SparseTileLog* log() { return log_.get(); }
    // Every tile written: puts the pyramid and `companions` in place under the temporaries' lock
    // (formats/temporaries.hpp), so that a signal finds all old or all new, and fills the report's
    // header, sharedTiles, bytes and files.
    void place(const std::vector<CompanionFile>& companions, ResidualPyramidReport& report);

private:
    void placeSparse(const std::vector<CompanionFile>& companions, ResidualPyramidReport& report);
    void placeStaged(std::vector<std::pair<std::string, uint64_t>> files, const std::vector<RegionRoot>& roots,
                     bool index, const std::vector<CompanionFile>& companions, ResidualPyramidReport& report);

    std::string output_;
    ResidualHeader header_;
    uint64_t maxFileBytes_ = 0;
    bool levelOrder_ = false;
    std::optional<int> parentModes_;
    std::unique_ptr<StagingDirectory> staging_;
    std::unique_ptr<ResidualFileWriter> writer_;
    std::unique_ptr<SparseTileLog> log_;
};

} // namespace pyramid
