#include "libpyramid/encode/residual/residual_parts.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

#include "formats/error.hpp"
#include "formats/output_paths.hpp"
#include "formats/staging_directory.hpp"
#include "formats/sparse_set.hpp"
#include "libpyramid/encode/residual/residual_output.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

nlohmann::json residualHeaderJson(const ResidualHeader& h) {
    return {{"min_level", h.minLevel},   {"max_level", h.maxLevel}, {"tile_size", h.tileSize},
            {"root_level", h.rootLevel}, {"root_tx", h.rootTx},     {"root_ty", h.rootTy},
            {"scale", h.scale}};
}

std::vector<ResidualLevelReport> residualLevelReports(const ResidualHeader& header, const std::vector<LevelStats>& stats) {
    std::vector<ResidualLevelReport> levels;
    for (int l = 0; l <= header.maxLevel; ++l) {
        const LevelStats& s = stats[static_cast<size_t>(l)];
        const int side = l < header.minLevel ? 1 : 1 << (l - header.minLevel);
        ResidualLevelReport lr;
        lr.level = l;
        lr.tiles = static_cast<int64_t>(side) * side;
        lr.samples = s.samples;
        lr.maxError = s.maxError;
        lr.rmsError = s.samples ? std::sqrt(s.sumSquares / static_cast<double>(s.samples)) : 0.0;
        lr.maxAbsResidual = s.maxAbsResidual;
        levels.push_back(lr);
    }
    return levels;
}

nlohmann::json residualLevelsJson(const std::vector<ResidualLevelReport>& levels) {
    nlohmann::json list = nlohmann::json::array();
    for (const ResidualLevelReport& l : levels) {
        list.push_back({{"level", l.level},
                        {"tiles", l.tiles},
                        {"samples", l.samples},
                        {"max_error", l.maxError},
                        {"rms_error", l.rmsError},
                        {"max_abs_residual", l.maxAbsResidual}});
    }
    return list;
}

nlohmann::json residualFilesJson(const std::vector<std::pair<std::string, uint64_t>>& files) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& [name, bytes] : files) {
        list.push_back({{"file", name}, {"bytes", bytes}});
    }
    return list;
}

nlohmann::json residualCodingJson(const ResidualTileCoding& coding) {
    return {{"compression", residualCodecName(coding.codec)},
            {"deflate_level", coding.codec == ResidualCodec::Context ? nlohmann::json()
                                                                     : nlohmann::json(coding.effectiveDeflateLevel())}};
}

std::vector<uint8_t> packLevelStats(const LevelStats& s) {
    std::vector<uint8_t> out(36);
    std::memcpy(out.data(), &s.samples, 8);
    std::memcpy(out.data() + 8, &s.maxError, 8);
    std::memcpy(out.data() + 16, &s.sumSquares, 8);
    const int32_t maxAbs = s.maxAbsResidual;
    std::memcpy(out.data() + 24, &maxAbs, 4);
    std::memcpy(out.data() + 28, &s.overflowResidual, 8);
    return out;
}

LevelStats unpackLevelStats(const std::vector<uint8_t>& bytes, const std::string& where) {
    if (bytes.size() != 36) {
        fail(where, "corrupt part file (a tile's statistics are " + std::to_string(bytes.size()) + " bytes, not 36)");
    }
    LevelStats s;
    int32_t maxAbs = 0;
    std::memcpy(&s.samples, bytes.data(), 8);
    std::memcpy(&s.maxError, bytes.data() + 8, 8);
    std::memcpy(&s.sumSquares, bytes.data() + 16, 8);
    std::memcpy(&maxAbs, bytes.data() + 24, 4);
    std::memcpy(&s.overflowResidual, bytes.data() + 28, 8);
    s.maxAbsResidual = maxAbs;
    return s;
}

namespace {

ResidualHeader headerOf(const nlohmann::json& j, const std::string& where) {
    ResidualHeader h;
    h.minLevel = j.at("min_level").get<int>();
    h.maxLevel = j.at("max_level").get<int>();
    h.tileSize = j.at("tile_size").get<int>();
    h.rootLevel = j.at("root_level").get<int>();
    h.rootTx = j.at("root_tx").get<int>();
    h.rootTy = j.at("root_ty").get<int>();
    h.scale = j.at("scale").get<float>();
    h.validate(where);
    return h;
}

} // namespace

