#include "formats/residual_set.hpp"

#include <cstdint>
#include <string>

#include "formats/error.hpp"
#include "formats/set_splitter.hpp"

namespace pyramid {

ResidualHeader residualRegionHeader(const ResidualHeader& whole, const RegionRoot& root, int last) {
    ResidualHeader r = whole;
    r.maxLevel = last;
    if (root.level > 0) {
        r.minLevel = 0;
        r.maxLevel = last - root.level;
        r.rootLevel = root.level;
        r.rootTx = root.tx;
        r.rootTy = root.ty;
    }
    return r;
}

std::vector<ResidualSetFile> writeResidualSet(const ResidualFileWriter& whole, const std::string& mainName,
                                              uint64_t maxFileBytes,
                                              const std::function<std::string(const std::string&)>& place) {
    const ResidualHeader& h = whole.header();
    if (h.rootLevel != 0) {
        fail(whole.path(), "only a root pyramid (rootLevel 0) is split into region files");
    }
    SplitSource source;
    source.tiles = &whole.table();
    source.path = whole.path();
    source.minLevel = h.minLevel;
    source.maxLevel = h.maxLevel;
    source.headerBytes = ResidualHeader::kBytes;
    source.offsetBytes = 4;
    source.maxOffset = UINT32_MAX;
    auto headerOf = [&h](const SplitFile& f) { return residualRegionHeader(h, f.root, f.last); };
    const std::vector<SplitFile> split = writeSplitSet(
        source, mainName, maxFileBytes,
        [&](const std::string& path, const SplitFile& f) {
            const ResidualHeader r = headerOf(f);
            r.validate(path);
            return packResidualHeader(r);
        },
        place);
    std::vector<ResidualSetFile> files;
    for (const SplitFile& f : split) {
        files.push_back(ResidualSetFile{f.name, headerOf(f), f.bytes});
    }
    return files;
}

} // namespace pyramid
