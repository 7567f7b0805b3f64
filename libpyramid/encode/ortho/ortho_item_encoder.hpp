// The items of an ortho walk (OrthoLevels::walk) encoded for encodeOrtho's outputs, tile by tile
// (ortho_tile_encoder.hpp). A tile's colour residual is predicted from its parent's rebuilt
// colours: within a subtree, its own tiles'; above a subtree, and within levels 0..C, those of
// levels 0..C, kept here as the walk hands those levels out (before the subtrees that need them).
//
// A pruned walk's blank tile with nothing below it (TrueTile::blankBelow) becomes an empty subtree
// of the TIFF and DXT outputs. Its colour residuals are encoded (closed loop, against its parent's
// rebuilt colours, which near the map are not all 0) and so are its blank descendants', until a
// tile's rebuilt colours are all at most 1: below such a tile every prediction is at most 1
// (weights summing to 16, shifted by 4), every residual (0 - p) / 2 + 128 = 128 and every rebuilt
// colour the prediction again, so each of its children is an empty subtree of the colour residual
// output: what a dense build stores there, and what the colour-residual producer rebuilds where a
// set has no tile (doc/format.md 1.5, "Sparse sets").
#pragma once
#include <map>
#include <memory>
#include <tuple>
#include <vector>

#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_levels.hpp"
#include "libpyramid/encode/ortho/ortho_tile_encoder.hpp"

namespace pyramid {

// One item of a walk (a subtree, or a level of levels 0..C) encoded, its tiles in the walk's
// order (a blank subtree's colour residuals after its root).
using EncodedItem = std::vector<EncodedOrthoTile>;

// The items of levels 0..C and the subtree items may be given different outputs (`top` and
// `subtrees`: a build in two walks), which a later walk may change (setSubtreeOutputs).
class OrthoItemEncoder {
public:
    OrthoItemEncoder(const OrthoLevels& levels, const OrthoEncodeOptions& top, const OrthoEncodeOptions& subtrees);
    // The outputs of the subtree items from now on (the options must outlive this object).
    void setSubtreeOutputs(const OrthoEncodeOptions& subtrees);
    // The colour reconstruction of a tile this walk does not encode (a region's parent).
    void seed(int level, int tx, int ty, std::vector<uint8_t> recon);

    // A whole level of 0..C, from the walk's calling thread: its tiles in parallel, independent
    // given the previous level's reconstruction.
    EncodedItem encodeLevel(const TileBatch& batch);
    // A subtree, in pre-order (its parents before its children), on the calling thread; called
    // by several threads at once, never while a level is encoded.
    EncodedItem encodeSubtree(const TileBatch& item) const;
    // The same, letting go of each tile's pixels once it is encoded (a tile's children need its
    // rebuilt colours, not its pixels), so that the tiles encoded next reuse that memory.
    EncodedItem encodeSubtree(TileBatch&& item) const;

private:
    using TileKey = std::tuple<int, int, int>; // level, tx, ty
    static TileKey parentOf(const TrueTile& t) { return {t.level - 1, t.tx / 2, t.ty / 2}; }

    // Appends tile t's entries: t encoded by `encoder`, or, for a blankBelow tile, its empty
    // subtree and (`residuals`) its blank subtree's colour residuals.
    void encodeInto(const OrthoTileEncoder& encoder, bool residuals, const TrueTile& t,
                    const std::vector<uint8_t>* parent, EncodedItem& out) const;
    // `release`: the item itself, whose tiles' pixels are let go once encoded (or none).
    EncodedItem encodeSubtreeTiles(const TileBatch& item, TileBatch* release) const;
    void blankResiduals(int level, int tx, int ty, const std::vector<uint8_t>* parent, const Image8* zero,
                        EncodedItem& out) const;

    const OrthoLevels& levels_;
    const OrthoTileEncoder top_;
    const bool topResiduals_;
    const bool handOutRecon_; // OrthoEncodeOptions::colourReconstruction is set: the writer needs every tile's
    OrthoEncodeOptions residualOptions_; // top's, colour residuals only
    const OrthoTileEncoder residualOnly_;
    std::unique_ptr<OrthoTileEncoder> subtree_;
    bool subtreeResiduals_ = false;
    const int threads_;
    std::map<TileKey, SharedBytes> shallowRecon_; // levels 0..C
};

} // namespace pyramid
