#include "formats/pyramid_set.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/georeference_sidecar.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"

namespace pyramid {

namespace fs = std::filesystem;

bool regionHolds(const RegionRoot& root, int level, int tx, int ty) {
    const int d = level - root.level;
    return d >= 0 && (tx >> d) == root.tx && (ty >> d) == root.ty;
}

RegionRoot regionRelativeTile(const RegionRoot& root, int level, int tx, int ty) {
    const int d = level - root.level;
    return RegionRoot{d, tx - (root.tx << d), ty - (root.ty << d)};
}

std::string tileText(const RegionRoot& r) {
    // Appended piece by piece: GCC 12 at -O3 misreads "(" + std::string&& as an overlapping copy.
    std::string text(1, '(');
    text += std::to_string(r.level);
    text += ',';
    text += std::to_string(r.tx);
    text += ',';
    text += std::to_string(r.ty);
    text += ')';
    return text;
}

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A path of the index, relative to the index's directory.
std::string besideIndex(const std::string& index, const std::string& file) {
    const fs::path dir = fs::path(index).parent_path();
    return dir.empty() ? file : (dir / file).string();
}

void checkRoot(const RegionRoot& r, const std::string& path) {
    if (r.level < 1 || r.level > kMaxLevel) {
        fail(path, "region root " + tileText(r) + ": the level must be 1 to " + std::to_string(kMaxLevel));
    }
    const int64_t side = int64_t{1} << r.level;
    if (r.tx < 0 || r.ty < 0 || r.tx >= side || r.ty >= side) {
        fail(path, "region root " + tileText(r) + " lies outside its level");
    }
}

// A set's files lie at or below the index's directory: a name that is absolute or climbs out of
// it ("..") would send a reader anywhere on the disk (an index that came with a download).
bool withinIndexDirectory(const std::string& file) {
    const fs::path p(file);
    return !p.is_absolute() && !p.has_root_name() &&
           std::none_of(p.begin(), p.end(), [](const fs::path& part) { return part == ".."; });
}

void checkIndex(const RegionIndex& index, const std::string& path) {
    if (index.main.empty()) {
        fail(path, "the main file's name is empty");
    }
    if (!withinIndexDirectory(index.main)) {
        fail(path, "the main file '" + index.main + "' is not a path within the index's directory");
    }
    for (const RegionEntry& e : index.regions) {
        if (e.file.empty()) {
            fail(path, "region " + tileText(e.root) + ": its file name is empty");
        }
        if (!withinIndexDirectory(e.file)) {
            fail(path, "region " + tileText(e.root) + ": '" + e.file + "' is not a path within the index's directory");
        }
        checkRoot(e.root, path);
    }
}

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

std::string regionIndexPath(const std::string& mainFile) { return mainFile + kRegionIndexSuffix; }

std::string regionFilePath(const std::string& mainFile, const RegionRoot& root) {
    const fs::path p(mainFile);
    const std::string name = p.stem().string() + "-L" + std::to_string(root.level) + "-" + std::to_string(root.tx) +
                             "-" + std::to_string(root.ty) + p.extension().string();
    return p.has_parent_path() ? (p.parent_path() / name).string() : name;
}

std::optional<RegionFileName> parseRegionFilePath(const std::string& file) {
    const fs::path p(file);
    const std::string extension = p.extension().string();
    std::string stem = p.stem().string();
    // The three numbers after the last "-L", "-" and "-" of the stem, as regionFilePath spells them.
    int numbers[3] = {0, 0, 0};
    for (int k = 2; k >= 0; --k) {
        const size_t dash = stem.rfind('-');
        if (dash == std::string::npos) {
            return std::nullopt;
        }
        std::string digits = stem.substr(dash + 1);
        if (k == 0) {
            if (digits.empty() || digits[0] != 'L') {
                return std::nullopt;
            }
            digits.erase(0, 1);
        }
        if (digits.empty() || digits.size() > 10 ||
            !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
            return std::nullopt;
        }
        const int64_t value = std::stoll(digits);
        if (value > INT32_MAX) {
            return std::nullopt;
        }
        numbers[k] = static_cast<int>(value);
        stem.erase(dash);
    }
    const RegionRoot root{numbers[0], numbers[1], numbers[2]};
    if (stem.empty() || root.level < 1 || !isQuadtreeTile(root.level, root.tx, root.ty)) {
        return std::nullopt;
    }
    const std::string mainName = stem + extension;
    // Only the names regionFilePath gives (no leading zeros, the stem and extension it splits).
    if (regionFilePath(mainName, root) != p.filename().string()) {
        return std::nullopt;
    }
    return RegionFileName{p.has_parent_path() ? (p.parent_path() / mainName).string() : mainName, root};
}

RegionIndex parseRegionIndex(const std::string& text, const std::string& path) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) {
        fail(path, "not a region set index: not JSON");
    }
    RegionIndex index;
    try {
        if (!j.is_object() || !j.contains("format") || j.at("format") != kRegionIndexFormat) {
            fail(path, std::string("not a region set index (no \"format\": \"") + kRegionIndexFormat + "\")");
        }
        if (!j.at("version").is_number_integer() || j.at("version").get<int>() != kRegionIndexVersion) {
            fail(path, "region set index version " + j.at("version").dump() + " (this reader knows version " +
                           std::to_string(kRegionIndexVersion) + ")");
        }
        const std::string kind = j.at("kind").get<std::string>();
        if (kind == "residual") {
            index.kind = PyramidKind::Residual;
        } else if (kind == "ortho") {
            index.kind = PyramidKind::Ortho;
        } else {
            fail(path, "unknown kind '" + kind + "' (residual or ortho)");
        }
        index.main = j.at("main").get<std::string>();
        for (const nlohmann::json& r : j.at("regions")) {
            RegionEntry e;
            e.file = r.at("file").get<std::string>();
            const nlohmann::json& root = r.at("root");
            if (!root.is_array() || root.size() != 3 || !root[0].is_number_integer() || !root[1].is_number_integer() ||
                !root[2].is_number_integer()) {
                fail(path, "region '" + e.file + "': its root is not three whole numbers [level, tx, ty]");
            }
            const auto value = [&](size_t k) {
                const int64_t v = root[k].get<int64_t>();
                return static_cast<int>(std::clamp<int64_t>(v, -1, INT32_MAX));
            };
            e.root = RegionRoot{value(0), value(1), value(2)};
            index.regions.push_back(std::move(e));
        }
    } catch (const nlohmann::json::exception& e) {
        fail(path, std::string("not a region set index: ") + e.what());
    }
    checkIndex(index, path);
    return index;
}