ResidualMergeReport mergeResidualParts(const std::vector<std::string>& paths, const std::string& directory,
                                       const std::function<void(int64_t, int64_t)>& progress) {
    const auto start = std::chrono::steady_clock::now();
    const PartSet set = readPartSet(paths, kResidualPartFormat);
    const int count = set.count;
    const int pyramids = set.pyramids;
    const int64_t totalTiles = set.tiles;
    const auto& runs = set.shares;
    ResidualMergeReport report;
    report.parts = count;
    report.directory = directory;
    OutputParents parents; // removed again if the merge fails
    makeOutputDirectory(directory.empty() ? "." : directory, parents, directory);
    std::unique_ptr<StagingDirectory> staging;
    if (pyramids > 1) {
        staging = std::make_unique<StagingDirectory>(directory);
    }
    int64_t done = 0;
    for (int k = 0; k < pyramids; ++k) {
        const std::vector<PartSet::Share>& list = runs.at(k);
        const nlohmann::json& top = *list[0].entry;
        const std::string& topPath = list[0].part->reader->path();
        const std::string name = top.at("name").get<std::string>();
        const ResidualHeader header = headerOf(top.at("header"), topPath);
        const std::string output = staging ? staging->path(name) : (std::filesystem::path(directory) / name).string();
        const uint64_t maxFileBytes = top.at("max_file_bytes").get<uint64_t>();
        // A sparse build's parts: their empty subtrees are records without statistics, and the
        // files hold only what its log chooses (formats/sparse_set.hpp).
        const bool sparse = top.value("sparse", false);
        // The merge has no thread count of its own: all cores.
        const std::optional<int> parentModes =
            top.value("parent_modes", false) ? std::optional<int>(0) : std::nullopt;
        std::unique_ptr<ResidualOutput> sparseOut, denseOut;
        if (sparse) {
            const std::optional<std::vector<uint8_t>> empty = bytesOfHex(top.value("empty_tile", std::string()));
            if (!empty || empty->empty()) {
                fail(topPath, "corrupt part file (a sparse pyramid without its empty tile)");
            }
            sparseOut = std::make_unique<ResidualOutput>(output, header, maxFileBytes,
                                                         ResidualOutput::Sparse{*empty, parentModes});
        } else {
            denseOut = std::make_unique<ResidualOutput>(output, header, maxFileBytes, false, parentModes);
        }
        ResidualOutput& out = sparse ? *sparseOut : *denseOut;
        std::vector<LevelStats> stats(static_cast<size_t>(header.maxLevel) + 1);
        ResidualPyramidReport pr;
        for (const PartSet::Share& r : list) {
            const PartFileReader& reader = *r.part->reader;
            const auto range = r.entry->at("records");
            auto cursor = reader.records(range.at(0).get<uint64_t>(), range.at(1).get<uint64_t>());
            PartFileReader::Record record;
            while (cursor.next(record)) {
                if (record.stream != static_cast<uint32_t>(k) || !header.contains(record.level, record.tx, record.ty)) {
                    fail(reader.path(), "corrupt part file (a record of stream " + std::to_string(record.stream) +
                                            " for tile " + std::to_string(record.level) + "/" + std::to_string(record.tx) +
                                            "/" + std::to_string(record.ty) + " among " + name + "'s)");
                }
                if (sparse && record.extra.empty()) {
                    out.log()->addEmptySubtree(record.level, record.tx, record.ty);
                } else if (sparse) {
                    out.log()->add(record.level, record.tx, record.ty, record.blob);
                } else {
                    out.writer().writeTileBytes(record.level, record.tx, record.ty, record.blob);
                }
                if (!record.extra.empty() || !sparse) {
                    stats[static_cast<size_t>(record.level)].merge(unpackLevelStats(record.extra, reader.path()));
                }
                ++done;
                if (progress) {
                    progress(done, totalTiles);
                }
            }
            pr.nodataFilled += r.entry->at("nodata_filled").get<int64_t>();
        }
        std::vector<CompanionFile> companions;
        for (const auto& [file, text] : top.at("companions").items()) {
            companions.push_back(CompanionFile{file, text.get<std::string>()});
        }
        pr.tiles = header.tileCount();
        out.place(companions, pr); // a sparse set's tiles: those of its files
        pr.finestSamples = top.at("finest_samples").get<int64_t>();
        pr.scalesTried = top.at("scales_tried").get<std::vector<double>>();
        pr.levels = residualLevelReports(header, stats);
        report.outputs.push_back((std::filesystem::path(directory) / name).string());
        report.pyramids.push_back(std::move(pr));
    }
    if (staging) {
        staging->commit();
    }
    parents.keep();
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

nlohmann::json toJson(const ResidualMergeReport& r) {
    nlohmann::json pyramids = nlohmann::json::array();
    for (size_t k = 0; k < r.pyramids.size(); ++k) {
        const ResidualPyramidReport& p = r.pyramids[k];
        pyramids.push_back({{"output", r.outputs[k]},
                            {"header", residualHeaderJson(p.header)},
                            {"tiles", p.tiles},
                            {"shared_tiles", p.sharedTiles},
                            {"bytes", p.bytes},
                            {"files", residualFilesJson(p.files)},
                            {"nodata_filled", p.nodataFilled},
                            {"levels", residualLevelsJson(p.levels)}});
    }
    return {{"parts", r.parts}, {"directory", r.directory}, {"pyramids", pyramids}, {"seconds", r.seconds}};
}

} // namespace pyramid
