// What the ortho encoder and the merge of a split ortho build share: how an output file is put
// in place (one file, or a region set and its index), and a level's statistics added up tile by
// tile in write order.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "formats/ortho_file.hpp"
#include "formats/sparse_set.hpp"
#include "formats/staging_directory.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_tile_encoder.hpp"

namespace pyramid {

// Completes `writer` (every tile written) in `staging`: one file when maxFileBytes is 0 or the
// pyramid fits, else a region set (formats/ortho_set.hpp); with maxFileBytes, an index beside it.
// `name`: the output's path relative to the directory; `output`: its final path (for messages).
// Appends the output's bytes and files to the report.
void placeOrthoOutput(std::unique_ptr<OrthoFileWriter> writer, const std::string& name, const std::string& output,
                      uint64_t maxFileBytes, StagingDirectory& staging, OrthoReport& report);

// Writes a sparse output (formats/sparse_set.hpp) from the tiles and empty subtrees `log` holds,
// of the pyramid `header` describes, into `staging`: the files that hold the data, each at most
// maxFileBytes when it is not 0, and the set's index unless that is one file of every level (and
// no maxFileBytes). Appends the output's shared tiles, bytes and files to the report; returns
// the tiles its files hold.
int64_t placeSparseOrthoOutput(const SparseTileLog& log, const OrthoHeader& header, const std::string& name,
                               const std::string& output, uint64_t maxFileBytes, StagingDirectory& staging,
                               OrthoReport& report);

// A level's statistics, added up tile by tile.
struct OrthoLevelTotals {
    int64_t tiles = 0;
    OrthoTileStats s;

    void add(const OrthoTileStats& t);
    OrthoLevelReport report(int level) const;
};

// A tile's statistics as a part file records them, and back.
std::vector<uint8_t> packOrthoTileStats(const OrthoTileStats& stats);
OrthoTileStats unpackOrthoTileStats(const std::vector<uint8_t>& bytes, const std::string& where);

} // namespace pyramid