std::string formatRegionIndex(const RegionIndex& index) {
    nlohmann::ordered_json regions = nlohmann::ordered_json::array();
    for (const RegionEntry& e : index.regions) {
        regions.push_back({{"file", e.file}, {"root", {e.root.level, e.root.tx, e.root.ty}}});
    }
    nlohmann::ordered_json j;
    j["format"] = kRegionIndexFormat;
    j["version"] = kRegionIndexVersion;
    j["kind"] = kindName(index.kind);
    j["main"] = index.main;
    j["regions"] = regions;
    return j.dump(2) + "\n";
}

RegionIndex readRegionIndex(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        fail(path, "cannot open the region set index");
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) {
        fail(path, "cannot read the region set index");
    }
    return parseRegionIndex(text.str(), path);
}

std::vector<std::string> filesNamedAfter(const std::string& path) {
    std::vector<std::string> files;
    std::error_code ec;
    const auto exists = [&](const std::string& f) { return std::filesystem::is_regular_file(f, ec); };
    const std::string index = regionIndexPath(path);
    if (exists(index)) {
        files.push_back(index);
        try {
            // Only the region files named by the rule (never a path the index could point anywhere).
            for (const RegionEntry& r : readRegionIndex(index).regions) {
                const std::string file = regionFilePath(path, r.root);
                if (std::filesystem::path(r.file) == std::filesystem::path(file).filename() && exists(file)) {
                    files.push_back(file);
                }
            }
        } catch (const Error&) {
            // An index that cannot be read names no region files; it goes itself.
        }
    }
    const std::string sidecar = georeferenceSidecarPath(path);
    if (exists(sidecar)) {
        files.push_back(sidecar);
    }
    return files;
}

