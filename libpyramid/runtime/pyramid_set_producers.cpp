#include "libpyramid/runtime/pyramid_set_producers.hpp"

#include <algorithm>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/runtime/region_lookup.hpp"

namespace pyramid {

namespace {

void requireKind(const PyramidSet& set, PyramidKind kind) {
    if (set.kind != kind) {
        fail(set.name(), std::string("holds ") + (set.kind == PyramidKind::Residual ? "a residual" : "an ortho") +
                             " pyramid, not " + (kind == PyramidKind::Residual ? "a residual" : "an ortho") + " one");
    }
}

// The files' headers, as deepestHolder takes them (main file first).
struct HeaderOnly {
    ResidualHeader h;
    const ResidualHeader& header() const { return h; }
};
std::vector<std::unique_ptr<HeaderOnly>> residualHeaders(const PyramidSet& set) {
    std::vector<std::unique_ptr<HeaderOnly>> headers;
    headers.push_back(std::make_unique<HeaderOnly>(HeaderOnly{ResidualFileReader::readHeader(set.main)}));
    for (const std::string& r : set.regions) {
        headers.push_back(std::make_unique<HeaderOnly>(HeaderOnly{ResidualFileReader::readHeader(r)}));
    }
    return headers;
}

} // namespace

bool residualSetHolds(const PyramidSet& set, int level, int tx, int ty) {
    requireKind(set, PyramidKind::Residual);
    RelativeTile rel;
    return deepestHolder(residualHeaders(set), level, tx, ty, rel) >= 0;
}

StoredResidualTile storedResidualTile(const PyramidSet& set, int level, int tx, int ty) {
    requireKind(set, PyramidKind::Residual);
    RelativeTile rel;
    const int k = deepestHolder(residualHeaders(set), level, tx, ty, rel);
    if (k < 0) {
        fail(set.name(), "no tile " + tileText(RegionRoot{level, tx, ty}) + " in any file of the set");
    }
    StoredResidualTile t;
    t.file = k == 0 ? set.main : set.regions[static_cast<size_t>(k - 1)];
    const auto reader = ResidualFileReader::open(t.file);
    t.level = rel.level;
    t.tx = rel.tx;
    t.ty = rel.ty;
    t.side = reader->header().tileSamples(rel.level);
    t.residuals = reader->readTile(rel.level, rel.tx, rel.ty);
    return t;
}

int setMaxLevel(const PyramidSet& set) {
    int deepest = 0;
    const auto add = [&](const std::string& file) {
        if (set.kind == PyramidKind::Residual) {
            const ResidualHeader h = ResidualFileReader::readHeader(file);
            deepest = std::max(deepest, h.rootLevel + h.maxLevel);
        } else {
            const OrthoHeader h = OrthoFileReader::open(file)->header(); // a copy: the reader is a temporary
            deepest = std::max(deepest, h.rootLevel + h.maxLevel);
        }
    };
    add(set.main);
    std::for_each(set.regions.begin(), set.regions.end(), add);
    return deepest;
}

std::shared_ptr<ResidualProducer> openResidualSet(const PyramidSet& set, const ResidualProducerOptions& options) {
    requireKind(set, PyramidKind::Residual);
    return std::make_shared<ResidualProducer>(set.main, set.regions, options);
}

std::shared_ptr<ResidualProducer> openResidualSet(const std::string& path, const ResidualProducerOptions& options) {
    return openResidualSet(openPyramidSet(path), options);
}

std::shared_ptr<OrthoProducer> openOrthoSet(const PyramidSet& set) {
    requireKind(set, PyramidKind::Ortho);
    return std::make_shared<OrthoProducer>(set.main, set.regions);
}

std::shared_ptr<OrthoProducer> openOrthoSet(const std::string& path) { return openOrthoSet(openPyramidSet(path)); }

std::shared_ptr<ResidualProducer> openResidualsForElevations(const std::string& path, int n) {
    const PyramidSet set = openPyramidSet(path);
    requireKind(set, PyramidKind::Residual);
    const ResidualHeader main = ResidualFileReader::readHeader(set.main);
    ResidualProducerOptions ro;
    ro.delta = elevationDelta(main, n > 0 ? n : main.tileSize, set.main);
    return openResidualSet(set, ro);
}

std::shared_ptr<ElevationProducer> openElevationSet(const std::string& path, const ElevationProducerOptions& options) {
    return std::make_shared<ElevationProducer>(openResidualsForElevations(path, options.tileSize), options);
}

FileLevelProducer makeSetLevelProducer(const PyramidSet& set, int level, size_t cacheCapacity) {
    if (set.index.empty()) {
        return makeFileLevelProducer(set.main, level, cacheCapacity);
    }
    requireKind(set, PyramidKind::Residual);
    const ResidualHeader header = ResidualFileReader::readHeader(set.main);
    const int deepest = setMaxLevel(set);
    if (level < 0 || level > deepest) {
        fail(set.name(), "no level " + std::to_string(level) + " (levels 0.." + std::to_string(deepest) + ")");
    }
    FileLevelProducer p;
    p.delta = std::min(level, header.minLevel);
    p.n = header.tileSize >> (header.minLevel - p.delta);
    ResidualProducerOptions ro;
    ro.delta = p.delta;
    ElevationProducerOptions eo;
    eo.tileSize = p.n;
    eo.cacheCapacity = cacheCapacity;
    p.producer = std::make_shared<ElevationProducer>(openResidualSet(set, ro), eo);
    return p;
}

FileLevelProducer makeSetLevelProducer(const std::string& path, int level, size_t cacheCapacity) {
    if (findRegionIndex(path).empty()) {
        return makeFileLevelProducer(path, level, cacheCapacity);
    }
    return makeSetLevelProducer(openPyramidSet(path), level, cacheCapacity);
}

PointHeight setHeightAt(const std::string& path, double u, double v) {
    if (findRegionIndex(path).empty()) {
        return fileHeightAt(path, u, v);
    }
    const PyramidSet set = openPyramidSet(path);
    const FileLevelProducer finest = makeSetLevelProducer(set, setMaxLevel(set), 4);
    try {
        PointHeight p = heightAt(*finest.producer, u, v); // from the deepest file holding the point
        p.level += finest.delta; // the set's absolute level
        return p;
    } catch (const Error& e) {
        fail(set.name(), e.what());
    }
}

} // namespace pyramid
