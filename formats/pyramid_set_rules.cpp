// The rules a region set keeps (pyramid_set.hpp: pyramidSetProblems, openPyramidSet): every
// listed file opens as the index's kind, the main file is rooted at (0,0,0), each region has the
// main file's tiles and the index's root, and no two regions share a root or lie outside the set.
#include "formats/pyramid_set.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"

namespace pyramid {

namespace fs = std::filesystem;

namespace {

// The header fields the set's rules compare, for either kind.
struct FileFacts {
    int rootLevel = 0, rootTx = 0, rootTy = 0, maxLevel = 0;
    int minLevel = 0; // residual: levels below it hold one tile
};

// True when the file of `facts` holds absolute tile (level, tx, ty), as the runtime looks tiles
// up (libpyramid/runtime/region_lookup.hpp): (tx, ty) relative to the root's tiles at `level`.
bool holds(const FileFacts& f, int level, int tx, int ty) {
    const int l = level - f.rootLevel;
    if (l < 0 || l > f.maxLevel) {
        return false;
    }
    const int64_t x = int64_t{tx} - (int64_t{f.rootTx} << l);
    const int64_t y = int64_t{ty} - (int64_t{f.rootTy} << l);
    const int64_t side = l < f.minLevel ? 1 : int64_t{1} << (l - f.minLevel);
    return x >= 0 && y >= 0 && x < side && y < side;
}

} // namespace

std::vector<std::string> pyramidSetProblems(const PyramidSet& set) {
    std::vector<std::string> problems;
    if (set.index.empty()) {
        return problems;
    }
    const char* kind = kindName(set.kind);
    const auto problem = [&](const std::string& file, const std::string& what) { problems.push_back(file + ": " + what); };
    // Opens one file of the set as the set's kind: null (and a problem) otherwise.
    const auto open = [&](const std::string& file) -> std::unique_ptr<OpenedPyramid> {
        std::error_code ec;
        if (!fs::is_regular_file(file, ec)) {
            problem(file, std::string("no such file (listed in ") + set.index + ")");
            return nullptr;
        }
        try {
            auto opened = std::make_unique<OpenedPyramid>(openPyramid(file));
            if (opened->kind != set.kind) {
                problem(file, std::string("holds ") + (opened->kind == PyramidKind::Residual ? "a" : "an") + " " +
                                  kindName(opened->kind) + " pyramid; the set is " + kind);
                return nullptr;
            }
            return opened;
        } catch (const Error& e) {
            problems.push_back(e.what());
            return nullptr;
        }
    };
    const auto main = open(set.main);
    std::vector<FileFacts> facts(set.regions.size());
    std::vector<bool> opened(set.regions.size(), false);
    FileFacts mainFacts;
    if (main) {
        if (set.kind == PyramidKind::Residual) {
            const ResidualHeader& h = main->residual->header();
            mainFacts = {h.rootLevel, h.rootTx, h.rootTy, h.maxLevel, h.minLevel};
        } else {
            const OrthoHeader& h = main->ortho->header();
            mainFacts = {h.rootLevel, h.rootTx, h.rootTy, h.maxLevel, 0};
        }
        if (mainFacts.rootLevel != 0) {
            problem(set.main, "the main file of a set must be rooted at tile (0,0,0), not " +
                                  tileText({mainFacts.rootLevel, mainFacts.rootTx, mainFacts.rootTy}));
        }
    }
    for (size_t k = 0; k < set.regions.size(); ++k) {
        const std::string& file = set.regions[k];
        const RegionRoot& root = set.roots[k];
        const auto region = open(file);
        if (!region) {
            continue;
        }
        std::vector<std::string> differs;
        if (set.kind == PyramidKind::Residual) {
            const ResidualHeader& h = region->residual->header();
            facts[k] = {h.rootLevel, h.rootTx, h.rootTy, h.maxLevel, h.minLevel};
            if (h.minLevel != 0) {
                differs.push_back("minLevel " + std::to_string(h.minLevel) + ", not 0");
            }
            if (main) {
                const ResidualHeader& m = main->residual->header();
                if (h.tileSize != m.tileSize) {
                    differs.push_back("tile size " + std::to_string(h.tileSize) + ", the main file's is " +
                                      std::to_string(m.tileSize));
                }
                if (h.scale != m.scale) {
                    std::ostringstream s;
                    s.precision(9);
                    s << "scale " << h.scale << ", the main file's is " << m.scale;
                    differs.push_back(s.str());
                }
            }
        } else {
            const OrthoHeader& h = region->ortho->header();
            facts[k] = {h.rootLevel, h.rootTx, h.rootTy, h.maxLevel, 0};
            if (main) {
                const OrthoHeader& m = main->ortho->header();
                if (h.tileSize != m.tileSize) {
                    differs.push_back("tile size " + std::to_string(h.tileSize) + ", the main file's is " +
                                      std::to_string(m.tileSize));
                }
                if (h.channels != m.channels) {
                    differs.push_back(std::to_string(h.channels) + " channels, the main file's has " +
                                      std::to_string(m.channels));
                }
                if (h.border() != m.border()) {
                    differs.push_back("border " + std::to_string(h.border()) + ", the main file's is " +
                                      std::to_string(m.border()));
                }
                if (h.dxt() != m.dxt()) {
                    differs.push_back(std::string(h.dxt() ? "DXT" : "not DXT") + " tiles, the main file's are " +
                                      (m.dxt() ? "DXT" : "not DXT"));
                }
            }
        }
        const RegionRoot headerRoot{facts[k].rootLevel, facts[k].rootTx, facts[k].rootTy};
        if (headerRoot != root) {
            differs.push_back("root " + tileText(headerRoot) + " in its header, the index says " + tileText(root));
        }
        for (const std::string& d : differs) {
            problem(file, d);
        }
        opened[k] = differs.empty();
    }
    // Roots: one region each, and each inside the set (its parent tile held by another file).
    std::map<RegionRoot, size_t> seen;
    for (size_t k = 0; k < set.regions.size(); ++k) {
        const RegionRoot& root = set.roots[k];
        const auto [it, inserted] = seen.emplace(root, k);
        if (!inserted) {
            problem(set.regions[k], "root " + tileText(root) + " is also the root of " + set.regions[it->second]);
            continue;
        }
        const RegionRoot parent{root.level - 1, root.tx / 2, root.ty / 2};
        bool inside = main && holds(mainFacts, parent.level, parent.tx, parent.ty);
        for (size_t o = 0; o < set.regions.size() && !inside; ++o) {
            inside = o != k && opened[o] && holds(facts[o], parent.level, parent.tx, parent.ty);
        }
        if (!inside && main) {
            problem(set.regions[k], "root " + tileText(root) + " lies outside the set: no file holds its parent tile " +
                                        tileText(parent));
        }
    }
    return problems;
}

PyramidSet openPyramidSet(const std::string& path) {
    PyramidSet set = resolvePyramidSet(path);
    const std::vector<std::string> problems = pyramidSetProblems(set);
    if (!problems.empty()) {
        throw Error(problems.front());
    }
    return set;
}

} // namespace pyramid
