// The true tiles of an ortho pyramid, computed from an input image in bounded memory
// (doc/ortho-encoding.md): shared by preprocessOrtho and `pyramid verify`.
//
// Geometry. The finest level M is W = tileSize << M pixels across the root quad; its pixel
// (x, y), y = 0 at the south, is input pixel (x, W - 1 - y) when the input is W x W pixels
// (pixel exact). Otherwise the input is resampled bilinearly at pixel centres: input position
// X = (x + 0.5) * s - 0.5, Y = (W - 1 - y + 0.5) * s - 0.5 with s = max(width, height) / W (aspect
// kept, input at the north-west corner, pixels beyond it are 0 in every channel, i.e. black
// and transparent) or, with stretching, s = width / W and height / W per axis. 16-bit input is
// brought to 8 bits at the finest level: v8 = round(v16 * 255 / 65535).
//
// Cube faces. A pyramid may instead hold one face of a spherical planet (cube_faces.hpp): the
// finest level is then the face grid of W pixel centres per side, pixel (x, y) being the
// equirectangular input sampled at the geodetic point of its cube point (face_sampler.hpp),
// bilinearly, and converted to 8 bits as above; points outside the input's extent are 0 in
// every channel. By default M is the smallest level with W >= width / 4 (a face spans 90
// degrees of longitude at the equator).
//
// Levels. Level l < M is the 2x2 average of level l + 1 (colour_average.hpp). Tiles carry a
// border of 2 pixels taken from the neighbouring tiles of the same level; beyond the map's edge
// the edge pixels repeat. A face has no such edge: its levels are computed with a margin beyond
// the face (folded onto the neighbouring faces), so every border pixel at every level is the
// neighbouring face's pixel at the same cube point, bit for bit (both are the same averages of
// the same finest samples, as the face edges fall between 2x2 blocks at every level).
//
// Several resolutions. An input whose parts differ in resolution (a coarse base and fine insets:
// a planar mosaic's RasterInfo::parts, a planet's map of several members) has resolution where
// its parts are: a part needs the levels down to its own (the first whose width holds its
// pixels, by the rule that gives M), and a tile (l, tx, ty) is in the pyramid when its parent is
// and a part needing level l may reach its interior (PixelSource::mayNeedLevel). Below the
// others, a reader magnifies their parent (doc/format.md 1.5, "Sparse sets"). A pixel of level l
// is then the 2x2 average of level l + 1 where the level-(l + 1) tile over it is in the pyramid,
// and otherwise the input sampled at its own centre (PixelSource::sampleAt): a coarse base is
// read at its own level, not resampled at the inset's. Every walk is pruned; a face's pixels
// beyond its edge (borders) are sampled at their own level. An input of one resolution is
// walked as above, to the same bytes.
//
// Order and memory. Deeper tiles come in subtrees: for each tile of level C + 1
// (C = max(0, M - 4)), its footprint is read from the input, reduced level by level, and its
// subtree's tiles are produced depth first (pre-order). Levels 0..C are held in memory whole,
// in blocks of which only those the input may reach are stored (sparse_level.hpp; a tile no
// stored block meets is handed out blank, as a subtree wholly beyond the input is):
// either built first in a streaming pass over the input (bands of 2^(M-C) rows reduced as they
// are read), when every tile must come after its parent, or assembled from the subtrees'
// level-(C+1) tiles, reduced once more (and, for a face, its margin from bands of its own),
// and produced after them. For a
// face, level C is built with 2 << C pixels beyond each side (level l then has 2 << l, at least
// the border), and a footprint is the tile and its border, wherever they lie; tileSize must be
// at least 4 so that the margin stays within half a face of the edge.
//
// The code. What differs between a plane and a face is behind PixelSource (pixel_source.hpp):
// the finest pixels, the margin beyond the map and the border rule, from planar_pixels.hpp or
// face_pixels.hpp; ortho_levels.cpp reduces the levels, cuts the tiles and walks them in either
// order for both.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "libpyramid/filters/colour_average.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

