// `pyramid info FILE [--json]`: what a pyramid file holds.
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
        [&](int l) { return h.tileSamples(l); }, [](const std::vector<uint8_t>& b) { return describeTiff(b); });
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

} // namespace

CommandRunner setupInfoCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    app.add_option("FILE", *file, "Residual (DEM) or ortho pyramid file")->required();
    app.add_flag("--json", *json, "Print the information as JSON");
    return [file, json]() {
        const PyramidKind kind = detectPyramidKind(*file);
        nlohmann::json j = kind == PyramidKind::Residual ? residualInfo(*file) : orthoInfo(*file);
        j["file"] = *file;
        j["file_bytes"] = std::filesystem::file_size(*file);
        if (*json) {
            writeJson(j, "-");
        } else {
            printInfo(j);
        }
        return kExitOk;
    };
}

} // namespace pyramid::cli
