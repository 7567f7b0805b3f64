// Residual builds split across processes (doc/planet-scale.md): each process encodes one share
// of the pyramids' tiles into a part file (formats/part_file.hpp), and a merge replays the parts
// in order into the pyramid writers. Tile bytes do not depend on the split and the writers see
// the tiles in the single process's order, so the files are byte for byte a single run's,
// whatever the number of parts.
//
// The share: the subtrees below the in-memory top levels of every pyramid of the build (the
// level-(C+1) tiles, residual_pyramid_encoder.cpp), taken pyramid by pyramid and in Z order
// within each, are cut into `count` runs of whole groups of 4 (the groups an int16 overflow is
// reported by); part I encodes run I. The part whose run holds a pyramid's first subtree also
// records the pyramid's top levels, which every part with a subtree of that pyramid computes
// (its subtrees' parents). A pyramid held in memory whole (C = maxLevel) is one unit.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/part_file.hpp"
#include "formats/residual_codec.hpp"
#include "libpyramid/support/work_share.hpp"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"
#include "libpyramid/encode/residual/residual_tile.hpp"

namespace pyramid {

// The format residual builds' part files name in their trailers.
inline constexpr const char* kResidualPartFormat = "libpyramid residual part";

// A header as part files record it (the scale included).
nlohmann::json residualHeaderJson(const ResidualHeader& header);
// The per-level report of a pyramid from its tiles' statistics, merged in write order.
std::vector<ResidualLevelReport> residualLevelReports(const ResidualHeader& header, const std::vector<LevelStats>& stats);

// A report's levels and a set's files as the JSON reports write them.
nlohmann::json residualLevelsJson(const std::vector<ResidualLevelReport>& levels);
nlohmann::json residualFilesJson(const std::vector<std::pair<std::string, uint64_t>>& files);
// How the tiles are coded, as reports write it: {"compression", "deflate_level" (null for
// context coding)}, to merge into a report's object.
nlohmann::json residualCodingJson(const ResidualTileCoding& coding);

// A tile's statistics as a part file records them, and back.
std::vector<uint8_t> packLevelStats(const LevelStats& stats);
LevelStats unpackLevelStats(const std::vector<uint8_t>& bytes, const std::string& where);

struct ResidualMergeReport {
    int parts = 0;
    std::string directory;
    std::vector<std::string> outputs;            // each pyramid's main file
    std::vector<ResidualPyramidReport> pyramids; // in the build's order
    double seconds = 0.0;
};

// Checks that `parts` are every part (0 to N-1) of one build, each pyramid's runs complete and
// contiguous, and writes the build's pyramids into `directory`, each as a single process puts it
// in place (ResidualOutput: one file or a set, with its companions); several pyramids appear
// together (formats/staging_directory.hpp). `progress(done, total)` counts tiles. Throws Error
// naming the part file and the problem; writes nothing then.
ResidualMergeReport mergeResidualParts(const std::vector<std::string>& parts, const std::string& directory,
                                       const std::function<void(int64_t, int64_t)>& progress = {});

nlohmann::json toJson(const ResidualMergeReport& report);

} // namespace pyramid