struct OrthoLevelsOptions {
    int tileSize = 192;
    // 0 to 20; none: the smallest level whose width holds the input's longer side (face: width / 4).
    std::optional<int> maxLevel;
    // Planar only, without maxLevel: tileSize and maxLevel fitted to the input's longer side L
    // instead (fitOrthoTiles): the fewest levels whose tiles of at most 256 pixels hold L, and the
    // smallest tile size, a multiple of 4 (DXT blocks), that does, so that the finest level is
    // L pixels wide or at most 4 x 2^M - 1 more (192-tiles resample a 4096-pixel map onto 6144).
    bool fitTiles = false;
    std::optional<int> channels; // the first `channels` (1 to min(4, the input's)); none: every input channel (1..4)
    ColourSpace colourSpace = ColourSpace::Srgb;
    bool stretch = false; // planar only
    int threads = 0;
    int cacheMegabytes = 256; // at least 1
    PlanarTarget target; // planar only: the CRS and extent a mosaic (or one file) is resampled onto

    // The checks that do not need the input (tileSize, maxLevel, threads, cacheMegabytes);
    // OrthoLevels checks the others against it. Throws OptionError naming the field.
    void validate() const;
};

// The tile size and maxLevel OrthoLevelsOptions::fitTiles chooses for a longer side of `side`
// pixels (at least 1): maxLevel M the smallest with 256 << M >= side, tileSize the smallest
// multiple of 4 with tileSize << M >= side.
struct OrthoTileFit {
    int tileSize = 0;
    int maxLevel = 0;
};
OrthoTileFit fitOrthoTiles(int64_t side);

// One tile of the pyramid with a 2-pixel border: (tileSize + 4)^2 x channels, row 0 = south.
struct TrueTile {
    int level = 0, tx = 0, ty = 0;
    Image8 pixels;              // empty when blank (image() gives the walk's tile of 0s)
    bool blank = false;         // known to be 0 everywhere without looking (beyond the input)
    const Image8* zero = nullptr; // blank: the walk's one tile of 0s, shared by every blank tile
    // A pruned walk's blank tile under a tile that is not: this tile and every tile below it are
    // blank, and the walk hands out none of those below (blank is set too).
    bool blankBelow = false;
    // An input of several resolutions has none of its own here: no part needs this tile's level
    // over it. The tile and every tile below it are not in the pyramid (a reader magnifies the
    // parent); blank and blankBelow are set too, and the pixels are not the tile's.
    bool beyond = false;

    const Image8& image() const { return blank ? *zero : pixels; }
    // A blank tile (level, tx, ty) whose pixels are `zero`, a tile of 0s that outlives it.
    static TrueTile blankAt(int level, int tx, int ty, const Image8* zero) {
        TrueTile t;
        t.level = level;
        t.tx = tx;
        t.ty = ty;
        t.blank = true;
        t.zero = zero;
        return t;
    }
};

// A unit of work handed to the consumer: tiles in pyramid order, each tile after its parent
// when both are in the same item.
using TileBatch = std::vector<TrueTile>;

class OrthoLevels {
public:
    // A planar pyramid of the image file `input`.
    OrthoLevels(const std::string& input, const OrthoLevelsOptions& options);
    // Of a mosaic of georeferenced files on one grid, in priority order (input/raster_mosaic.hpp).
    OrthoLevels(const std::vector<std::string>& inputs, const OrthoLevelsOptions& options);
    // A planar pyramid of a raster already open (a caller's own pixels: RasterSource::fromPixels),
    // which must outlive this object. options.target does not apply.
    OrthoLevels(const RasterSource& source, const OrthoLevelsOptions& options);
    // Cube face `face` (1..6) of `body`, from the image `source` placed by `placement` (a plate
    // carree over an extent, or georeferenced), or with `map` from that map (several images each
    // placed by its own georeferencing; `source` is then one of them, for its description).
    // `source` and `map` must outlive this object; they may serve several faces at once.
    OrthoLevels(const RasterSource& source, const MapPlacement& placement, const PlanetBody& body, int face,
                const OrthoLevelsOptions& options, const GeodeticMap* map = nullptr);
    ~OrthoLevels();

