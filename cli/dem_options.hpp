// The options preprocessDem and preprocessSphericalDem share (tile sizes, levels, scale,
// band, nodata, threads, cache, report, quiet), declared once and resolved into
// DemEncodeOptions once the command line is parsed.
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "cli/cli_common.hpp"
#include "libpyramid/api/encoders.hpp"

namespace CLI {
class App;
class Option;
}

namespace pyramid::cli {

struct DemArgs {
    InputArgs input;
    // A number of intervals (the library's default unless given), or "auto" where the command
    // takes it.
    std::string tileSize = std::to_string(DemEncodeOptions{}.tileSize);
    CLI::Option* rootTileSizeOption = nullptr; // counted: --tile-size auto chooses it
    std::string output; // a file (preprocessDem) or a directory (preprocessSphericalDem)
    std::string scale = "1";
    double maxError = 0.0;
    bool maxErrorGiven = false;
    int band = 1;
    std::string nodata;
    std::string report;
    ResidualCodingArgs coding; // --compression, --deflate-level
    bool quiet = false;
    MaxFileBytesArgs maxFileBytes;
    std::string layout = "sparse"; // --layout sparse|dense
    std::string part;         // --part I/N
    RegionArgs region;        // --region LEVEL,TX,TY, --parent FILE
    DemEncodeOptions options;
};

// Declares INPUT, -o and the shared options on `app`, bound to `args`. `tileSizeAuto`: the
// command takes `--tile-size auto` (planar inputs: preprocessDem); elsewhere `auto` is a usage
// error that says so.
void addDemOptions(CLI::App& app, const std::shared_ptr<DemArgs>& args, const char* inputHelp, const char* outputHelp,
                   const char* maxLevelHelp, bool tileSizeAuto = false);

// The encoder options the parsed arguments ask for; throws Error naming the option when a
// value is impossible. Prints the tile-size warning of the original runtime unless quiet.
DemEncodeOptions resolveDemOptions(const DemArgs& args);

// `--tile-size auto`'s choice on stderr, one line (and the original runtime's warning when its
// tiles are too large for it); for DemEncodeOptions::tileFitChosen.
void printTileFit(const DemTileFit& fit);

// The two summary lines of one residual file on stderr: tiles, levels, scale, bits per sample,
// time; the largest error against the bound, filled nodata and the sampling rule.
void printDemSummary(const DemReport& report);
// "INPUT: heights are band N's samples x SCALE + OFFSET (its GDAL metadata)", where the input's
// height band declares a scale or offset (RasterInfo::scaling); nothing otherwise.
void printValueScaling(const std::string& input, const RasterInfo& info, int band);

// The merged pyramid's figures into a rank-0 report of its own share.
void takeMerged(DemReport& report, const ResidualPyramidReport& merged);

} // namespace pyramid::cli
