// Ortho builds split across processes (doc/planet-scale.md): each process encodes its share of
// the tiles of every output (TIFF, DXT, colour residuals) into a part file (formats/part_file.hpp,
// one stream per pyramid and output), and the merge replays the parts in order into the output
// writers: the files are a single run's, byte for byte.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/encode/ortho/ortho_encoder.hpp"

namespace pyramid {

struct OrthoMergeReport {
    int parts = 0;
    std::string directory;
    // Per pyramid (a face), in the build's order: its outputs' paths, bytes, files, shared tiles
    // and per-level statistics.
    std::vector<OrthoReport> pyramids;
    double seconds = 0.0;
};

// Checks that `parts` are every part of one ortho build (readPartSet) and writes its outputs
// into `directory` as a single run puts them in place (one file or a set each, the sidecar), all
// appearing together. `progress(done, total)` counts tiles. Throws Error naming the part file and
// the problem; writes nothing then.
OrthoMergeReport mergeOrthoParts(const std::vector<std::string>& parts, const std::string& directory,
                                 const std::function<void(int64_t, int64_t)>& progress = {});

nlohmann::json toJson(const OrthoMergeReport& report);

} // namespace pyramid
