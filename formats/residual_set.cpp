#include "formats/residual_set.hpp"

#include <algorithm>
#include <string>
#include <tuple>
#include <unordered_set>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"

namespace pyramid {

namespace {

// A file of the set: the subtree rooted at absolute tile (level, tx, ty), levels down to `last`.
struct FilePlan {
    int level = 0, tx = 0, ty = 0;
    int last = 0;
};

class SetPlanner {
public:
    SetPlanner(const ResidualFileWriter& whole, uint64_t cap) : whole_(whole), h_(whole.header()), cap_(cap) {}

    // Calls f(tx, ty) for the tiles of level `l` in the subtree rooted at (L0, X0, Y0), row by row.
    template <class F>
    void forEachTile(const FilePlan& root, int l, F f) const {
        if (root.level == 0) {
            const int side = static_cast<int>(h_.tilesPerSide(l));
            for (int y = 0; y < side; ++y) {
                for (int x = 0; x < side; ++x) {
                    f(x, y);
                }
            }
            return;
        }
        const int d = l - root.level, side = 1 << d;
        for (int y = 0; y < side; ++y) {
            for (int x = 0; x < side; ++x) {
                f((root.tx << d) + x, (root.ty << d) + y);
            }
        }
    }

    // The file of the subtree at `root` down to its deepest level that fits (at least `lowest`),
    // then the files of the subtrees below it.
    void plan(FilePlan root, std::vector<FilePlan>& out) const {
        const int lowest = root.level == 0 ? std::max(0, h_.minLevel - 1) : root.level;
        uint64_t tiles = 0, data = 0;
        std::unordered_set<uint64_t> ranges; // tiles sharing bytes store them once per file
        int fits = -1;
        for (int l = root.level; l <= h_.maxLevel; ++l) {
            forEachTile(root, l, [&](int x, int y) {
                ++tiles;
                const TileTable::Range r = whole_.tileRange(l, x, y);
                if (ranges.insert(r.begin).second) {
                    data += r.size();
                }
            });
            if (ResidualHeader::kBytes + 8 * tiles + data > cap_) {
                break;
            }
            fits = l;
        }
        if (fits < lowest) {
            const std::string what = root.level == 0 ? "the levels 0.." + std::to_string(lowest) + " of the main file"
                                                     : "the tile (" + std::to_string(root.level) + "," +
                                                           std::to_string(root.tx) + "," + std::to_string(root.ty) + ")";
            fail(whole_.path(), what + " alone pass the file size limit of " + std::to_string(cap_) + " bytes");
        }
        root.last = fits;
        out.push_back(root);
        if (fits < h_.maxLevel) {
            forEachTile(root, fits + 1, [&](int x, int y) { plan(FilePlan{fits + 1, x, y, 0}, out); });
        }
    }

private:
    const ResidualFileWriter& whole_;
    const ResidualHeader& h_;
    uint64_t cap_;
};

} // namespace

std::vector<ResidualSetFile> writeResidualSet(const ResidualFileWriter& whole, const std::string& mainName,
                                              uint64_t maxFileBytes,
                                              const std::function<std::string(const std::string&)>& place) {
    const ResidualHeader& h = whole.header();
    if (h.rootLevel != 0) {
        fail(whole.path(), "only a root pyramid (rootLevel 0) is split into region files");
    }
    const SetPlanner planner(whole, maxFileBytes);
    std::vector<FilePlan> plans;
    planner.plan(FilePlan{}, plans);
    std::sort(plans.begin() + 1, plans.end(), [](const FilePlan& a, const FilePlan& b) {
        return std::tie(a.level, a.tx, a.ty) < std::tie(b.level, b.tx, b.ty);
    });
    std::vector<ResidualSetFile> files;
    for (const FilePlan& p : plans) {
        ResidualSetFile f;
        f.header = h;
        f.header.maxLevel = p.last;
        if (p.level == 0) {
            f.name = mainName;
        } else {
            f.name = regionFilePath(mainName, RegionRoot{p.level, p.tx, p.ty});
            f.header.minLevel = 0;
            f.header.maxLevel = p.last - p.level;
            f.header.rootLevel = p.level;
            f.header.rootTx = p.tx;
            f.header.rootTy = p.ty;
        }
        ResidualFileWriter out(place(f.name), f.header);
        for (int l = p.level; l <= p.last; ++l) {
            const int d = l - p.level;
            planner.forEachTile(p, l, [&](int x, int y) {
                const std::vector<uint8_t> blob = whole.readTileBytes(l, x, y);
                if (p.level == 0) {
                    out.writeTileBytes(l, x, y, blob);
                } else {
                    out.writeTileBytes(d, x - (p.tx << d), y - (p.ty << d), blob);
                }
            });
        }
        out.commit();
        f.bytes = ResidualHeader::kBytes + 8 * static_cast<uint64_t>(f.header.tileCount()) + out.bytesWritten();
        files.push_back(std::move(f));
    }
    return files;
}

} // namespace pyramid
