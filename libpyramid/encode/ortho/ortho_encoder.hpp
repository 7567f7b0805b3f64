// preprocessOrtho as a library call: imagery in, up to three ortho pyramid files out, as the
// original tools write them (doc/ortho-encoding.md):
//   DIR/NAME.dat            plain tiles, TIFF (lossless Deflate by default)
//   DIR/dxt/NAME.dat        DXT1 (1-3 channels, expanded to RGB) or DXT5 (4 channels)
//   DIR/residuals/NAME.dat  colour residuals for the colour-residual producer, closed loop
// With maxFileBytes, each of them is a region set when it does not fit (formats/ortho_set.hpp):
//   DIR/NAME.dat, DIR/NAME-L6-12-40.dat, ..., DIR/NAME.dat.regions.json (and so in dxt/, residuals/)
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/ortho_file.hpp"
#include "formats/staging_directory.hpp"
#include "libpyramid/encode/region_request.hpp"
#include "libpyramid/encode/ortho/ortho_levels.hpp"
#include "libpyramid/input/pyramid_georeference.hpp"

namespace pyramid {

// Original: JPEG inside, Deflate on the outer edge. JpegYCbCr: JPEG tiles as YCbCr 4:2:0, not
// readable by the original runtime (formats/ortho_file.hpp).
enum class TilePolicy { Deflate, Lzw, Jpeg, JpegYCbCr, None, Original };

class PartOutput;

// One process's share of a build split across processes (support/work_share.hpp,
// doc/planet-scale.md): part `index` of `count`, whose tiles go to `out` instead of the outputs.
struct OrthoShare {
    int index = 0;
    int count = 1;
    PartOutput* out = nullptr;
};

// The format ortho builds' part files name in their trailers (formats/part_file.hpp).
inline constexpr const char* kOrthoPartFormat = "libpyramid ortho part";

struct OrthoEncodeOptions {
    OrthoLevelsOptions levels;
    std::string name = "RGB";
    bool writeTiff = true;
    bool writeDxt = true;
    bool writeResiduals = true;
    int border = 2;                  // 2 or 0 (TIFF and DXT files; residual files always have 2)
    TilePolicy compression = TilePolicy::Deflate;
    int jpegQuality = 90;
    // Deflate TIFF tiles: libdeflate's level, 1 to 12. With the horizontal predictor, which
    // turns neighbouring colours into small differences, level 1 gives files 20 to 35 % smaller
    // than level 6 without it, in about a third of the time (bench/ortho_bench.md); higher levels
    // give a few % fewer bytes in several times the time.
    int deflateLevel = 1;
    // JPEG TIFF tiles are decoded again to measure their error (tiff_max_error): off by default,
    // as the decoding costs about a sixth of a JPEG run; `pyramid verify` measures it afterwards.
    bool measureJpegError = false;
    int dxtQuality = 1;              // 0 fastest .. 3 best (formats/dxt_codec.hpp)
    TilePolicy residualCompression = TilePolicy::Deflate; // Deflate or Jpeg
    // Deflate colour residual tiles (no predictor: residuals hover around 128, they are not
    // smooth): libdeflate's level, 1 to 12, or 0 to choose per tile the faster of levels 1 and
    // 2 from the tile's residuals (doc/ortho-encoding.md, "Compression policy of TIFF tiles"):
    // level 2 where they are smooth, level 1 where they are grainy.
    int residualDeflateLevel = 0;
    // 0: each output one file (ortho files have 64-bit offsets: no size limit). Otherwise each
    // output is a region set of files of at most this many bytes each, with its index
    // (formats/ortho_set.hpp, doc/planet-scale.md); an output that fits is the one file a build
    // without it writes, byte for byte, and an index of no regions.
    uint64_t maxFileBytes = 0;
    // Sparse: a cube face the input does not fill is written as sparse sets, the files that hold
    // its data (doc/format.md 1.5, "Sparse sets"; formats/sparse_set.hpp): blank subtrees are
    // neither walked nor stored, and readers find no tile there (for colour residuals, residual
    // 128). A face the input fills, and a plane, are one file (or a maxFileBytes set) as Dense
    // writes it.
    PyramidLayout layout = PyramidLayout::Sparse;
    // Set: encode only this region (region_request.hpp), each output as one region file named as
    // a set names its files (DIR/NAME-L6-12-40.dat, dxt/..., residuals/...), without the planar
    // georeference sidecar (the main file's places it). Its parent is the enclosing pyramid's
    // colour-residual file or set (residuals/NAME.dat). Neither a share nor with maxFileBytes.
    std::optional<RegionRequest> region;
    // Set in each process of a split build: encode only this share, into its part file; this
    // pyramid is `pyramid` of the build's `pyramids` (a cube face among the faces built).
    const OrthoShare* share = nullptr;
    int pyramid = 0;
    int pyramids = 1;
    // A build in two walks (colour residuals beside TIFF or DXT tiles) keeps the first walk's
    // subtrees for the second when they fit in this many bytes (ortho_kept_subtrees.hpp): the
    // input is then sampled once. 0: never (the second walk samples the input again). The
    // files are the same bytes either way.
    int64_t keptSubtreeBytes = int64_t{64} << 20;
    std::function<void(int64_t, int64_t)> progress;       // (tiles done, total), one thread at a time
    // Asked after every tile, from one thread at a time: true stops the encoding, which throws
    // Cancelled (formats/error.hpp) and leaves no file behind.
    std::function<bool()> cancelled;
    // Called from one thread at a time with each tile's colour-residual reconstruction
    // ((tileSize+4)^2 x channels), exactly what the colour-residual producer rebuilds: for tests.
    std::function<void(int level, int tx, int ty, const std::vector<uint8_t>&)> colourReconstruction;

