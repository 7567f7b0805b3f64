#include "libpyramid/encode/ortho/ortho_outputs.hpp"

#include <algorithm>
#include <filesystem>

#include "formats/ortho_set.hpp"
#include "libpyramid/encode/ortho/ortho_output.hpp"
#include "libpyramid/encode/ortho/pixel_source.hpp"

namespace pyramid {

// Encoded as any tile of level 2 away from the pyramid's edge.
EncodedOrthoTile blankTileBytes(const OrthoLevels& levels, const OrthoEncodeOptions& o) {
    const int side = levels.tileSize() + 2 * kTileBorder;
    const Image8 zero(side, side, levels.channels());
    const std::vector<uint8_t> parent(zero.pixels.size(), 0);
    return OrthoTileEncoder(levels, o).encode(TrueTile::blankAt(2, 1, 1, &zero), o.writeResiduals ? &parent : nullptr);
}

OrthoOutputs::OrthoOutputs(const OrthoLevels& levels, const std::string& directory, StagingDirectory& staging,
                           const OrthoEncodeOptions& o, OrthoReport& report, const RegionRoot* region, bool sparse)
    : staging_(staging), maxFileBytes_(o.maxFileBytes), region_(region),
      leaveOutPictures_(sparse && levels.severalLevels()) {
    OrthoHeader base;
    base.maxLevel = levels.maxLevel();
    base.tileSize = levels.tileSize();
    base.channels = levels.channels();
    base.flags = o.border == 0 ? OrthoHeader::kFlagNoBorder : 0u;
    const std::filesystem::path dir(directory);
    const std::string file = o.name + ".dat";
    EncodedOrthoTile blank;
    if (sparse) {
        blank = blankTileBytes(levels, o);
    }
    auto output = [&](size_t k, const std::string& whole, const OrthoHeader& h, const SharedBytes& empty) {
        const std::string relative = region ? regionFilePath(whole, *region) : whole;
        names_.push_back(relative);
        report.outputs.push_back((dir / relative).string());
        headers_[k] = h;
        if (sparse) {
            // The blobs wait in the staging directory, in a temporary that is never put in place.
            logs_[k] = std::make_unique<SparseTileLog>(staging.path(relative + ".tiles"), bytesOf(empty));
            return std::unique_ptr<OrthoFileWriter>();
        }
        if (region) {
            // Staged as the tiles come, never committed: put in level order when complete.
            const OrthoHeader r = orthoRegionHeader(h, *region, h.maxLevel);
            r.validate(relative);
            return std::make_unique<OrthoFileWriter>(staging.path(relative) + ".staged", r);
        }
        return std::make_unique<OrthoFileWriter>(staging.path(relative), h);
    };
    if (o.writeTiff) {
        tiff_ = output(0, file, base, blank.tiff);
    }
    if (o.writeDxt) {
        OrthoHeader h = base;
        h.channels = std::max(3, base.channels);
        h.flags |= OrthoHeader::kFlagDxt;
        dxt_ = output(1, "dxt/" + file, h, blank.dxt);
    }
    if (o.writeResiduals) {
        OrthoHeader h = base;
        h.flags = 0; // colour residuals always carry their 2-pixel border
        residual_ = output(2, "residuals/" + file, h, blank.residual);
    }
}

OrthoOutputs::~OrthoOutputs() = default;

void OrthoOutputs::write(const EncodedOrthoTile& e, OutputSet made) {
    if (logs_[0] || logs_[1] || logs_[2]) {
        const bool wanted[3] = {made.tiff, made.dxt, made.residual};
        const SharedBytes* bytes[3] = {&e.tiff, &e.dxt, &e.residual};
        for (size_t k = 0; k < 3; ++k) {
            if (!logs_[k] || !wanted[k]) {
                continue;
            }
            if (k < 2 && e.picturesEmptyBelow && leaveOutPictures_) {
                logs_[k]->addLeftOutSubtree(e.level, e.tx, e.ty);
            } else if (k < 2 ? e.picturesEmptyBelow : e.residualEmptyBelow) {
                logs_[k]->addEmptySubtree(e.level, e.tx, e.ty);
            } else if (*bytes[k]) {
                logs_[k]->add(e.level, e.tx, e.ty, **bytes[k]);
            }
        }
        return;
    }
    RegionRoot t{e.level, e.tx, e.ty};
    if (region_) {
        t = regionRelativeTile(*region_, e.level, e.tx, e.ty);
    }
    if (tiff_ && made.tiff) {
        writeOne(*tiff_, firstWith_[0], t, e.tiff, e.uniform);
    }
    if (dxt_ && made.dxt) {
        writeOne(*dxt_, firstWith_[1], t, e.dxt, e.uniform);
    }
    if (residual_ && made.residual) {
        writeOne(*residual_, firstWith_[2], t, e.residual, e.uniform);
    }
}

void OrthoOutputs::finishPictures() {
    if (!region_ && maxFileBytes_ == 0) {
        for (auto* w : {&tiff_, &dxt_}) {
            if (*w) {
                (*w)->finish();
            }
        }
    }
}

int64_t OrthoOutputs::commit(OrthoReport& report) {
    size_t k = 0;
    int64_t tiles = -1;
    for (size_t slot = 0; slot < 3; ++slot) {
        std::unique_ptr<OrthoFileWriter>& w = slot == 0 ? tiff_ : slot == 1 ? dxt_ : residual_;
        if (logs_[slot]) {
            const int64_t held = placeSparseOrthoOutput(*logs_[slot], headers_[slot], names_[k], report.outputs[k],
                                                        maxFileBytes_, staging_, report);
            logs_[slot].reset(); // its spooled blobs go before the staging directory is committed
            tiles = tiles < 0 ? held : tiles;
            ++k;
        } else if (w) {
            report.sharedTiles.push_back(w->sharedTiles());
            tiles = tiles < 0 ? w->header().tileCount() : tiles;
            commitOne(std::move(w), names_[k], report.outputs[k], report);
            ++k;
        }
    }
    return tiles;
}

// Tile t's bytes: a uniform tile's bytes given before are not compared again, byte for byte,
// with those the writer stored (a face that a small map barely touches has millions).
void OrthoOutputs::writeOne(OrthoFileWriter& writer, FirstWith& firstWith, const RegionRoot& t,
                            const SharedBytes& bytes, bool uniform) {
    if (uniform && bytes) {
        const auto it = firstWith.find(bytes.get());
        if (it != firstWith.end()) {
            writer.writeTileSameAs(t.level, t.tx, t.ty, it->second.second);
            return;
        }
        firstWith.emplace(bytes.get(), std::make_pair(bytes, std::array<int, 3>{t.level, t.tx, t.ty}));
    }
    writer.writeTileBytes(t.level, t.tx, t.ty, bytesOf(bytes));
}

void OrthoOutputs::commitOne(std::unique_ptr<OrthoFileWriter> writer, const std::string& name,
                             const std::string& output, OrthoReport& report) {
    if (region_) {
        // Level by level, row by row: the order the set splitter gives a region file, so that
        // a region built alone is byte for byte the file of a set (formats/set_splitter.hpp).
        const OrthoHeader& h = writer->header();
        auto ordered = std::make_unique<OrthoFileWriter>(staging_.path(name), h);
        for (int l = 0; l <= h.maxLevel; ++l) {
            const int side = 1 << l;
            for (int ty = 0; ty < side; ++ty) {
                for (int tx = 0; tx < side; ++tx) {
                    ordered->writeTileBytes(l, tx, ty, writer->table().read(h.tileIndex(l, tx, ty)));
                }
            }
        }
        writer = std::move(ordered);
        report.sharedTiles.back() = writer->sharedTiles();
    }
    placeOrthoOutput(std::move(writer), name, output, maxFileBytes_, staging_, report);
}

} // namespace pyramid
