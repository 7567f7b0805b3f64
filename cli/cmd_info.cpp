// `pyramid info SET [--report FILE|-]`: what a pyramid file holds; for a region set (its main file, index
// or directory), its files with their roots and sizes, and the totals.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_file.hpp"
#include "formats/tiff_tile.hpp"

namespace pyramid::cli {

namespace {

// Level-by-level census of a file's offset table: tiles, bytes, sharing, encodings.
struct Census {
    struct Level {
        int level = 0;
        int64_t tiles = 0;
        int tileSide = 0;     // samples or pixels per side, borders included
        uint64_t bytes = 0;   // bytes of the level's distinct ranges
        int64_t shared = 0;   // tiles reusing a range stored before them
    };
    std::vector<Level> levels;
    std::map<std::string, int64_t> encodings; // per distinct range
    int64_t distinct = 0;
    uint64_t dataBytes = 0;
};

template <class TileSide, class Describe>
Census takeCensus(const TileTable& table, int maxLevel, const std::function<int64_t(int)>& tilesAtLevel,
                  const std::function<int64_t(int, int64_t)>& indexOf, TileSide tileSide, Describe describe) {
    Census c;
    std::set<std::pair<uint64_t, uint64_t>> seen;
    for (int l = 0; l <= maxLevel; ++l) {
        Census::Level level;
        level.level = l;
        level.tileSide = tileSide(l);
        const int64_t count = tilesAtLevel(l);
        for (int64_t k = 0; k < count; ++k) {
            const int64_t index = indexOf(l, k);
            const TileTable::Range r = table.range(index);
            ++level.tiles;
            if (!seen.insert({r.begin, r.end}).second) {
                ++level.shared;
                continue;
            }
            level.bytes += r.size();
            c.dataBytes += r.size();
            ++c.distinct;
            c.encodings[r.size() ? describe(table.read(index)) : std::string("missing")] += 1;
        }
        c.levels.push_back(level);
    }
    return c;
}

nlohmann::json censusJson(const Census& c) {
    nlohmann::json levels = nlohmann::json::array();
    for (const Census::Level& l : c.levels) {
        levels.push_back({{"level", l.level}, {"tiles", l.tiles}, {"tile_side", l.tileSide}, {"bytes", l.bytes},
                          {"shared_tiles", l.shared}});
    }
    return {{"distinct_tiles", c.distinct}, {"data_bytes", c.dataBytes}, {"encodings", c.encodings}, {"levels", levels}};
}

nlohmann::json residualInfo(const std::string& path) {
    const auto reader = ResidualFileReader::open(path);
    const ResidualHeader& h = reader->header();
    const Census c = takeCensus(
        reader->table(), h.maxLevel, [&](int l) { return h.tilesPerSide(l) * h.tilesPerSide(l); },
        [&](int l, int64_t k) {
            const int64_t side = h.tilesPerSide(l);
            return h.tileIndex(l, static_cast<int>(k % side), static_cast<int>(k / side));
        },
        [&](int l) { return h.tileSamples(l); }, [](const std::vector<uint8_t>& b) { return describeResidualBlob(b); });
    nlohmann::json j = censusJson(c);
    j["kind"] = "residual";
    j["header"] = {{"min_level", h.minLevel}, {"max_level", h.maxLevel}, {"tile_size", h.tileSize},
                   {"root_level", h.rootLevel}, {"root_tx", h.rootTx},   {"root_ty", h.rootTy},
                   {"scale", h.scale}};
    j["tiles"] = h.tileCount();
    return j;
}

nlohmann::json orthoInfo(const std::string& path) {
    const auto reader = OrthoFileReader::open(path);
    const OrthoHeader& h = reader->header();
    const Census c = takeCensus(
        reader->table(), h.maxLevel, [](int l) { return int64_t{1} << (2 * l); },
        [&](int l, int64_t k) {
            const int64_t side = int64_t{1} << l;
            return h.tileIndex(l, static_cast<int>(k % side), static_cast<int>(k / side));
        },
        [&](int) { return h.tilePixels(); },
        [&](const std::vector<uint8_t>& b) {
            return h.dxt() ? std::string(h.channels == 4 ? "dxt5" : "dxt1") : describeTiff(b);
        });
    nlohmann::json j = censusJson(c);
    j["kind"] = "ortho";
    j["header"] = {{"max_level", h.maxLevel}, {"tile_size", h.tileSize}, {"channels", h.channels},
                   {"root_level", h.rootLevel}, {"root_tx", h.rootTx}, {"root_ty", h.rootTy},
                   {"flags", h.flags},          {"dxt", h.dxt()},      {"border", h.border()}};
    j["tiles"] = h.tileCount();
    return j;
}

void printInfo(const nlohmann::json& j) {
    std::printf("%s: %s pyramid file, %lld bytes\n", j["file"].get<std::string>().c_str(),
                j["kind"].get<std::string>().c_str(), j["file_bytes"].get<long long>());
    std::printf("  header:");
    for (const auto& [key, value] : j["header"].items()) {
        std::printf(" %s=%s", key.c_str(), value.dump().c_str());
    }
    std::printf("\n  tiles: %lld (%lld distinct), tile data %lld bytes\n", j["tiles"].get<long long>(),
                j["distinct_tiles"].get<long long>(), j["data_bytes"].get<long long>());
    std::printf("  encodings:");
    for (const auto& [key, value] : j["encodings"].items()) {
        std::printf(" %s=%lld", key.c_str(), value.get<long long>());
    }
    std::printf("\n  level  tiles  side        bytes  shared\n");
    for (const auto& l : j["levels"]) {
        std::printf("  %5d %6lld %5d %12lld %7lld\n", l["level"].get<int>(), l["tiles"].get<long long>(),
                    l["tile_side"].get<int>(), l["bytes"].get<long long>(), l["shared_tiles"].get<long long>());
    }
}

nlohmann::json fileInfo(const std::string& file) {
    nlohmann::json j = detectPyramidKind(file) == PyramidKind::Residual ? residualInfo(file) : orthoInfo(file);
    j["file"] = file;
    j["file_bytes"] = std::filesystem::file_size(file);
    return j;
}

// A region set: every file's information, its root and levels in the set, and the totals.
nlohmann::json setInfo(const std::string& path) {
    const PyramidSet set = openPyramidSet(path);
    std::vector<std::string> all{set.main};
    all.insert(all.end(), set.regions.begin(), set.regions.end());
    nlohmann::json files = nlohmann::json::array();
    uint64_t fileBytes = 0, dataBytes = 0;
    int64_t tiles = 0, distinct = 0;
    int deepest = 0;
    for (const std::string& file : all) {
        nlohmann::json j = fileInfo(file);
        const nlohmann::json& h = j["header"];
        const int rootLevel = h["root_level"].get<int>();
        const int maxLevel = h["max_level"].get<int>();
        j["root"] = {rootLevel, h["root_tx"].get<int>(), h["root_ty"].get<int>()};
        j["levels"] = {rootLevel, rootLevel + maxLevel}; // absolute, first and last
        deepest = std::max(deepest, rootLevel + maxLevel);
        fileBytes += j["file_bytes"].get<uint64_t>();
        dataBytes += j["data_bytes"].get<uint64_t>();
        tiles += j["tiles"].get<int64_t>();
        distinct += j["distinct_tiles"].get<int64_t>();
        files.push_back(std::move(j));
    }
    return {{"set", set.name()},
            {"kind", kindName(set.kind)},
            {"main", set.main},
            {"max_level", deepest},
            {"files", files},
            {"totals",
             {{"files", all.size()}, {"file_bytes", fileBytes}, {"tiles", tiles}, {"distinct_tiles", distinct},
              {"data_bytes", dataBytes}}}};
}

void printSetInfo(const nlohmann::json& j) {
    const nlohmann::json& t = j["totals"];
    std::printf("%s: %s pyramid set, %lld files, %lld bytes, levels 0..%d\n", j["set"].get<std::string>().c_str(),
                j["kind"].get<std::string>().c_str(), t["files"].get<long long>(), t["file_bytes"].get<long long>(),
                j["max_level"].get<int>());
    std::printf("  tiles: %lld (%lld distinct), tile data %lld bytes\n", t["tiles"].get<long long>(),
                t["distinct_tiles"].get<long long>(), t["data_bytes"].get<long long>());
    std::printf("  %-14s %-7s %8s %12s  file\n", "root", "levels", "tiles", "bytes");
    for (const auto& f : j["files"]) {
        const auto& r = f["root"];
        const std::string root = "(" + r[0].dump() + "," + r[1].dump() + "," + r[2].dump() + ")";
        const std::string levels = f["levels"][0].dump() + ".." + f["levels"][1].dump();
        std::printf("  %-14s %-7s %8lld %12lld  %s\n", root.c_str(), levels.c_str(), f["tiles"].get<long long>(),
                    f["file_bytes"].get<long long>(), f["file"].get<std::string>().c_str());
    }
}

// Every pyramid under a directory (pyramidsUnder): each one's information as it would be alone,
// and the totals. Throws Error for the first that cannot be read, as for a set.
nlohmann::json directoryInfo(const std::string& directory, const PyramidsUnder& found) {
    if (found.count() == 0) {
        fail(directory, "no pyramid (a *.dat file or a *.regions.json index) in this directory");
    }
    nlohmann::json pyramids = nlohmann::json::array();
    uint64_t fileBytes = 0;
    int64_t files = 0;
    for (const std::string& index : found.sets) {
        nlohmann::json j = setInfo(index);
        fileBytes += j["totals"]["file_bytes"].get<uint64_t>();
        files += j["totals"]["files"].get<int64_t>();
        pyramids.push_back(std::move(j));
    }
    for (const std::string& file : found.files) {
        nlohmann::json j = fileInfo(file);
        fileBytes += j["file_bytes"].get<uint64_t>();
        files += 1;
        pyramids.push_back(std::move(j));
    }
    return {{"directory", directory},
            {"pyramids", pyramids},
            {"totals",
             {{"pyramids", found.count()}, {"region_sets", found.sets.size()}, {"files", files},
              {"file_bytes", fileBytes}}}};
}

void printDirectoryInfo(const nlohmann::json& j) {
    for (const auto& p : j["pyramids"]) {
        if (p.contains("set")) {
            printSetInfo(p);
        } else {
            printInfo(p);
        }
    }
    const nlohmann::json& t = j["totals"];
    const auto count = t["pyramids"].get<long long>(), sets = t["region_sets"].get<long long>();
    std::printf("%s: %lld pyramid%s (%lld region set%s), %lld files, %lld bytes\n",
                j["directory"].get<std::string>().c_str(), count, count == 1 ? "" : "s", sets, sets == 1 ? "" : "s",
                t["files"].get<long long>(), t["file_bytes"].get<long long>());
}

} // namespace

CommandRunner setupInfoCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    auto report = std::make_shared<std::string>();
    app.add_option("FILE", *file,
                   "Residual (DEM) or ortho pyramid file, a region set (its main file, index or directory), or a "
                   "directory: every pyramid under it")
        ->required();
    addReportOption(app, *report, "the information");
    return [file, report]() {
        std::error_code ec;
        if (std::filesystem::is_directory(*file, ec)) {
            // One set and nothing else: the set as before; else every pyramid under it.
            const PyramidsUnder found = pyramidsUnder(*file);
            const bool oneSet = found.sets.size() == 1 && found.files.empty() &&
                                std::filesystem::equivalent(std::filesystem::path(found.sets[0]).parent_path(), *file, ec);
            if (!oneSet) {
                const nlohmann::json j = directoryInfo(*file, found);
                if (!report->empty()) {
                    writeJson(j, *report);
                }
                if (*report != "-") {
                    printDirectoryInfo(j);
                }
                return kExitOk;
            }
        }
        if (!findRegionIndex(*file).empty()) {
            const nlohmann::json j = setInfo(*file);
            if (!report->empty()) {
                writeJson(j, *report);
            }
            if (*report != "-") {
                printSetInfo(j);
            }
            return kExitOk;
        }
        const PyramidKind kind = detectPyramidKind(*file);
        nlohmann::json j = kind == PyramidKind::Residual ? residualInfo(*file) : orthoInfo(*file);
        j["file"] = *file;
        j["file_bytes"] = std::filesystem::file_size(*file);
        if (!report->empty()) {
            writeJson(j, *report);
        }
        if (*report != "-") {
            printInfo(j);
        }
        return kExitOk;
    };
}

} // namespace pyramid::cli
