// One ortho pyramid's tiles encoded from its true tiles into its outputs (or a share's part
// file), the step every encodeOrtho ends in (ortho_encoder.hpp): a plane's, with its
// georeference sidecar, or a cube face's.
#pragma once
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "formats/staging_directory.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_levels.hpp"

namespace pyramid {

// Writes the outputs and `companions` into `staging` (the caller commits it); the report names
// their final paths in `directory`. With o.share, the share's tiles go to its part file instead
// (and `staging` is null).
OrthoReport encodeOrthoLevels(const OrthoLevels& levels, const std::string& directory, StagingDirectory* staging,
                              const OrthoEncodeOptions& o,
                              const std::vector<std::pair<std::string, std::string>>& companions,
                              std::chrono::steady_clock::time_point start);

} // namespace pyramid
