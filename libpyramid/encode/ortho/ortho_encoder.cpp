#include "libpyramid/encode/ortho/ortho_encoder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <map>
#include <mutex>
#include <tuple>

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"
#include "formats/staging_directory.hpp"
#include "libpyramid/encode/ortho/ortho_tile_encoder.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

struct LevelTotals {
    int64_t tiles = 0;
    OrthoTileStats s;
};

// The options that do not depend on the input, checked before it is opened.
void checkOptions(const OrthoEncodeOptions& o) {
    if (o.border != 0 && o.border != 2) {
        fail("--border", std::to_string(o.border) + " is not 0 or 2");
    }
    if (!o.writeTiff && !o.writeDxt && !o.writeResiduals) {
        fail("--outputs", "selects no output");
    }
    if (o.jpegQuality < 1 || o.jpegQuality > 100) {
        fail("--jpeg-quality", std::to_string(o.jpegQuality) + " is not 1..100");
    }
    if (o.deflateLevel < 1 || o.deflateLevel > 12) {
        fail("--deflate-level", std::to_string(o.deflateLevel) + " is not 1..12");
    }
    if (o.dxtQuality < 0 || o.dxtQuality >= kDxtQualityLevels) {
        fail("--dxt-quality", std::to_string(o.dxtQuality) + " is not 0, 1, 2 or 3");
    }
    if (o.residualCompression != TilePolicy::Deflate && o.residualCompression != TilePolicy::Jpeg) {
        fail("--residual-compression", "must be deflate or jpeg");
    }
    if (o.name.empty() || o.name.find('/') != std::string::npos) {
        fail("--name", "'" + o.name + "' is not a plain file name");
    }
}