    // The checks that do not need the input (levels has its own); encodeOrtho checks the others
    // against it. Throws OptionError naming the field.
    void validate() const;
};

struct OrthoLevelReport {
    int level = 0;
    int64_t tiles = 0;
    int tiffMaxError = 0;      // decoded TIFF tile vs the true tile (0 when lossless)
    int64_t jpegTiles = 0;     // JPEG TIFF tiles: their error is measured only on request
    double dxtPsnr = 0.0;      // dB over the level's tiles (infinity written as 99)
    int residualMaxError = 0;  // colour-residual reconstruction vs the true tile
    double residualRmsError = 0.0;
    int64_t clampedResiduals = 0;
};

struct OrthoReport {
    std::string input;
    std::string directory;
    std::vector<std::string> outputs;
    std::string sampling;
    int inputWidth = 0, inputHeight = 0, channels = 0;
    int tileSize = 0, maxLevel = 0, border = 0; // a region's maxLevel counts from its root
    std::optional<RegionRoot> region;           // options.region's root
    int64_t tiles = 0;
    std::vector<uint64_t> bytes;     // per output (a region set: the total of its files)
    // Per output, with maxFileBytes: its region set's files, the main first, named relative to
    // `directory` ("dxt/RGB-L6-12-40.dat"), and their sizes; empty lists without maxFileBytes.
    std::vector<std::vector<std::pair<std::string, uint64_t>>> files;
    std::vector<int64_t> sharedTiles;
    std::vector<OrthoLevelReport> levels; // a region's counted from its root, as its files count them
    bool jpegErrorMeasured = false; // options.measureJpegError
    // A georeferenced input's placement of the pyramid (planar pyramids only), also written as
    // DIR/NAME.dat.georef.json.
    std::optional<PyramidGeoreference> georeference;
    int threads = 0;
    double seconds = 0.0;
};

// The outputs appear together when every one is complete (formats/staging_directory.hpp), or
// not at all.
OrthoReport encodeOrtho(const std::string& input, const std::string& directory, const OrthoEncodeOptions& options);
// A mosaic of georeferenced images on one grid, in priority order (input/raster_mosaic.hpp).
OrthoReport encodeOrtho(const std::vector<std::string>& inputs, const std::string& directory,
                        const OrthoEncodeOptions& options);
// A raster already open (a caller's own pixels: RasterSource::fromPixels); options.levels.target
// does not apply.
OrthoReport encodeOrtho(const RasterSource& source, const std::string& directory, const OrthoEncodeOptions& options);
// The same from true tiles already set up (e.g. one cube face), into a staging directory of
// `directory` that the caller commits (with the other faces): options.levels is not used, the
// files are named options.name.
OrthoReport encodeOrtho(const OrthoLevels& levels, const std::string& directory, StagingDirectory& staging,
                        const OrthoEncodeOptions& options);

// The same as one share of a split build (options.share set): its tiles into the share's part file.
OrthoReport encodeOrthoShare(const OrthoLevels& levels, const std::string& directory, const OrthoEncodeOptions& options);

nlohmann::json toJson(const OrthoReport& report);

} // namespace pyramid
