#include "libpyramid/runtime/ortho_producer.hpp"

#include <algorithm>
#include <utility>

#include "formats/error.hpp"
#include "libpyramid/runtime/region_lookup.hpp"

namespace pyramid {

struct OrthoProducer::Impl {
    std::vector<std::unique_ptr<OrthoFileReader>> files; // main file first
    int maxLevel = 0;

    const OrthoFileReader& holder(int level, int tx, int ty, RelativeTile& rel) const {
        const int k = deepestStorer(files, level, tx, ty, rel);
        if (k < 0) {
            throw MissingTileError(files.front()->path() + ": no tile " + tileCoordinates(level, tx, ty) +
                                   " stored in any file");
        }
        return *files[static_cast<size_t>(k)];
    }
};

OrthoProducer::OrthoProducer(const std::string& mainFile, const std::vector<std::string>& regions)
    : OrthoProducer(openFileSource(mainFile), openFileSources(regions)) {}

OrthoProducer::OrthoProducer(std::shared_ptr<const ByteSource> mainFile,
                             const std::vector<std::shared_ptr<const ByteSource>>& regions)
    : impl_(std::make_unique<Impl>()) {
    impl_->files.push_back(OrthoFileReader::open(std::move(mainFile)));
    const OrthoHeader& main = impl_->files.front()->header();
    if (main.rootLevel != 0) {
        fail(impl_->files.front()->path(), "the main file of an ortho producer must be rooted at tile (0,0,0)");
    }
    for (const auto& region : regions) {
        impl_->files.push_back(OrthoFileReader::open(region));
        const OrthoHeader& h = impl_->files.back()->header();
        const std::string& name = impl_->files.back()->path();
        if (h.tileSize != main.tileSize || h.channels != main.channels || h.flags != main.flags) {
            fail(name, "region tiles differ from the main file's (tile size, channels or flags)");
        }
        if (h.rootLevel < 1) {
            fail(name, "a region file must be rooted at level 1 or deeper");
        }
    }
    for (const auto& f : impl_->files) {
        impl_->maxLevel = std::max(impl_->maxLevel, f->header().rootLevel + f->header().maxLevel);
    }
}

OrthoProducer::~OrthoProducer() = default;

const std::string& OrthoProducer::path() const { return impl_->files.front()->path(); }
const OrthoHeader& OrthoProducer::header() const { return impl_->files.front()->header(); }
int OrthoProducer::maxLevel() const { return impl_->maxLevel; }

bool OrthoProducer::hasTile(int level, int tx, int ty) const {
    RelativeTile rel;
    return deepestStorer(impl_->files, level, tx, ty, rel) >= 0;
}

std::vector<uint8_t> OrthoProducer::tile(int level, int tx, int ty) const {
    RelativeTile rel;
    const OrthoFileReader& f = impl_->holder(level, tx, ty, rel);
    return f.readTile(rel.level, rel.tx, rel.ty);
}

std::vector<uint8_t> OrthoProducer::rawTile(int level, int tx, int ty) const {
    RelativeTile rel;
    const OrthoFileReader& f = impl_->holder(level, tx, ty, rel);
    return f.readTileBytes(rel.level, rel.tx, rel.ty);
}

} // namespace pyramid
