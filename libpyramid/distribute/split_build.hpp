// A build split into shares (support/work_share.hpp; encode/residual/residual_parts.hpp,
// encode/ortho/ortho_parts.hpp), run as one part of a batch (`--part I/N`, then `pyramid merge`),
// or by every rank of an MPI team at once, rank 0 merging. Either way the files are a single
// process's, byte for byte.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "libpyramid/distribute/team.hpp"
#include "libpyramid/encode/ortho/ortho_parts.hpp"
#include "libpyramid/encode/residual/residual_parts.hpp"

namespace pyramid {

// What one share of a split build is told: which part of how many, its part file, and (in a
// team) how to agree with the other parts on an int16 overflow (ResidualShare::agree).
struct PartContext {
    int index = 0;
    int count = 1;
    PartOutput* out = nullptr;
    std::function<std::optional<ResidualOverflow>(const std::optional<ResidualOverflow>&)> agree;
};
// Runs the build as one share (a residual build makes a ResidualShare of it, an ortho one an
// OrthoShare).
using PartEncode = std::function<void(const PartContext&)>;

// Part `index` of `count` into partFileName(base, index, count), written atomically: base is the
// build's output file (DIR/DEM.dat) or its directory and name prefix (DIR/DEM). `format` is the
// kind of build (kResidualPartFormat, kOrthoPartFormat); `job` identifies the build (the same in
// every part). Returns the part file's path.
std::string runPart(int index, int count, const std::string& base, const std::string& format, const nlohmann::json& job,
                    const PartEncode& encode);

// Thrown on a rank other than 0 when the team's build failed: rank 0 says why.
class TeamFailed : public Error {
public:
    TeamFailed() : Error("the build failed on another rank") {}
};

// Every rank of `team` encodes its share into a part file in a hidden directory that rank 0 makes
// inside `directory` (after `prepare`, its output checks), and rank 0 merges the parts
// (`merge`, given every part file in order) into `directory`. A failure on any rank fails every
// rank and leaves nothing: rank 0 throws the failing rank's error (prefixed "rank R: " when it is
// another rank's), the others throw TeamFailed.
void runTeam(Team& team, const std::string& directory, const std::string& partName, const std::string& format,
             const nlohmann::json& job, const std::function<void()>& prepare, const PartEncode& encode,
             const std::function<void(const std::vector<std::string>&)>& merge);

} // namespace pyramid
