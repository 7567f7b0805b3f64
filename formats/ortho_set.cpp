#include "formats/ortho_set.hpp"

#include <cstdint>
#include <string>

#include "formats/error.hpp"
#include "formats/set_splitter.hpp"

namespace pyramid {

OrthoHeader orthoRegionHeader(const OrthoHeader& whole, const RegionRoot& root, int last) {
    OrthoHeader r = whole;
    r.maxLevel = last - root.level;
    r.rootLevel = root.level;
    r.rootTx = root.tx;
    r.rootTy = root.ty;
    return r;
}

std::vector<OrthoSetFile> writeOrthoSet(const OrthoFileWriter& whole, const std::string& mainName, uint64_t maxFileBytes,
                                        const std::function<std::string(const std::string&)>& place,
                                        const std::string& name) {
    const OrthoHeader& h = whole.header();
    const std::string& where = name.empty() ? whole.path() : name;
    if (h.rootLevel != 0) {
        fail(where, "only a root pyramid (rootLevel 0) is split into region files");
    }
    SplitSource source;
    source.tiles = &whole.table();
    source.path = where;
    source.minLevel = 0;
    source.maxLevel = h.maxLevel;
    source.headerBytes = OrthoHeader::kBytes;
    source.offsetBytes = 8;
    source.maxOffset = static_cast<uint64_t>(INT64_MAX);
    // Every file keeps the whole header's tile size, channels and flags; a region its root.
    auto headerOf = [&h](const SplitFile& f) { return orthoRegionHeader(h, f.root, f.last); };
    const std::vector<SplitFile> split = writeSplitSet(
        source, mainName, maxFileBytes,
        [&](const std::string& path, const SplitFile& f) {
            const OrthoHeader r = headerOf(f);
            r.validate(path);
            return packOrthoHeader(r);
        },
        place);
    std::vector<OrthoSetFile> files;
    for (const SplitFile& f : split) {
        files.push_back(OrthoSetFile{f.name, headerOf(f), f.bytes});
    }
    return files;
}

} // namespace pyramid
