#include "libpyramid/encode/ortho/ortho_item_encoder.hpp"

#include <algorithm>

#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

OrthoEncodeOptions residualsOf(const OrthoEncodeOptions& o) {
    OrthoEncodeOptions r = o;
    r.writeTiff = r.writeDxt = false;
    return r;
}

// The tiles of a subtree rooted at `level` of a pyramid of levels 0..maxLevel.
int64_t subtreeTiles(int level, int maxLevel) {
    return ((int64_t{1} << (2 * (maxLevel - level + 1))) - 1) / 3;
}

EncodedOrthoTile emptyBelow(int level, int tx, int ty) {
    EncodedOrthoTile e;
    e.level = level;
    e.tx = tx;
    e.ty = ty;
    e.stats.tiles = 0;
    e.covers = 0;
    return e;
}

} // namespace

OrthoItemEncoder::OrthoItemEncoder(const OrthoLevels& levels, const OrthoEncodeOptions& top,
                                   const OrthoEncodeOptions& subtrees)
    : levels_(levels), top_(levels, top), topResiduals_(top.writeResiduals),
      handOutRecon_(static_cast<bool>(top.colourReconstruction)), residualOptions_(residualsOf(top)),
      residualOnly_(levels, residualOptions_), threads_(levels.threads()) {
    setSubtreeOutputs(subtrees);
}

void OrthoItemEncoder::setSubtreeOutputs(const OrthoEncodeOptions& subtrees) {
    subtree_ = std::make_unique<OrthoTileEncoder>(levels_, subtrees);
    subtreeResiduals_ = subtrees.writeResiduals;
}

void OrthoItemEncoder::seed(int level, int tx, int ty, std::vector<uint8_t> recon) {
    shallowRecon_[{level, tx, ty}] = std::make_shared<const std::vector<uint8_t>>(std::move(recon));
}

EncodedItem OrthoItemEncoder::encodeLevel(const TileBatch& batch) {
    std::vector<EncodedItem> parts(batch.size());
    parallelFor(static_cast<int64_t>(batch.size()), threads_, [&](int64_t i) {
        const TrueTile& t = batch[static_cast<size_t>(i)];
        const std::vector<uint8_t>* parent = t.level && topResiduals_ ? shallowRecon_.at(parentOf(t)).get() : nullptr;
        encodeInto(top_, topResiduals_, t, parent, parts[static_cast<size_t>(i)]);
    });
    EncodedItem level;
    level.reserve(batch.size());
    for (size_t i = 0; i < parts.size(); ++i) {
        for (size_t k = 0; k < parts[i].size(); ++k) {
            EncodedOrthoTile& e = level.emplace_back(std::move(parts[i][k]));
            e.top = true;
            if (topResiduals_ && k == 0 && !batch[i].blankBelow) {
                // The next levels and the subtrees predict from these rebuilt tiles while this one
                // is written. Moved rather than copied unless they are handed out too: a level's
                // rebuilt colours are held once (at planet scale, level C's are most of a gigabyte).
                SharedBytes& kept = shallowRecon_[{e.level, e.tx, e.ty}];
                kept = handOutRecon_ ? e.recon : std::move(e.recon);
            } else if (!handOutRecon_) {
                e.recon.reset();
            }
        }
    }
    return level;
}

EncodedItem OrthoItemEncoder::encodeSubtree(const TileBatch& item) const {
    return encodeSubtreeTiles(item, nullptr);
}

EncodedItem OrthoItemEncoder::encodeSubtree(TileBatch&& item) const {
    return encodeSubtreeTiles(item, &item);
}

EncodedItem OrthoItemEncoder::encodeSubtreeTiles(const TileBatch& item, TileBatch* release) const {
    std::map<TileKey, const std::vector<uint8_t>*> local;
    EncodedItem out;
    out.reserve(item.size());
    for (size_t k = 0; k < item.size(); ++k) {
        const TrueTile& t = item[k];
        if (!subtreeResiduals_) {
            encodeInto(*subtree_, false, t, nullptr, out); // no tile depends on its parent
        } else {
            const auto key = parentOf(t);
            const auto it = local.find(key);
            const std::vector<uint8_t>* parent = it != local.end() ? it->second : shallowRecon_.at(key).get();
            const size_t own = out.size();
            encodeInto(*subtree_, true, t, parent, out);
            local[{t.level, t.tx, t.ty}] = out[own].recon.get();
        }
        if (release) {
            (*release)[k].pixels = Image8();
        }
    }
    if (!handOutRecon_) {
        for (EncodedOrthoTile& e : out) {
            e.recon.reset(); // not held while the item waits to be written
        }
    }
    return out;
}

void OrthoItemEncoder::encodeInto(const OrthoTileEncoder& encoder, bool residuals, const TrueTile& t,
                                  const std::vector<uint8_t>* parent, EncodedItem& out) const {
    if (!t.blankBelow) {
        out.push_back(encoder.encode(t, parent));
        return;
    }
    const size_t own = out.size();
    if (t.beyond) {
        // Beyond the input's resolution: no tile of any output here or below (a reader magnifies
        // the parent; colour residuals are 128).
        out.push_back(emptyBelow(t.level, t.tx, t.ty));
        out[own].stats.tiles = 1;
        out[own].residualEmptyBelow = residuals;
    } else if (residuals) {
        blankResiduals(t.level, t.tx, t.ty, parent, t.zero, out);
    } else {
        out.push_back(emptyBelow(t.level, t.tx, t.ty));
        out[own].stats.tiles = 1;
    }
    out[own].picturesEmptyBelow = true;
    out[own].covers = subtreeTiles(t.level, levels_.maxLevel());
}

void OrthoItemEncoder::blankResiduals(int level, int tx, int ty, const std::vector<uint8_t>* parent,
                                      const Image8* zero, EncodedItem& out) const {
    EncodedOrthoTile e = residualOnly_.encode(TrueTile::blankAt(level, tx, ty, zero), parent);
    e.covers = 0;
    const SharedBytes recon = e.recon;
    const bool quiet = std::all_of(recon->begin(), recon->end(), [](uint8_t v) { return v <= 1; });
    out.push_back(std::move(e));
    if (level == levels_.maxLevel()) {
        return;
    }
    for (int k = 0; k < 4; ++k) {
        const int cx = 2 * tx + (k & 1), cy = 2 * ty + (k >> 1);
        if (quiet) {
            EncodedOrthoTile m = emptyBelow(level + 1, cx, cy);
            m.residualEmptyBelow = true;
            out.push_back(std::move(m));
        } else {
            blankResiduals(level + 1, cx, cy, recon.get(), zero, out);
        }
    }
}

} // namespace pyramid
