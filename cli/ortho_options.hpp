// The options preprocessOrtho and preprocessSphericalOrtho share (outputs, name, tile size,
// levels, channels, border, compressions, colour space, threads, cache, report, quiet),
// declared once and resolved into OrthoEncodeOptions once the command line is parsed.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "cli/cli_common.hpp"
#include "libpyramid/api/encoders.hpp"

namespace CLI {
class App;
class Option;
}

namespace pyramid::cli {

struct OrthoArgs {
    InputArgs input;
    // A whole number, or "auto" where the command takes it (its default there; the original
    // tools' 192 on cube faces, and where --max-level is given without --tile-size).
    std::string tileSize = "192";
    CLI::Option* tileSizeOption = nullptr; // to tell a --tile-size given from the default
    std::string output, outputs = "tiff,dxt,residuals", compression = "deflate",
                               residualCompression = "deflate", residualDeflateLevel = "auto", colourSpace = "srgb",
                               report;
    bool quiet = false;
    std::string part; // --part I/N
    std::string layout = "sparse"; // --layout sparse|dense (cube faces)
    RegionArgs region; // --region LEVEL,TX,TY, --parent FILE
    MaxFileBytesArgs maxFileBytes;
    OrthoEncodeOptions options;
};

// Declares INPUT, -o and the shared options on `app`, bound to `args`; with `tileSizeAuto`,
// --tile-size takes "auto" too (tiles fitted to a planar input: OrthoLevelsOptions::fitTiles).
void addOrthoOptions(CLI::App& app, const std::shared_ptr<OrthoArgs>& args, const char* inputHelp,
                     const char* outputHelp, const char* maxLevelHelp, bool tileSizeAuto = false);

// Declares --threads, --cache-mb, --max-file-bytes, --report and --quiet (after any
// command-specific options), and with `faces` --layout.
void addOrthoRunOptions(CLI::App& app, const std::shared_ptr<OrthoArgs>& args, bool faces = false);

// Throws Error naming the option when a value is not valid.
OrthoEncodeOptions resolveOrthoOptions(const OrthoArgs& args);

// The merged outputs' figures into a rank-0 report of its own share.
void takeMerged(OrthoReport& report, const OrthoReport& merged);

// One line per output file (tiles, shared tiles, bytes; a region set's files and the largest
// of them) and one for the levels, on stderr.
void printOrthoSummary(const OrthoReport& report);

} // namespace pyramid::cli