void writeRegionIndex(const std::string& path, RegionIndex index) {
    checkIndex(index, path);
    std::stable_sort(index.regions.begin(), index.regions.end(),
                     [](const RegionEntry& a, const RegionEntry& b) { return a.root < b.root; });
    const std::string text = formatRegionIndex(index);
    AtomicFile out(path);
    out.writeAt(0, text.data(), text.size());
    out.commit();
}

RegionIndex makeRegionIndex(const std::string& mainFile, PyramidKind kind, const std::vector<RegionRoot>& roots) {
    RegionIndex index;
    index.kind = kind;
    index.main = fs::path(mainFile).filename().string();
    for (const RegionRoot& r : roots) {
        index.regions.push_back({fs::path(regionFilePath(mainFile, r)).filename().string(), r});
    }
    std::sort(index.regions.begin(), index.regions.end(),
              [](const RegionEntry& a, const RegionEntry& b) { return a.root < b.root; });
    return index;
}

std::string findRegionIndex(const std::string& path) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) {
        return endsWith(path, ".json") ? path : std::string(); // for the readers' own messages
    }
    if (fs::is_directory(status)) {
        std::vector<std::string> found;
        for (const fs::directory_entry& e : fs::directory_iterator(path, ec)) {
            const std::string name = e.path().filename().string();
            if (endsWith(name, kRegionIndexSuffix) && e.is_regular_file()) {
                found.push_back(name);
            }
        }
        if (ec) {
            fail(path, "cannot list the directory: " + ec.message());
        }
        std::sort(found.begin(), found.end());
        if (found.empty()) {
            fail(path, std::string("no region set index (*") + kRegionIndexSuffix + ") in this directory");
        }
        if (found.size() > 1) {
            std::string names;
            for (const std::string& f : found) {
                names += (names.empty() ? "" : ", ") + f;
            }
            fail(path, "several region set indexes in this directory (" + names + "): name one");
        }
        return (fs::path(path) / found.front()).string();
    }
    if (endsWith(path, ".json")) {
        return path;
    }
    const std::string beside = regionIndexPath(path);
    return fs::exists(beside, ec) ? beside : std::string();
}

PyramidSet resolvePyramidSet(const std::string& path) {
    PyramidSet set;
    set.index = findRegionIndex(path);
    if (set.index.empty()) {
        set.main = path;
        set.kind = detectPyramidKind(path);
        return set;
    }
    const RegionIndex index = readRegionIndex(set.index);
    set.kind = index.kind;
    // A main file named by the user keeps the user's spelling in messages.
    const bool named = set.index != path && fs::path(path).filename() == fs::path(index.main).filename() &&
                       !fs::is_directory(path);
    set.main = named ? path : besideIndex(set.index, index.main);
    for (const RegionEntry& e : index.regions) {
        set.regions.push_back(besideIndex(set.index, e.file));
        set.roots.push_back(e.root);
    }
    return set;
}

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

PyramidsUnder pyramidsUnder(const std::string& directory) {
    PyramidsUnder found;
    std::vector<std::string> dats;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(directory, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
        if (!it->is_regular_file(ec)) {
            continue;
        }
        const std::string path = it->path().string();
        if (endsWith(path, kRegionIndexSuffix)) {
            found.sets.push_back(path);
        } else if (endsWith(path, ".dat")) {
            dats.push_back(path);
        }
    }
    if (ec) {
        fail(directory, "cannot list the directory: " + ec.message());
    }
    std::sort(found.sets.begin(), found.sets.end());
    std::sort(dats.begin(), dats.end());
    std::vector<std::string> listed; // the files the indexes name
    for (const std::string& index : found.sets) {
        try {
            const PyramidSet set = resolvePyramidSet(index);
            listed.push_back(fs::weakly_canonical(set.main).string());
            for (const std::string& r : set.regions) {
                listed.push_back(fs::weakly_canonical(r).string());
            }
        } catch (const Error&) {
            // a bad index: its problems are the set's
        }
    }
    std::sort(listed.begin(), listed.end());
    for (const std::string& dat : dats) {
        if (!std::binary_search(listed.begin(), listed.end(), fs::weakly_canonical(dat).string())) {
            found.files.push_back(dat);
        }
    }
    return found;
}

} // namespace pyramid