// Writes the outputs into `staging` (the caller commits it); the report names their final
// paths in `directory`.
OrthoReport encodeLevels(const OrthoLevels& levels, const std::string& directory, StagingDirectory& staging,
                         const OrthoEncodeOptions& o, std::chrono::steady_clock::time_point start) {
    const int channels = levels.channels();
    const int T = levels.tileSize();
    if ((o.compression == TilePolicy::Jpeg || o.compression == TilePolicy::JpegYCbCr) && o.writeTiff && channels != 1 &&
        channels != 3) {
        fail("--compression", "JPEG tiles hold 1 or 3 channels, the input has " + std::to_string(channels));
    }
    if (o.residualCompression == TilePolicy::Jpeg && o.writeResiduals && channels != 1 && channels != 3) {
        fail("--residual-compression", "JPEG tiles hold 1 or 3 channels, the input has " + std::to_string(channels));
    }
    if (o.writeDxt && (T + 2 * o.border) % 4 != 0) {
        fail("--tile-size", "DXT tiles need tile size + 2 x border to be a multiple of 4");
    }

    OrthoHeader base;
    base.maxLevel = levels.maxLevel();
    base.tileSize = T;
    base.channels = channels;
    base.flags = o.border == 0 ? OrthoHeader::kFlagNoBorder : 0u;
    const std::filesystem::path dir(directory);
    const std::string file = o.name + ".dat";
    std::unique_ptr<OrthoFileWriter> tiff, dxt, residual;
    std::vector<std::string> staged; // where each output is written before the commit
    OrthoReport report;
    report.input = levels.inputPath();
    report.directory = directory;
    auto output = [&](const std::string& relative, const OrthoHeader& h) {
        staged.push_back(staging.path(relative));
        report.outputs.push_back((dir / relative).string());
        return std::make_unique<OrthoFileWriter>(staged.back(), h);
    };
    if (o.writeTiff) {
        tiff = output(file, base);
    }
    if (o.writeDxt) {
        OrthoHeader h = base;
        h.channels = std::max(3, channels);
        h.flags |= OrthoHeader::kFlagDxt;
        dxt = output("dxt/" + file, h);
    }
    if (o.writeResiduals) {
        OrthoHeader h = base;
        h.flags = 0; // colour residuals always carry their 2-pixel border
        residual = output("residuals/" + file, h);
    }

    const OrthoTileEncoder encoder(levels, o);
    const int threads = levels.threads();
    std::vector<LevelTotals> totals(static_cast<size_t>(levels.maxLevel()) + 1);
    std::map<std::tuple<int, int, int>, std::vector<uint8_t>> shallowRecon; // levels 0..C
    const int64_t total = levels.tileCount();
    int64_t done = 0;
    auto parentOf = [](const TrueTile& t) { return std::make_tuple(t.level - 1, t.tx / 2, t.ty / 2); };

    // Writes one group's tiles in the walk's order and adds up their statistics.
    auto write = [&](std::vector<std::vector<EncodedOrthoTile>>& results) {
        for (auto& item : results) {
            for (EncodedOrthoTile& e : item) {
                if (tiff) {
                    tiff->writeTileBytes(e.level, e.tx, e.ty, e.tiff);
                }
                if (dxt) {
                    dxt->writeTileBytes(e.level, e.tx, e.ty, e.dxt);
                }
                if (residual) {
                    residual->writeTileBytes(e.level, e.tx, e.ty, e.residual);
                }
                LevelTotals& lt = totals[static_cast<size_t>(e.level)];
                lt.tiles += 1;
                lt.s.tiffMaxError = std::max(lt.s.tiffMaxError, e.stats.tiffMaxError);
                lt.s.jpegTiles += e.stats.jpegTiles;
                lt.s.dxtSquares += e.stats.dxtSquares;
                lt.s.dxtSamples += e.stats.dxtSamples;
                lt.s.residualMaxError = std::max(lt.s.residualMaxError, e.stats.residualMaxError);
                lt.s.residualSquares += e.stats.residualSquares;
                lt.s.residualSamples += e.stats.residualSamples;
                lt.s.clamped += e.stats.clamped;
                if (o.colourReconstruction && residual) {
                    o.colourReconstruction(e.level, e.tx, e.ty, e.recon);
                }
                if (o.progress) {
                    o.progress(++done, total);
                }
            }
        }
    };
    // A group is written (content hashes, file writes: serial, in order) by a thread of its own
    // while the walk samples and encodes the next group, instead of both cores waiting for it.
    // At most one group is being written: the next one waits for it, so the files' order is
    // unchanged and memory grows by one group's encoded tiles at most. Declared after everything
    // it uses (its destructor waits for a write still running).
    std::future<void> writing;
    auto finishWriting = [&] {
        if (writing.valid()) {
            writing.get(); // rethrows a failed write
        }
    };

    // Colour residuals predict each tile from its parent's rebuilt colours: parents first.
    // Without them, tiles are independent, and the input is read once (OrthoLevels::walk).
    const auto order = o.writeResiduals ? OrthoLevels::WalkOrder::CoarseFirst : OrthoLevels::WalkOrder::SinglePass;
    levels.walk([&](std::vector<TileBatch>& group) {
        std::vector<std::vector<EncodedOrthoTile>> results(group.size());
        const bool oneLevel = group.size() == 1 && !group[0].empty() &&
                              std::all_of(group[0].begin(), group[0].end(),
                                          [&](const TrueTile& t) { return t.level == group[0][0].level; });
        if (oneLevel) {
            // A whole level: its tiles are independent given the previous level's reconstruction.
            TileBatch& batch = group[0];
            results[0].resize(batch.size());
            parallelFor(static_cast<int64_t>(batch.size()), threads, [&](int64_t i) {
                const TrueTile& t = batch[static_cast<size_t>(i)];
                const std::vector<uint8_t>* parent =
                    t.level && o.writeResiduals ? &shallowRecon.at(parentOf(t)) : nullptr;
                results[0][static_cast<size_t>(i)] = encoder.encode(t, parent);
            });
        } else {
            // Subtrees: each in pre-order, its parents before its children.
            parallelFor(static_cast<int64_t>(group.size()), threads, [&](int64_t i) {
                std::map<std::tuple<int, int, int>, const std::vector<uint8_t>*> local;
                auto& out = results[static_cast<size_t>(i)];
                out.reserve(group[static_cast<size_t>(i)].size());
                for (const TrueTile& t : group[static_cast<size_t>(i)]) {
                    if (!o.writeResiduals) {
                        out.push_back(encoder.encode(t, nullptr)); // no tile depends on its parent
                        continue;
                    }
                    const auto key = parentOf(t);
                    const auto it = local.find(key);
                    const std::vector<uint8_t>* parent = it != local.end() ? it->second : &shallowRecon.at(key);
                    out.push_back(encoder.encode(t, parent));
                    local[{t.level, t.tx, t.ty}] = &out.back().recon;
                }
            });
        }
        if (oneLevel && o.writeResiduals) {
            // The next groups predict from these rebuilt tiles while this one is written.
            for (const EncodedOrthoTile& e : results[0]) {
                shallowRecon[{e.level, e.tx, e.ty}] = e.recon;
            }
        }
        finishWriting();
        writing = std::async(std::launch::async, [&write, batch = std::move(results)]() mutable { write(batch); });
    }, order);
    finishWriting();
    for (auto* w : {tiff.get(), dxt.get(), residual.get()}) {
        if (w) {
            w->commit();
            report.bytes.push_back(std::filesystem::file_size(staged[report.bytes.size()]));
            report.sharedTiles.push_back(w->sharedTiles());
        }
    }
    report.sampling = levels.sampling();
    report.inputWidth = levels.inputWidth();
    report.inputHeight = levels.inputHeight();
    report.channels = channels;
    report.tileSize = T;
    report.maxLevel = levels.maxLevel();
    report.border = o.border;
    report.tiles = total;
    report.threads = threads;
    report.jpegErrorMeasured = o.measureJpegError;
    for (size_t l = 0; l < totals.size(); ++l) {
        const OrthoTileStats& s = totals[l].s;
        OrthoLevelReport r;
        r.level = static_cast<int>(l);
        r.tiles = totals[l].tiles;
        r.tiffMaxError = s.tiffMaxError;
        r.jpegTiles = s.jpegTiles;
        if (s.dxtSamples) {
            const double mse = s.dxtSquares / static_cast<double>(s.dxtSamples);
            r.dxtPsnr = mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
        }
        r.residualMaxError = s.residualMaxError;
        r.residualRmsError = s.residualSamples ? std::sqrt(s.residualSquares / static_cast<double>(s.residualSamples)) : 0.0;
        r.clampedResiduals = s.clamped;
        report.levels.push_back(r);
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace

OrthoReport encodeOrtho(const std::string& input, const std::string& directory, const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    checkOptions(o);
    const OrthoLevels levels(input, o.levels);
    StagingDirectory staging(directory);
    OrthoReport report = encodeLevels(levels, directory, staging, o, start);
    staging.commit(); // the outputs appear together, or none of them
    return report;
}

OrthoReport encodeOrtho(const OrthoLevels& levels, const std::string& directory, StagingDirectory& staging,
                        const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    checkOptions(o);
    return encodeLevels(levels, directory, staging, o, start);
}

nlohmann::json toJson(const OrthoReport& r) {
    nlohmann::json levels = nlohmann::json::array();
    for (const OrthoLevelReport& l : r.levels) {
        // Not measured: null, never a 0 that would read as lossless.
        const nlohmann::json tiffMaxError =
            l.jpegTiles > 0 && !r.jpegErrorMeasured ? nlohmann::json() : nlohmann::json(l.tiffMaxError);
        levels.push_back({{"level", l.level},
                          {"tiles", l.tiles},
                          {"jpeg_tiles", l.jpegTiles},
                          {"tiff_max_error", tiffMaxError},
                          {"dxt_psnr_db", l.dxtPsnr},
                          {"residual_max_error", l.residualMaxError},
                          {"residual_rms_error", l.residualRmsError},
                          {"clamped_residuals", l.clampedResiduals}});
    }
    return {{"input", {{"path", r.input}, {"width", r.inputWidth}, {"height", r.inputHeight}, {"channels", r.channels}}},
            {"directory", r.directory},
            {"outputs", r.outputs},
            {"bytes", r.bytes},
            {"shared_tiles", r.sharedTiles},
            {"sampling", r.sampling},
            {"tile_size", r.tileSize},
            {"max_level", r.maxLevel},
            {"border", r.border},
            {"tiles", r.tiles},
            {"levels", levels},
            {"threads", r.threads},
            {"seconds", r.seconds}};
}

} // namespace pyramid
