// A residual build split into shares (libpyramid/encode/residual/residual_parts.hpp), run as one
// part of a batch (`--part I/N`, then `pyramid merge`), or by every rank of an MPI team at once,
// rank 0 merging. Either way the files are a single process's, byte for byte.
#pragma once
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "libpyramid/distribute/team.hpp"
#include "libpyramid/encode/residual/residual_parts.hpp"

namespace pyramid {

// Runs the build (`encode`, with the share it is given in its options) as one share.
using ShareEncode = std::function<void(const ResidualShare&)>;

// Part `index` of `count` into partFileName(base, index, count), written atomically: base is the
// build's output file (DIR/DEM.dat) or its directory and name prefix (DIR/DEM). `job` identifies the
// build (the same in every part). Returns the part file's path.
std::string runResidualPart(int index, int count, const std::string& base, const nlohmann::json& job,
                            const ShareEncode& encode);

// Thrown on a rank other than 0 when the team's build failed: rank 0 says why.
class TeamFailed : public Error {
public:
    TeamFailed() : Error("the build failed on another rank") {}
};

// Every rank of `team` encodes its share into a part file in a hidden directory that rank 0 makes
// inside `directory` (after `prepare`, its output checks), and rank 0 merges the parts into
// `directory` (mergeResidualParts, reporting `mergeProgress`). A failure on any rank fails every
// rank and leaves nothing: rank 0 throws the failing rank's error (prefixed "rank R: " when it is
// another rank's), the others throw TeamFailed. Returns the merge's report on rank 0.
std::optional<ResidualMergeReport> runResidualTeam(Team& team, const std::string& directory, const std::string& partName,
                                                   const nlohmann::json& job, const std::function<void()>& prepare,
                                                   const ShareEncode& encode,
                                                   const std::function<void(int64_t, int64_t)>& mergeProgress);

} // namespace pyramid
