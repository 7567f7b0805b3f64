// Recoding a residual file: the same residuals in every tile, stored with another codec
// (formats/residual_codec.hpp), e.g. the original tools' files made smaller with context coding,
// or context-coded files made readable again by the original runtime. `pyramid recode`.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "formats/residual_codec.hpp"
#include "formats/residual_file.hpp"

namespace pyramid {

struct ResidualRecodeOptions {
    ResidualTileCoding tiles;
    int threads = 0; // 0: all cores; the file does not depend on it
    // Called from one thread at a time with (tiles done, total tiles).
    std::function<void(int64_t, int64_t)> progress;
};

struct ResidualRecodeReport {
    std::string input, output;
    ResidualHeader header;
    ResidualTileCoding coding;
    int64_t tiles = 0;
    int64_t sharedTiles = 0; // tiles that reuse another tile's bytes in the output
    uint64_t inputBytes = 0, bytes = 0;
    int threads = 0;
    double seconds = 0.0;
};

// Reads every tile of `input` (a residual file, not a region set), codes its residuals as
// `options.tiles` says and writes `output` atomically, with the same header and the tiles in
// the same order. `output` may be `input` (replaced once the new file is complete). Tiles that
// share bytes in the input are decoded once. Throws Error naming the file for a file that is
// not a residual pyramid or a tile that does not decode; OptionError for the options.
ResidualRecodeReport recodeResidualFile(const std::string& input, const std::string& output,
                                        const ResidualRecodeOptions& options);

nlohmann::json toJson(const ResidualRecodeReport& report);

} // namespace pyramid
