#include "libpyramid/encode/ortho/ortho_parts.hpp"

#include <chrono>
#include <filesystem>
#include <memory>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/part_file.hpp"
#include "formats/staging_directory.hpp"
#include "libpyramid/encode/ortho/ortho_output.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

OrthoMergeReport mergeOrthoParts(const std::vector<std::string>& paths, const std::string& directory,
                                 const std::function<void(int64_t, int64_t)>& progress) {
    const auto start = std::chrono::steady_clock::now();
    const PartSet set = readPartSet(paths, kOrthoPartFormat);
    OrthoMergeReport report;
    report.parts = set.count;
    report.directory = directory;
    StagingDirectory staging(directory); // every output appears together, or none
    int64_t done = 0;
    for (int k = 0; k < set.pyramids; ++k) {
        const std::vector<PartSet::Share>& shares = set.shares.at(k);
        const nlohmann::json& top = *shares[0].entry;
        const std::string& topPath = shares[0].part->reader->path();
        OrthoReport pr;
        pr.directory = directory;
        std::unique_ptr<OrthoFileWriter> writers[3];
        // A sparse build's parts (OrthoEncodeOptions::layout): each output's tiles and empty
        // subtrees (records of no bytes) go to a log, and its files are those the log chooses
        // (formats/sparse_set.hpp), as in the single run.
        std::unique_ptr<SparseTileLog> logs[3];
        OrthoHeader headers[3];
        const bool sparse = top.value("sparse", false);
        // An input of several resolutions: the TIFF and DXT empty subtrees are left out.
        const bool leftOut = top.value("left_out", false);
        std::string names[3];
        int maxLevel = 0;
        try {
            for (const nlohmann::json& o : top.at("header").at("outputs")) {
                const int slot = o.at("slot").get<int>();
                if (slot < 0 || slot > 2 || writers[slot]) {
                    fail(topPath, "corrupt part file trailer (output slot " + std::to_string(slot) + ")");
                }
                OrthoHeader h;
                h.maxLevel = o.at("max_level").get<int>();
                h.tileSize = o.at("tile_size").get<int>();
                h.channels = o.at("channels").get<int>();
                h.flags = o.at("flags").get<uint32_t>();
                h.validate(topPath);
                names[slot] = o.at("name").get<std::string>();
                headers[slot] = h;
                if (sparse) {
                    const std::optional<std::vector<uint8_t>> empty =
                        bytesOfHex(top.at("empty_tiles").at(static_cast<size_t>(slot)).get<std::string>());
                    if (!empty || empty->empty()) {
                        fail(topPath, "corrupt part file (a sparse pyramid without its empty tiles)");
                    }
                    logs[slot] = std::make_unique<SparseTileLog>(staging.path(names[slot] + ".tiles"), *empty);
                } else {
                    writers[slot] = std::make_unique<OrthoFileWriter>(staging.path(names[slot]), h);
                }
                maxLevel = h.maxLevel;
                pr.tileSize = h.tileSize;
                pr.maxLevel = h.maxLevel;
                pr.tiles = h.tileCount();
            }
        } catch (const nlohmann::json::exception& e) {
            fail(topPath, std::string("corrupt part file trailer (") + e.what() + ")");
        }
        std::vector<OrthoLevelTotals> totals(static_cast<size_t>(maxLevel) + 1);
        for (const PartSet::Share& share : shares) {
            const PartFileReader& reader = *share.part->reader;
            const auto& range = share.entry->at("records");
            auto cursor = reader.records(range.at(0).get<uint64_t>(), range.at(1).get<uint64_t>());
            PartFileReader::Record r;
            while (cursor.next(r)) {
                const uint32_t slot = r.stream % 3;
                if (r.stream / 3 != static_cast<uint32_t>(k) || !(writers[slot] || logs[slot]) || r.level > maxLevel ||
                    r.tx < 0 || r.ty < 0 || r.tx >= (1 << r.level) || r.ty >= (1 << r.level)) {
                    fail(reader.path(), "corrupt part file (a record of stream " + std::to_string(r.stream) + " for tile " +
                                            std::to_string(r.level) + "/" + std::to_string(r.tx) + "/" +
                                            std::to_string(r.ty) + ")");
                }
                if (!logs[slot]) {
                    writers[slot]->writeTileBytes(r.level, r.tx, r.ty, r.blob);
                } else if (r.blob.empty() && leftOut && slot < 2) {
                    logs[slot]->addLeftOutSubtree(r.level, r.tx, r.ty);
                } else if (r.blob.empty()) {
                    logs[slot]->addEmptySubtree(r.level, r.tx, r.ty);
                } else {
                    logs[slot]->add(r.level, r.tx, r.ty, r.blob);
                }
                if (!r.extra.empty()) {
                    const OrthoTileStats stats = unpackOrthoTileStats(r.extra, reader.path());
                    if (stats.tiles != 0 && stats.tiles != 1) {
                        fail(reader.path(), "corrupt part file (a tile's statistics count " + std::to_string(stats.tiles) + " tiles)");
                    }
                    totals[static_cast<size_t>(r.level)].add(stats);
                    done += stats.tiles;
                    if (progress && stats.tiles) {
                        progress(done, set.tiles);
                    }
                }
            }
        }
        const uint64_t maxFileBytes = top.at("max_file_bytes").get<uint64_t>();
        bool firstOutput = true;
        for (int slot = 0; slot < 3; ++slot) {
            if (logs[slot]) {
                const std::string output = (std::filesystem::path(directory) / names[slot]).string();
                pr.outputs.push_back(output);
                const int64_t held =
                    placeSparseOrthoOutput(*logs[slot], headers[slot], names[slot], output, maxFileBytes, staging, pr);
                logs[slot].reset(); // its spooled blobs go before the staging directory is committed
                if (firstOutput) {
                    pr.tiles = held; // the tiles the first output's files hold, as the single run reports
                }
                firstOutput = false;
            }
            if (writers[slot]) {
                const std::string output = (std::filesystem::path(directory) / names[slot]).string();
                pr.outputs.push_back(output);
                pr.sharedTiles.push_back(writers[slot]->sharedTiles());
                placeOrthoOutput(std::move(writers[slot]), names[slot], output, maxFileBytes, staging, pr);
            }
        }
        for (const auto& [name, text] : top.at("companions").items()) {
            AtomicFile file(staging.path(name));
            const std::string t = text.get<std::string>();
            file.writeAt(0, t.data(), t.size());
            file.commit();
        }
        for (size_t l = 0; l < totals.size(); ++l) {
            pr.levels.push_back(totals[l].report(static_cast<int>(l)));
        }
        report.pyramids.push_back(std::move(pr));
    }
    staging.commit();
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

nlohmann::json toJson(const OrthoMergeReport& r) {
    nlohmann::json pyramids = nlohmann::json::array();
    for (const OrthoReport& p : r.pyramids) {
        nlohmann::json outputs = nlohmann::json::array();
        for (size_t i = 0; i < p.outputs.size(); ++i) {
            nlohmann::json files = nlohmann::json::array();
            for (const auto& [name, bytes] : p.files[i]) {
                files.push_back({{"file", name}, {"bytes", bytes}});
            }
            outputs.push_back({{"output", p.outputs[i]},
                               {"bytes", p.bytes[i]},
                               {"shared_tiles", p.sharedTiles[i]},
                               {"files", files}});
        }
        nlohmann::json levels = nlohmann::json::array();
        for (const OrthoLevelReport& l : p.levels) {
            levels.push_back({{"level", l.level},
                              {"tiles", l.tiles},
                              {"tiff_max_error", l.tiffMaxError},
                              {"dxt_psnr_db", l.dxtPsnr},
                              {"residual_max_error", l.residualMaxError},
                              {"residual_rms_error", l.residualRmsError},
                              {"clamped_residuals", l.clampedResiduals}});
        }
        pyramids.push_back({{"tiles", p.tiles}, {"outputs", outputs}, {"levels", levels}});
    }
    return {{"parts", r.parts}, {"directory", r.directory}, {"pyramids", pyramids}, {"seconds", r.seconds}};
}

} // namespace pyramid
