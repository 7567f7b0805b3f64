#include "formats/pyramid_set.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/georeference_sidecar.hpp"
#include "formats/pyramid_file_rules.hpp"

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

} // namespace pyramid