    int tileSize() const;
    int maxLevel() const;
    int channels() const;
    int inputWidth() const;
    int inputHeight() const;
    const std::string& inputPath() const;
    const RasterInfo& inputInfo() const;
    const std::string& sampling() const; // the geometry rule applied, one sentence
    int64_t tileCount() const;
    int threads() const;                 // options.threads, or every available thread

    // Hands the whole pyramid to `sink`, item by item, and returns the number of the walk's
    // items (each handed out, unless the sink stops the walk or an item fails). An item is
    // either a subtree (its tiles in pre-order: a tile, then its children's subtrees) or a whole
    // level of 0..C (its tiles in Z order). The items' order, which numbers them from 0, is
    // deterministic (it does not depend on the thread count):
    //  * CoarseFirst: one item per level 0..C, then one item per level-(C+1) subtree, in Z
    //    order: every tile after its parent.
    //  * SinglePass: one item per level-(C+1) subtree, row by row from the north edge (the
    //    face's +y edge), west to east, then one item per level 0..C; the finest level is
    //    sampled once instead of twice (a face's margin beyond it excepted).
    enum class WalkOrder { CoarseFirst, SinglePass };
    struct Sink {
        // A subtree: each is sampled and handed over by one of the walk's threads (OpenMP), in
        // parallel with the others, as soon as its pixels are read; the subtrees are taken in
        // order (a thread takes the next one when it is free). False stops the walk: no
        // further item is handed out.
        std::function<bool(int64_t index, TileBatch& item)> subtree;
        // A level of 0..C, from the calling thread, which may work on it in parallel: the levels
        // are handed out one after the other, never while a subtree is.
        std::function<bool(int64_t index, TileBatch& item)> level;
        // Item `index` failed: called on its thread, before the walk stops handing out items,
        // so that a sink holding later items back until this one is delivered can release them.
        // walk() then rethrows the exception of the lowest failed index, once the items in
        // progress are done.
        std::function<void(int64_t index)> failed;
        // The walk is the last to read the input: a SinglePass walk of every item then lets an
        // input opened from files give back the rows its subtrees have passed (a decoded
        // image's memory); a caller's RasterSource keeps them.
        bool lastRead = false;
    };
    // A share of a walk (a build split across processes: support/work_share.hpp): the subtree
    // items [begin, end) of the order, and the items of levels 0..C when `top`. A CoarseFirst
    // walk gives levels 0..C whatever `top` (they are its subtrees' parents); a SinglePass walk
    // with `top` computes them from the input in bands, the same pixels as from every subtree.
    struct Range {
        int64_t begin = 0, end = 0;
        bool top = true;
    };
    // Pruned walks (`pruned` below) hand out only what the input may reach: a tile of level >= 1
    // is handed out when its parent is not blank; a blank one comes with blankBelow, and none
    // below it. The subtree items are then only those under level-C tiles that are not blank,
    // in the same order (numbered from 0 without gaps), a blank one as its root tile alone. What
    // a pruned walk hands out is what the whole walk hands out, tile for tile. A face a small
    // map barely touches is then walked in time and memory that follow the map, not the face
    // (doc/spherical.md, "Files where the map is").
    //
    // The deepest level of a walk's top levels (C) in `order`.
    int topLevels(WalkOrder order) const;
    // The subtree items of a walk in `order` (0 when levels 0..C are the whole pyramid).
    int64_t subtreeItems(WalkOrder order, bool pruned = false) const;
    // Whether every tile of level C (CoarseFirst's) may be reached by the input: a pruned walk
    // then leaves out no subtree item. Always true for a plane that the input fills.
    bool reachesEveryTopTile() const;
    bool isFace() const; // a cube face (else a plane)
    // Whether the input's parts differ in resolution ("Several resolutions" above): every walk
    // is then pruned, and tiles beyond the resolution of the parts there come as `beyond`.
    bool severalLevels() const;
    // How many items a sink may hold between handing them on and consuming them, such as
    // encoded items waiting to be written in order: max(4, 2 x threads).
    int64_t itemWindow() const;
    int64_t walk(const Sink& sink, WalkOrder order = WalkOrder::CoarseFirst, const Range* range = nullptr,
                 bool pruned = false) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
