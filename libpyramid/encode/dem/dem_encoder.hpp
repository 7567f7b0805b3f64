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
#include "libpyramid/encode/dem/dem_tile_fit.hpp"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"
#include "libpyramid/input/pyramid_georeference.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"

namespace pyramid {

// The options of a DEM pyramid: its shape and how the input is read, on top of the residual
// encoder's (scale, threads, hooks).
struct DemEncodeOptions : ResidualEncodeOptions {
    int tileSize = 192;
    int rootTileSize = 24;          // tileSize >> minLevel
    // The file's maxLevel, counted from the root (level 0, one tile of rootTileSize
    // intervals), minLevel to 24; none: the smallest pyramid whose finest level holds every
    // input sample.
    std::optional<int> maxLevel;
    // The same level counted as the original tools' preprocessDem counts it (dstMaxLevel), from
    // the first level of full-size tiles: maxLevel = minLevel + dstMaxLevel, with minLevel =
    // log2(tileSize / rootTileSize), so 0 to 24 - minLevel. At most one of maxLevel and
    // dstMaxLevel.
    std::optional<int> dstMaxLevel;
    // `--tile-size auto`: tileSize, rootTileSize and maxLevel are chosen from the input's size
    // by fitDemTiles (dem_tile_fit.hpp), so that the finest level is the input's grid; the
    // three fields above are then ignored, and maxLevel and dstMaxLevel may not be given.
    // Planar inputs only: the cube faces of preprocessSphericalDem refuse it.
    bool fitTiles = false;
    // With fitTiles: called once the input is open and the fit chosen, before any encoding
    // (the programs print it).
    std::function<void(const DemTileFit&)> tileFitChosen;
    int band = 0;                   // 0-based
    std::optional<double> nodata;   // overrides what the file declares
    bool ignoreDeclaredNodata = false;
    bool stretch = false;           // map width and height independently (the original behaviour)
    int cacheMegabytes = 256;       // input cache budget, at least 1
    PlanarTarget target;            // the CRS and extent a mosaic (or one file) is resampled onto

    // Throws OptionError for values no input can take: tileSize, rootTileSize, maxLevel and
    // dstMaxLevel (together, outside their range, or with fitTiles), cacheMegabytes, scale.
    void validate() const;
    // minLevel = log2(tileSize / rootTileSize), of options that validate().
    int minLevel() const;
};

// What the encoder measured (ResidualPyramidReport), and of which input.
struct DemReport : ResidualPyramidReport {
    std::string input;               // the input, or the first of several and how many more
    std::vector<std::string> inputs; // every file read, in priority order
    std::string output;
    RasterInfo inputInfo;
    int band = 0;                 // 0-based, as DemEncodeOptions
    std::optional<double> nodata; // the nodata value used (option or declared), if any
    std::string sampling;         // the geometry rule applied
    ResidualTileCoding coding;    // how the tiles were coded (options.tiles)
    std::optional<DemTileFit> tileFit; // with options.fitTiles: the tiles and levels chosen
    // A georeferenced input's placement of the pyramid, also written beside the output
    // (georeferenceSidecarPath(output)).
    std::optional<PyramidGeoreference> georeference;
    double seconds = 0.0;
};

// The height band and nodata value the options select in an input: throws OptionError("band")
// when the input has no such band; the nodata value is the option's, else what the file declares
// (unless options.ignoreDeclaredNodata), else none. A value other than the file's own on a band
// whose heights are read converted (heightsConverted: a scale, an offset or another unit) throws
// OptionError("nodata"): reading keeps only the file's own nodata value as stored.
std::optional<double> checkBandAndNodata(const RasterInfo& input, const DemEncodeOptions& options,
                                         const std::string& where);

// The pyramid's header for an input and options: maxLevel resolved (the default from the
// input's size; `where` names the input when that default makes too many tiles), and with
// options.fitTiles the tiles too (the fit into `fit`, when given).
ResidualHeader planDemPyramid(const RasterInfo& input, const DemEncodeOptions& options, const std::string& where,
                              DemTileFit* fit = nullptr);

// Encodes `input` into the residual file `output` (written atomically), and a georeferenced
// input's placement into the sidecar georeferenceSidecarPath(output) (atomically, after it). Throws Error with a
// one-line message on bad input, impossible options or int16 overflow (which names the
// smallest scale that would fit).
DemReport encodeDem(const std::string& input, const std::string& output, const DemEncodeOptions& options);
// A mosaic of georeferenced files on one grid, in priority order (input/raster_mosaic.hpp:
// read as the stitched raster would be; files on other grids are refused by name).
DemReport encodeDem(const std::vector<std::string>& inputs, const std::string& output, const DemEncodeOptions& options);
// A raster already open (a caller's own heights: RasterSource::fromPixels); options.target does
// not apply.
DemReport encodeDem(const RasterSource& source, const std::string& output, const DemEncodeOptions& options);

nlohmann::json toJson(const DemReport& report);
// The report's "tile_fit": the tiles and levels chosen, whether the fit is exact, finest
// intervals per input interval ("resampling"), whether the original runtime reads the tiles,
// and the rule in one sentence.
nlohmann::json toJson(const DemTileFit& fit);

// The band's scale and offset (RasterInfo::scaling) as the reports' "values": {"scale",
// "offset", "from"}, or null where its values are as stored.
nlohmann::json valueScalingJson(const RasterInfo& info, int band);

// The "input" object of the DEM reports: path, size, channels, sample type, format, band (from
// 1) and the nodata value used (null, a number, or "nan", "inf", "-inf": JSON has neither NaN
// nor infinities).
nlohmann::json demInputJson(const std::string& path, const RasterInfo& info, int band, std::optional<double> nodata);

} // namespace pyramid
