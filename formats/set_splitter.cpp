#include "formats/set_splitter.hpp"

#include <algorithm>
#include <string>
#include <tuple>
#include <unordered_set>

#include "formats/error.hpp"
#include "formats/temporaries.hpp"

namespace pyramid {

namespace {

using Layout = SetFileLayout;

class SetPlanner {
public:
    SetPlanner(const SplitSource& whole, uint64_t cap) : whole_(whole), layout_{whole.minLevel}, cap_(cap) {}

    const Layout& layout() const { return layout_; }

    // Calls f(tx, ty) for the tiles of absolute level `l` in the subtree of `file`, row by row.
    template <class F>
    void forEachTile(const SplitFile& file, int l, F f) const {
        if (file.root.level == 0) {
            const int side = static_cast<int>(layout_.tilesPerSide(l));
            for (int y = 0; y < side; ++y) {
                for (int x = 0; x < side; ++x) {
                    f(x, y);
                }
            }
            return;
        }
        const int d = l - file.root.level, side = 1 << d;
        for (int y = 0; y < side; ++y) {
            for (int x = 0; x < side; ++x) {
                f((file.root.tx << d) + x, (file.root.ty << d) + y);
            }
        }
    }

    uint64_t fileBytes(uint64_t tiles, uint64_t data) const {
        return whole_.headerBytes + 2 * static_cast<uint64_t>(whole_.offsetBytes) * tiles + data;
    }

    // The file of the subtree at `root` down to its deepest level that fits (at least `lowest`),
    // then the files of the subtrees below it.
    void plan(const RegionRoot& root, std::vector<SplitFile>& out) const {
        const int lowest = root.level == 0 ? std::max(0, whole_.minLevel - 1) : root.level;
        SplitFile file;
        file.root = root;
        uint64_t tiles = 0, data = 0;
        std::unordered_set<uint64_t> ranges; // tiles sharing bytes store them once per file
        int fits = -1;
        for (int l = root.level; l <= whole_.maxLevel; ++l) {
            forEachTile(file, l, [&](int x, int y) {
                ++tiles;
                const TileTable::Range r = whole_.tiles->range(layout_.tileIndex(l, x, y));
                if (ranges.insert(r.begin).second) {
                    data += r.size();
                }
            });
            if (fileBytes(tiles, data) > cap_) {
                break;
            }
            fits = l;
        }
        if (fits < lowest) {
            const std::string what = root.level == 0
                                         ? "the levels 0.." + std::to_string(lowest) + " of the main file alone pass"
                                         : "the tile " + tileCoordinates(root.level, root.tx, root.ty) + " alone passes";
            // Named as the output, not as the staged file being split.
            fail(outputName(whole_.path), what + " the file size limit of " + std::to_string(cap_) + " bytes");
        }
        file.last = fits;
        out.push_back(file);
        if (fits < whole_.maxLevel) {
            forEachTile(file, fits + 1, [&](int x, int y) { plan(RegionRoot{fits + 1, x, y}, out); });
        }
    }

private:
    const SplitSource& whole_;
    const Layout layout_;
    uint64_t cap_;
};

} // namespace

std::vector<SplitFile> writeSplitSet(const SplitSource& whole, const std::string& mainName, uint64_t maxFileBytes,
                                     const SplitHeaderFactory& header,
                                     const std::function<std::string(const std::string&)>& place) {
    const SetPlanner planner(whole, maxFileBytes);
    std::vector<SplitFile> files;
    planner.plan(RegionRoot{}, files);
    std::sort(files.begin() + 1, files.end(), [](const SplitFile& a, const SplitFile& b) {
        return std::tie(a.root.level, a.root.tx, a.root.ty) < std::tie(b.root.level, b.root.tx, b.root.ty);
    });
    const Layout& wholeLayout = planner.layout();
    for (SplitFile& f : files) {
        const bool main = f.root.level == 0;
        f.name = main ? mainName : regionFilePath(mainName, f.root);
        // The main file keeps the whole pyramid's layout (and its minLevel); a region file is a
        // full quadtree from its root.
        const Layout layout{main ? whole.minLevel : 0};
        int64_t tileCount = 0;
        for (int l = 0; l <= f.last - f.root.level; ++l) {
            tileCount += layout.tilesPerSide(l) * layout.tilesPerSide(l);
        }
        const std::string path = place(f.name);
        TileTableWriter out(path, header(path, f), tileCount, whole.offsetBytes, whole.maxOffset);
        for (int l = f.root.level; l <= f.last; ++l) {
            planner.forEachTile(f, l, [&](int x, int y) {
                const std::vector<uint8_t> blob = whole.tiles->read(wholeLayout.tileIndex(l, x, y));
                if (main) {
                    out.write(layout.tileIndex(l, x, y), blob);
                } else {
                    const RegionRoot r = regionRelativeTile(f.root, l, x, y);
                    out.write(layout.tileIndex(r.level, r.tx, r.ty), blob);
                }
            });
        }
        out.commit();
        f.bytes = planner.fileBytes(static_cast<uint64_t>(tileCount), out.bytesWritten());
    }
    return files;
}

std::vector<RegionRoot> splitRegionRoots(const std::vector<SplitFile>& files) {
    std::vector<RegionRoot> roots;
    for (size_t k = 1; k < files.size(); ++k) {
        roots.push_back(files[k].root);
    }
    return roots;
}

} // namespace pyramid
