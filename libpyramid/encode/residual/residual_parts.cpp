#include "libpyramid/encode/residual/residual_parts.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

#include "formats/error.hpp"
#include "formats/staging_directory.hpp"
#include "libpyramid/encode/residual/residual_output.hpp"

namespace pyramid {

namespace {

constexpr const char* kFormat = "libpyramid residual part";

// floor(total * i / count) without overflow.
int64_t cut(int64_t total, int i, int count) {
    return (total / count) * i + (total % count) * i / count;
}

} // namespace

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

ShareRange shareRange(int index, int count, int pyramid, int pyramids, int64_t units) {
    const int64_t total = units * pyramids;
    // Runs of whole groups of 4 when a pyramid has subtrees (units is then a multiple of 4).
    const int64_t group = units % 4 == 0 ? 4 : 1;
    const auto boundary = [&](int i) { return i >= count ? total : cut(total / group, i, count) * group; };
    const int64_t b = boundary(index), e = boundary(index + 1);
    const int64_t first = static_cast<int64_t>(pyramid) * units;
    ShareRange r;
    r.begin = std::clamp<int64_t>(b - first, 0, units);
    r.end = std::clamp<int64_t>(e - first, 0, units);
    r.top = first >= b && first < e;
    return r;
}

ResidualPartOutput::ResidualPartOutput(const std::string& path, int index, int count, nlohmann::json job)
    : file_(path), index_(index), count_(count), job_(std::move(job)) {}

void ResidualPartOutput::addPyramid(nlohmann::json entry) { pyramids_.push_back(std::move(entry)); }

void ResidualPartOutput::commit() {
    const nlohmann::json trailer{{"format", kFormat}, {"version", 1},   {"part", index_},
                                 {"parts", count_},   {"job", job_},    {"pyramids", pyramids_}};
    file_.commit(trailer.dump());
}

std::string partFileName(const std::string& output, int index, int count) {
    return output + ".part-" + std::to_string(index) + "-of-" + std::to_string(count);
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

struct Part {
    std::unique_ptr<PartFileReader> reader;
    nlohmann::json trailer;
};

struct Run {
    const Part* part = nullptr;
    const nlohmann::json* entry = nullptr;
    int64_t begin = 0, end = 0;
    bool top = false;
};

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
    if (paths.empty()) {
        failOption("parts", "no part files to merge");
    }
    std::vector<Part> parts;
    for (const std::string& path : paths) {
        Part p;
        p.reader = std::make_unique<PartFileReader>(path);
        try {
            p.trailer = nlohmann::json::parse(p.reader->trailer());
            if (p.trailer.at("format").get<std::string>() != kFormat || p.trailer.at("version").get<int>() != 1) {
                fail(path, "not a part of a residual build (" + p.trailer.at("format").get<std::string>() + ")");
            }
            (void)p.trailer.at("part").get<int>();
            (void)p.trailer.at("parts").get<int>();
            (void)p.trailer.at("pyramids").size();
        } catch (const nlohmann::json::exception& e) {
            fail(path, std::string("corrupt part file trailer (") + e.what() + ")");
        }
        parts.push_back(std::move(p));
    }
    std::sort(parts.begin(), parts.end(), [](const Part& a, const Part& b) {
        return a.trailer["part"].get<int>() < b.trailer["part"].get<int>();
    });
    const int count = parts[0].trailer["parts"].get<int>();
    std::vector<const Part*> byIndex(static_cast<size_t>(std::max(count, 0)), nullptr);
    for (const Part& p : parts) {
        const std::string& where = p.reader->path();
        if (p.trailer["parts"].get<int>() != count) {
            fail(where, "is a part of " + std::to_string(p.trailer["parts"].get<int>()) + ", the others of " +
                            std::to_string(count));
        }
        if (p.trailer["job"] != parts[0].trailer["job"]) {
            fail(where, "is a part of another build than " + parts[0].reader->path() + " (" +
                            p.trailer["job"].dump() + " against " + parts[0].trailer["job"].dump() + ")");
        }
        const int index = p.trailer["part"].get<int>();
        if (index < 0 || index >= count) {
            fail(where, "corrupt part file trailer (part " + std::to_string(index) + " of " + std::to_string(count) + ")");
        }
        if (byIndex[static_cast<size_t>(index)]) {
            fail(where, "part " + std::to_string(index) + " of " + std::to_string(count) + " is given twice (also " +
                            byIndex[static_cast<size_t>(index)]->reader->path() + ")");
        }
        byIndex[static_cast<size_t>(index)] = &p;
    }
    for (int i = 0; i < count; ++i) {
        if (!byIndex[static_cast<size_t>(i)]) {
            fail(parts[0].reader->path(), "part " + std::to_string(i) + " of " + std::to_string(count) +
                                               " is missing: every part of the build is needed");
        }
    }

    // Each pyramid's runs, in order.
    std::map<int, std::vector<Run>> runs;
    int pyramids = -1;
    int64_t totalTiles = 0;
    for (const Part& p : parts) {
        const std::string& where = p.reader->path();
        try {
            for (const nlohmann::json& e : p.trailer["pyramids"]) {
                const int k = e.at("pyramid").get<int>();
                const int of = e.at("pyramids").get<int>();
                if (pyramids < 0) {
                    pyramids = of;
                }
                if (of != pyramids || k < 0 || k >= pyramids) {
                    fail(where, "corrupt part file trailer (pyramid " + std::to_string(k) + " of " + std::to_string(of) + ")");
                }
                Run r;
                r.part = &p;
                r.entry = &e;
                r.begin = e.at("begin").get<int64_t>();
                r.end = e.at("end").get<int64_t>();
                r.top = e.at("top").get<bool>();
                totalTiles += e.at("tiles").get<int64_t>();
                runs[k].push_back(r);
            }
        } catch (const nlohmann::json::exception& e) {
            fail(where, std::string("corrupt part file trailer (") + e.what() + ")");
        }
    }
    if (pyramids <= 0) {
        fail(parts[0].reader->path(), "the parts hold no pyramid");
    }
    for (int k = 0; k < pyramids; ++k) {
        std::vector<Run>& list = runs[k];
        if (list.empty()) {
            fail(parts[0].reader->path(), "no part holds pyramid " + std::to_string(k + 1) + " of " + std::to_string(pyramids));
        }
        const nlohmann::json& first = *list[0].entry;
        const int64_t units = first.at("units").get<int64_t>();
        int64_t next = 0;
        for (size_t i = 0; i < list.size(); ++i) {
            const Run& r = list[i];
            const std::string& where = r.part->reader->path();
            const nlohmann::json& e = *r.entry;
            if (e.at("name") != first.at("name") || e.at("header") != first.at("header") || e.at("units") != first.at("units") ||
                e.at("max_file_bytes") != first.at("max_file_bytes")) {
                fail(where, "its pyramid " + e.at("name").get<std::string>() + " differs from " +
                                list[0].part->reader->path() + "'s (header, scale or split)");
            }
            if (r.top != (i == 0) || r.begin != next || r.end < r.begin || r.end > units) {
                fail(where, "its share of " + e.at("name").get<std::string>() + " (subtrees " + std::to_string(r.begin) +
                                " to " + std::to_string(r.end) + ") does not follow the part before it (which ends at " +
                                std::to_string(next) + ")");
            }
            next = r.end;
        }
        if (next != units && !(units == 1 && next == 0 && list[0].top)) {
            fail(list.back().part->reader->path(), "the parts of " + first.at("name").get<std::string>() +
                                                       " end at subtree " + std::to_string(next) + " of " +
                                                       std::to_string(units));
        }
    }

    ResidualMergeReport report;
    report.parts = count;
    report.directory = directory;
    std::filesystem::create_directories(directory.empty() ? std::filesystem::path(".") : std::filesystem::path(directory));
    std::unique_ptr<StagingDirectory> staging;
    if (pyramids > 1) {
        staging = std::make_unique<StagingDirectory>(directory);
    }
    int64_t done = 0;
    for (int k = 0; k < pyramids; ++k) {
        const std::vector<Run>& list = runs[k];
        const nlohmann::json& top = *list[0].entry;
        const std::string& topPath = list[0].part->reader->path();
        const std::string name = top.at("name").get<std::string>();
        const ResidualHeader header = headerOf(top.at("header"), topPath);
        const std::string output = staging ? staging->path(name) : (std::filesystem::path(directory) / name).string();
        ResidualOutput out(output, header, top.at("max_file_bytes").get<uint64_t>());
        std::vector<LevelStats> stats(static_cast<size_t>(header.maxLevel) + 1);
        ResidualPyramidReport pr;
        for (const Run& r : list) {
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
                out.writer().writeTileBytes(record.level, record.tx, record.ty, record.blob);
                stats[static_cast<size_t>(record.level)].merge(unpackLevelStats(record.extra, reader.path()));
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
        out.place(companions, pr);
        pr.tiles = header.tileCount();
        pr.finestSamples = top.at("finest_samples").get<int64_t>();
        pr.scalesTried = top.at("scales_tried").get<std::vector<double>>();
        pr.levels = residualLevelReports(header, stats);
        report.outputs.push_back((std::filesystem::path(directory) / name).string());
        report.pyramids.push_back(std::move(pr));
    }
    if (staging) {
        staging->commit();
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

nlohmann::json toJson(const ResidualMergeReport& r) {
    nlohmann::json pyramids = nlohmann::json::array();
    for (size_t k = 0; k < r.pyramids.size(); ++k) {
        const ResidualPyramidReport& p = r.pyramids[k];
        nlohmann::json files = nlohmann::json::array();
        for (const auto& [name, bytes] : p.files) {
            files.push_back({{"file", name}, {"bytes", bytes}});
        }
        nlohmann::json levels = nlohmann::json::array();
        for (const ResidualLevelReport& l : p.levels) {
            levels.push_back({{"level", l.level},
                              {"tiles", l.tiles},
                              {"samples", l.samples},
                              {"max_error", l.maxError},
                              {"rms_error", l.rmsError},
                              {"max_abs_residual", l.maxAbsResidual}});
        }
        pyramids.push_back({{"output", r.outputs[k]},
                            {"header", residualHeaderJson(p.header)},
                            {"tiles", p.tiles},
                            {"shared_tiles", p.sharedTiles},
                            {"bytes", p.bytes},
                            {"files", files},
                            {"nodata_filled", p.nodataFilled},
                            {"levels", levels}});
    }
    return {{"parts", r.parts}, {"directory", r.directory}, {"pyramids", pyramids}, {"seconds", r.seconds}};
}

} // namespace pyramid
