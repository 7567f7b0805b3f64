// The pieces `pyramid preview` draws with (preview.cpp for planes, planet_preview.cpp for the six
// cube faces of a planet): one level of a pyramid set read tile by tile through the runtime's
// producers, sampled at its own samples or between them; the colours of elevation styles; and a
// level drawn as rows of pixels, north first, one row of tiles at a time.
#pragma once
#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/preview/png_writer.hpp"
#include "libpyramid/preview/preview.hpp"
#include "libpyramid/preview/shading.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"

namespace pyramid::preview {

// A level's samples a side: a DEM level of tiles of n intervals has tiles x n + 1 vertices, an
// ortho level 2^L x tileSize pixels.
int64_t elevationLevelSide(const ResidualHeader& h, int level);
int64_t orthoLevelSide(const OrthoHeader& h, int level);

// The level drawn: `o.level`, or the deepest whose side is at most `limit` (level 0 at least).
// Throws OptionError("level") for a level beyond `deepest`.
int chooseLevel(const PreviewOptions& o, int deepest, int64_t limit, const std::function<int64_t(int)>& side,
                const std::string& name);

// One level of an elevation set: the heights the runtime's elevation producer makes, or (when
// `residuals`) the stored residuals times the scale. Tiles of n intervals, `across` a side.
class ElevationGrid {
public:
    ElevationGrid(const PyramidSet& set, int level, bool residuals, size_t cacheTiles);
    int across() const { return across_; }
    int n() const { return n_; }
    int64_t side() const { return int64_t{across_} * n_ + 1; }
    // Vertex (i, j) of tile (tx, ty), i and j in -2 .. n + 2 (its borders), row 0 the south.
    float at(int tx, int ty, int i, int j);
    // The level between its vertices, x and y in 0 .. side - 1 (runtime/level_heights.hpp).
    double bilinear(double x, double y);
    // The lowest and highest finite sample of the level's tiles (0, 0 when there is none).
    std::pair<double, double> range();

private:
    void load(int tx, int ty);
    PyramidSet set_;
    int level_ = 0;
    bool residuals_ = false;
    float scale_ = 1.0f;
    int across_ = 1, n_ = 0;
    FileLevelProducer producer_;
    int64_t key_ = -1; // the tile loaded
    std::shared_ptr<const ElevationTile> tile_;
    StoredResidualTile stored_;
    const float* heights_ = nullptr;
};

// One level of an ortho set, or of a colour-residual set (a file in a residuals/ directory, as
// preprocessOrtho names it) as the colours the colour producer rebuilds.
class ColourGrid {
public:
    // `producer` reads `set` (openOrthoSet).
    ColourGrid(const PyramidSet& set, std::shared_ptr<OrthoProducer> producer, int level, size_t cacheTiles);
    int across() const { return across_; }
    int tileSize() const { return tileSize_; }
    int border() const { return border_; }
    int channels() const { return channels_; }
    bool residuals() const { return bool(colours_); }
    int64_t side() const { return int64_t{across_} * tileSize_; }
    // Tile (tx, ty): (tileSize + 2 border)^2 pixels of `channels`, row 0 the south.
    const uint8_t* tile(int tx, int ty);
    // The level between its pixel centres (pixel k's centre at k, -0.5 .. side - 0.5 reaching
    // into the borders), bilinear, into `out` (channels bytes).
    void bilinear(double x, double y, uint8_t* out);

private:
    std::shared_ptr<OrthoProducer> producer_;
    std::unique_ptr<ColourProducer> colours_;
    int level_ = 0, across_ = 1, tileSize_ = 0, border_ = 0, channels_ = 3;
    size_t capacity_ = 1;
    std::list<std::pair<int64_t, std::shared_ptr<const std::vector<uint8_t>>>> tiles_; // most recent first
    std::unordered_map<int64_t, decltype(tiles_)::iterator> index_;
};

// The colours of the elevation styles (hillshade, shade, heights, residuals) over a range.
struct ElevationPaint {
    PreviewStyle style = PreviewStyle::Hillshade;
    double lo = 0.0, hi = 0.0;         // the heights' range, or the residuals'
    std::optional<double> seaLevel;    // heights at or below it drawn as water
    double zFactor = 1.0, azimuth = 315.0, altitude = 45.0;
    ElevationPaint(PreviewStyle style, double lo, double hi, const PreviewOptions& o);
    bool shading() const { return style == PreviewStyle::Hillshade || style == PreviewStyle::Shade; }
    // The colour of value `v` before any shading (black when it is not finite).
    Rgb8 base(double v) const;
    // The colour of value `v` whose slopes are dz/dx (east) and dz/dy (north), in height units
    // per ground unit (read by the shading styles only).
    Rgb8 colour(double v, double dzdx, double dzdy) const;
    // The legend's values: its left and right ends (residuals: symmetric about 0).
    double legendLow() const;
    double legendHigh() const;
};

// A level drawn as rows of pixels, north first, in strips of rows (one row of tiles each).
struct LevelImage {
    int64_t side = 0; // pixels a side
    int channels = 3;
    int strips = 0;
    // Strip s (0 = the northernmost) into `rows` (its rows of side x channels bytes, north
    // first); returns how many rows it holds.
    std::function<int(int, std::vector<uint8_t>&)> strip;
};

// Ground distances between a DEM level's neighbouring samples along x and y at vertex (i, j)
// of tile (tx, ty), in height units.
using SampleSpacing = std::function<std::array<double, 2>(int tx, int ty, int i, int j)>;

// An elevation level drawn by `paint`: every vertex a pixel (a tile's last row and column are its
// neighbour's first, drawn once), slopes from central differences within the tile (its borders
// at its edges).
LevelImage elevationImage(ElevationGrid& grid, const ElevationPaint& paint, const SampleSpacing& spacing);
// An ortho level drawn as its tiles' pixels, borders cut.
LevelImage colourImage(ColourGrid& grid);

// Rows appended below an elevation image: a colour bar of `paint`'s base colours from its
// legend's low end (left) to its high end (right), the two values written under its ends (and
// 0 under its middle for residuals). Returns the rows (width x 3 bytes each, top first).
std::vector<std::vector<uint8_t>> legendRows(int64_t width, const ElevationPaint& paint);

// The style an elevation set is drawn in (auto: hillshade); throws OptionError for colours, and
// for a legend of the shade style (it has no colour scale).
PreviewStyle elevationStyle(const PreviewOptions& o, const std::string& name);
// Checks that an ortho set can be drawn as asked (colours, no legend); throws OptionError.
void checkColourStyle(const PreviewOptions& o, const std::string& name);

// The PNG's text: Software, Source, Level, Style, Projection (planets), and for elevations the
// range as exact decimals ("Minimum height", "Maximum height" or "... residual").
std::vector<PngText> previewText(const std::string& source, const PreviewReport& report);
// Every strip of `image`, in order.
void writeImage(PngWriter& png, const LevelImage& image);

} // namespace pyramid::preview
