// preprocessDem as a library call: an elevation raster in, a residual pyramid file out
// (doc/dem-encoding.md). Residuals are computed closed loop with the runtime's own arithmetic
// (libpyramid/filters/elevation_upsample.hpp), so the CPU and GL producers rebuild exactly what the
// encoder measured.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/residual_file.hpp"
#include "libpyramid/input/raster_source.hpp"

namespace pyramid {

struct DemEncodeOptions {
    int tileSize = 192;
    int rootTileSize = 24;          // tileSize >> minLevel
    int maxLevel = -1;              // -1: the smallest pyramid whose finest level holds every input sample
    double scale = 1.0;             // quantization step (height units per residual unit)
    bool autoScale = false;         // choose the smallest 1-2-5 x 10^k scale without int16 overflow
    int band = 0;                   // 0-based
    std::optional<double> nodata;   // overrides what the file declares
    bool ignoreDeclaredNodata = false;
    bool stretch = false;           // map width and height independently (the original behaviour)
    int threads = 0;                // 0: all cores
    int cacheMegabytes = 256;       // input cache budget
    // Called from one thread at a time with (tiles done, total tiles).
    std::function<void(int64_t, int64_t)> progress;
    // Called from one thread at a time with each tile's reconstruction ((n+5)^2 float32, row 0 =
    // bottom), exactly what a producer rebuilds from the file: for tests and inspection.
    std::function<void(int level, int tx, int ty, const std::vector<float>&)> reconstruction;
};

struct DemLevelReport {
    int level = 0;
    int64_t tiles = 0;
    int64_t samples = 0;     // valid source samples compared
    double maxError = 0.0;   // max |reconstruction - source|
    double rmsError = 0.0;
    int maxAbsResidual = 0;
};

struct DemReport {
    std::string input;
    std::string output;
    RasterInfo inputInfo;
    int band = 0;                 // 0-based, as DemEncodeOptions
    std::optional<double> nodata; // the nodata value used (option or declared), if any
    std::string sampling;    // the geometry rule applied
    ResidualHeader header;
    int64_t tiles = 0;
    int64_t sharedTiles = 0;
    uint64_t bytes = 0;      // file size
    int64_t finestSamples = 0;
    int64_t nodataFilled = 0; // finest-grid samples without a source height, filled
    std::vector<DemLevelReport> levels;
    std::vector<double> scalesTried; // --scale auto
    int threads = 0;
    double seconds = 0.0;
};

// The height band and nodata value the options select in an input: throws Error naming --band
// when the input has no such band; the nodata value is the option's, else what the file declares
// (unless options.ignoreDeclaredNodata), else none.
std::optional<double> checkBandAndNodata(const RasterInfo& input, const DemEncodeOptions& options,
                                         const std::string& where);

// The finest level's interval count for an input and options (maxLevel resolved).
ResidualHeader planDemPyramid(const RasterInfo& input, const DemEncodeOptions& options, const std::string& where);

// Encodes `input` into the residual file `output` (written atomically). Throws Error with a
// one-line message on bad input, impossible options or int16 overflow (which names the
// smallest scale that would fit).
DemReport encodeDem(const std::string& input, const std::string& output, const DemEncodeOptions& options);

nlohmann::json toJson(const DemReport& report);

// The "input" object of the DEM reports: path, size, channels, sample type, format, band (from
// 1) and the nodata value used (null, a number, or "nan": JSON has no NaN).
nlohmann::json demInputJson(const std::string& path, const RasterInfo& info, int band, std::optional<double> nodata);

} // namespace pyramid
