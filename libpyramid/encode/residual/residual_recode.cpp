#include "libpyramid/encode/residual/residual_recode.hpp"

#include <omp.h>

#include <chrono>
#include <exception>
#include <filesystem>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/tile_table.hpp"
#include "libpyramid/encode/residual/residual_parent_pass.hpp"
#include "libpyramid/encode/residual/residual_parts.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

struct TileRef {
    int level = 0, tx = 0, ty = 0;
    uint64_t begin = 0; // the input byte range's start: tiles sharing bytes share it
    bool shared = false;
};

// Tiles coded at once: enough for every thread, few enough to bound memory.
constexpr size_t kBatchPerThread = 16;

} // namespace

ResidualRecodeReport recodeResidualFile(const std::string& input, const std::string& output,
                                        const ResidualRecodeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    options.tiles.validate();
    const int threads = workerThreads(options.threads);
    OpenedPyramid opened = openPyramid(input);
    if (opened.kind != PyramidKind::Residual) {
        fail(input, "holds an ortho pyramid: recoding stores a residual (DEM) file's tiles in another codec");
    }
    const std::unique_ptr<ResidualFileReader> reader = std::move(opened.residual);
    const ResidualHeader& h = reader->header();
    ResidualRecodeReport report;
    report.input = input;
    report.output = output;
    report.header = h;
    report.coding = options.tiles;
    report.threads = threads;
    report.inputBytes = std::filesystem::file_size(input);
    // Level by level, row by row; how many tiles share each input byte range.
    std::vector<TileRef> tiles;
    tiles.reserve(static_cast<size_t>(h.tileCount()));
    std::unordered_map<uint64_t, int64_t> uses;
    for (int l = 0; l <= h.maxLevel; ++l) {
        for (int ty = 0; ty < h.tilesPerSide(l); ++ty) {
            for (int tx = 0; tx < h.tilesPerSide(l); ++tx) {
                const TileTable::Range range = reader->tileRange(l, tx, ty);
                tiles.push_back({l, tx, ty, range.begin, false});
                ++uses[range.begin];
            }
        }
    }
    for (TileRef& t : tiles) {
        t.shared = uses[t.begin] > 1;
    }
    ResidualFileWriter writer(output, h);
    // The output blob of every shared input range, once coded (zero tiles, mostly).
    std::unordered_map<uint64_t, std::vector<uint8_t>> sharedBlobs;
    const size_t batch = kBatchPerThread * static_cast<size_t>(report.threads);
    std::vector<std::vector<uint8_t>> blobs;
    std::vector<size_t> todo;
    for (size_t first = 0; first < tiles.size(); first += batch) {
        const size_t last = std::min(tiles.size(), first + batch);
        // What this batch codes: each tile not shared, and the first of each shared range.
        todo.clear();
        std::unordered_map<uint64_t, size_t> firstInBatch;
        for (size_t k = first; k < last; ++k) {
            const TileRef& t = tiles[k];
            if (t.shared && (sharedBlobs.count(t.begin) || !firstInBatch.emplace(t.begin, k).second)) {
                continue;
            }
            todo.push_back(k);
        }
        blobs.assign(last - first, {});
        std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic) num_threads(report.threads)
        for (size_t i = 0; i < todo.size(); ++i) {
            const TileRef& t = tiles[todo[i]];
            try {
                const std::vector<int16_t> residuals = reader->readTile(t.level, t.tx, t.ty);
                blobs[todo[i] - first] = encodeResidualBlob(residuals, h.tileSamples(t.level), options.tiles);
            } catch (...) {
#pragma omp critical(pyramid_recode_failure)
                if (!failure) {
                    failure = std::current_exception();
                }
            }
        }
        if (failure) {
            std::rethrow_exception(failure);
        }
        for (size_t k = first; k < last; ++k) {
            const TileRef& t = tiles[k];
            if (t.shared) {
                auto found = sharedBlobs.find(t.begin);
                if (found == sharedBlobs.end()) {
                    found = sharedBlobs.emplace(t.begin, std::move(blobs[firstInBatch.at(t.begin) - first])).first;
                }
                writer.writeTileBytes(t.level, t.tx, t.ty, found->second);
            } else {
                writer.writeTileBytes(t.level, t.tx, t.ty, blobs[k - first]);
            }
        }
        if (options.progress) {
            options.progress(static_cast<int64_t>(last), static_cast<int64_t>(tiles.size()));
        }
    }
    writer.commit();
    if (options.tiles.codec == ResidualCodec::Context) {
        // Its tiles take the parent mode where smaller (a second complete file, put in place the same way).
        rewriteInParentMode(output, output, threads)->commit();
    }
    report.tiles = static_cast<int64_t>(tiles.size());
    report.sharedTiles = writer.sharedTiles();
    report.bytes = std::filesystem::file_size(output);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

nlohmann::json toJson(const ResidualRecodeReport& r) {
    nlohmann::json j = {{"input", r.input},
            {"output", r.output},
            {"tiles", r.tiles},
            {"shared_tiles", r.sharedTiles},
            {"input_bytes", r.inputBytes},
            {"bytes", r.bytes},
            {"threads", r.threads},
            {"seconds", r.seconds}};
    j.update(residualCodingJson(r.coding));
    return j;
}

} // namespace pyramid
