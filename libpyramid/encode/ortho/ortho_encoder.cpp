#include "libpyramid/encode/ortho/ortho_encoder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <span>
#include <tuple>

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"
#include "formats/staging_directory.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/filters/colour_upsample.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {


// Colour residual tiles: Deflate without predictor (residuals hover around 128, they are not
// smooth), at libdeflate's level 4. Measured on the synthetic 8192^2 image and the 5400 x 2700
// Blue Marble (residual file only): level 6 gives 5 % fewer bytes in 1.9 and 1.25 times the
// time, level 1 8 to 9 % more bytes for 35 % less time on the synthetic image and none on the
// Blue Marble.
constexpr int kResidualDeflateLevel = 4;

// The encoded uniform tiles kept for reuse (Encoder::encode): a few hundred KB each.
constexpr size_t kUniformTilesKept = 64;

struct TileStats {
    int tiffMaxError = 0;
    int64_t jpegTiles = 0;
    double dxtSquares = 0.0;
    int64_t dxtSamples = 0;
    int residualMaxError = 0;
    double residualSquares = 0.0;
    int64_t residualSamples = 0;
    int64_t clamped = 0;
};

struct EncodedTile {
    int level = 0, tx = 0, ty = 0;
    std::vector<uint8_t> tiff, dxt, residual;
    std::vector<uint8_t> recon; // colour-residual reconstruction, for the children
    TileStats stats;
};

TiffCompression tiffCompression(TilePolicy p, bool edge, int channels) {
    switch (p) {
    case TilePolicy::Deflate:
        return TiffCompression::Deflate;
    case TilePolicy::Lzw:
        return TiffCompression::Lzw;
    case TilePolicy::Jpeg:
        return TiffCompression::Jpeg;
    case TilePolicy::JpegYCbCr:
        return TiffCompression::JpegYCbCr;
    case TilePolicy::None:
        return TiffCompression::None;
    case TilePolicy::Original:
        // JPEG inside, Deflate on the pyramid's outer edge; JPEG cannot hold 2 or 4 channels.
        return edge || channels == 2 || channels == 4 ? TiffCompression::Deflate : TiffCompression::Jpeg;
    }
    return TiffCompression::Deflate;
}

// The tile without its border when the output has none (empty with the border: the tile's own
// pixels are used, not a copy).
std::vector<uint8_t> crop(const Image8& tile, int border) {
    if (border == 2) {
        return {};
    }
    const int side = tile.width - 4;
    std::vector<uint8_t> out(static_cast<size_t>(side) * side * tile.channels);
    const size_t row = static_cast<size_t>(side) * tile.channels;
    for (int y = 0; y < side; ++y) {
        std::copy_n(tile.at(2, y + 2), row, &out[static_cast<size_t>(y) * row]);
    }
    return out;
}

// Grey and grey+alpha expanded to RGB as the DXT codec does (RGB and RGBA are compared as they are).
std::vector<uint8_t> expandForDxt(std::span<const uint8_t> pixels, int channels) {
    const size_t n = pixels.size() / static_cast<size_t>(channels);
    std::vector<uint8_t> rgb(n * 3);
    for (size_t k = 0; k < n; ++k) {
        rgb[3 * k] = rgb[3 * k + 1] = rgb[3 * k + 2] = pixels[k * static_cast<size_t>(channels)];
    }
    return rgb;
}

class Encoder {
public:
    Encoder(const OrthoLevels& levels, const OrthoEncodeOptions& o) : o_(o) {
        channels_ = levels.channels();
        tileSize_ = levels.tileSize();
    }

    EncodedTile encode(const TrueTile& t, const std::vector<uint8_t>* parentRecon) const {
        // Tiles of one colour under a parent of that colour (the black beyond a non-square
        // input, sea, snow) encode to the same bytes wherever they are: encoded once per colour
        // and compression, then copied. At most kUniformTilesKept colours are kept (memory
        // stays bounded on a map of many flat colours; later ones are encoded as any tile).
        std::optional<UniformKey> key = uniformKey(t, parentRecon);
        if (key) {
            {
                const std::lock_guard<std::mutex> lock(uniformMutex_);
                const auto it = uniform_.find(*key);
                if (it != uniform_.end()) {
                    return placed(it->second, t);
                }
            }
            EncodedTile e = encodeNew(t, parentRecon);
            const std::lock_guard<std::mutex> lock(uniformMutex_);
            if (uniform_.size() < kUniformTilesKept) {
                uniform_.emplace(*key, e);
            }
            return e;
        }
        return encodeNew(t, parentRecon);
    }

private:
    // A uniform tile's colour (its 1 to 4 channels packed) and TIFF compression (which may
    // depend on the tile's place).
    using UniformKey = std::tuple<uint32_t, TiffCompression>;

    std::optional<UniformKey> uniformKey(const TrueTile& t, const std::vector<uint8_t>* parentRecon) const {
        if (t.level == 0) {
            return std::nullopt; // the root's residual tile holds the colours themselves
        }
        const std::vector<uint8_t>& p = t.pixels.pixels;
        const auto c = static_cast<size_t>(channels_);
        // Every pixel is the first one when every byte equals the one a pixel earlier (one
        // memcmp, which stops at the first difference).
        const auto uniform = [c](const std::vector<uint8_t>& v) {
            return v.size() >= c && std::memcmp(v.data(), v.data() + c, v.size() - c) == 0;
        };
        const auto sameColourAsTile = [&](const std::vector<uint8_t>* parent) {
            return parent != nullptr && uniform(*parent) && std::memcmp(parent->data(), p.data(), c) == 0;
        };
        if (!uniform(p) || (o_.writeResiduals && !sameColourAsTile(parentRecon))) {
            return std::nullopt;
        }
        uint32_t colour = 0;
        for (size_t k = 0; k < c; ++k) {
            colour |= static_cast<uint32_t>(p[k]) << (8 * k);
        }
        return UniformKey{colour, tiffCompressionOf(t)};
    }

    static EncodedTile placed(const EncodedTile& shared, const TrueTile& t) {
        EncodedTile e = shared;
        e.level = t.level;
        e.tx = t.tx;
        e.ty = t.ty;
        return e;
    }

    TiffCompression tiffCompressionOf(const TrueTile& t) const {
        const int last = (1 << t.level) - 1;
        const bool edge = t.tx == 0 || t.ty == 0 || t.tx == last || t.ty == last;
        return tiffCompression(o_.compression, edge, channels_);
    }

    EncodedTile encodeNew(const TrueTile& t, const std::vector<uint8_t>* parentRecon) const {
        EncodedTile e;
        e.level = t.level;
        e.tx = t.tx;
        e.ty = t.ty;
        const int outSide = tileSize_ + 2 * o_.border;
        const std::vector<uint8_t> cropped = crop(t.pixels, o_.border);
        const std::span<const uint8_t> plain = o_.border == 2 ? std::span<const uint8_t>(t.pixels.pixels)
                                                              : std::span<const uint8_t>(cropped);
        if (o_.writeTiff) {
            const TiffCompression c = tiffCompressionOf(t);
            // Deflate with the horizontal predictor, which readers undo inside libtiff.
            e.tiff = encodeTiff8(plain, outSide, outSide, channels_, c, o_.jpegQuality, o_.deflateLevel, true);
            e.stats.jpegTiles += isJpeg(c);
            if (isJpeg(c) && o_.measureJpegError) {
                const std::vector<uint8_t> back = decodeOrthoTiff(e.tiff, outSide, channels_, "JPEG tile");
                // A local maximum (not the member, which the byte loads might alias) vectorises.
                int maxError = 0;
                for (size_t k = 0; k < back.size(); ++k) {
                    const int d = static_cast<int>(back[k]) - static_cast<int>(plain[k]);
                    maxError = std::max(maxError, d < 0 ? -d : d);
                }
                e.stats.tiffMaxError = maxError;
            }
        }
        if (o_.writeDxt) {
            const DxtFormat format = channels_ == 4 ? DxtFormat::Dxt5 : DxtFormat::Dxt1;
            e.dxt = encodeDxt(plain, outSide, outSide, channels_, format, o_.dxtQuality);
            const std::vector<uint8_t> back = decodeDxt(e.dxt, outSide, outSide, format, "DXT tile");
            const std::vector<uint8_t> expanded = channels_ < 3 ? expandForDxt(plain, channels_) : std::vector<uint8_t>{};
            const std::span<const uint8_t> ref = channels_ < 3 ? std::span<const uint8_t>(expanded) : plain;
            for (size_t k = 0; k < back.size(); ++k) {
                const double d = static_cast<double>(back[k]) - static_cast<double>(ref[k]);
                e.stats.dxtSquares += d * d;
            }
            e.stats.dxtSamples += static_cast<int64_t>(back.size());
        }
        if (o_.writeResiduals) {
            encodeResidual(t, parentRecon, e);
        }
        return e;
    }

    // Closed loop: the stored residuals are decoded exactly as a reader will decode them, and
    // the tile is rebuilt from them, before its children are predicted from it.
    void encodeResidual(const TrueTile& t, const std::vector<uint8_t>* parent, EncodedTile& e) const {
        const int side = tileSize_ + 4;
        const std::vector<uint8_t>& truth = t.pixels.pixels;
        std::vector<uint8_t> stored(truth.size());
        std::vector<uint8_t> predicted(truth.size());
        if (t.level == 0) {
            stored = truth;
        } else {
            const size_t rowBytes = static_cast<size_t>(side) * channels_;
            const int rx = (t.tx & 1) * (tileSize_ / 2);
            const int ry = (t.ty & 1) * (tileSize_ / 2);
            for (int y = 0; y < side; ++y) {
                predictOrthoRow(parent->data(), rowBytes, channels_, rx, ry, y, side,
                                &predicted[static_cast<size_t>(y) * rowBytes]);
            }
            int64_t clampedCount = 0;
            for (size_t k = 0; k < truth.size(); ++k) {
                bool clamped = false;
                stored[k] = encodeColourResidual(truth[k], predicted[k], &clamped);
                clampedCount += clamped;
            }
            e.stats.clamped += clampedCount;
        }
        const bool jpeg = o_.residualCompression == TilePolicy::Jpeg;
        e.residual = encodeTiff8(stored, side, side, channels_, jpeg ? TiffCompression::Jpeg : TiffCompression::Deflate,
                                 o_.jpegQuality, kResidualDeflateLevel);
        const std::vector<uint8_t> decoded = jpeg ? decodeOrthoTiff(e.residual, side, channels_, "JPEG residual tile") : stored;
        if (t.level == 0) {
            e.recon = decoded;
        } else {
            e.recon.resize(truth.size());
            for (size_t k = 0; k < truth.size(); ++k) {
                e.recon[k] = applyColourResidual(predicted[k], decoded[k]);
            }
        }
        // Integers summed exactly (a tile's squares stay far below 2^53): the same total as
        // adding them one by one in double precision, in a loop that vectorises.
        int maxError = 0;
        int64_t squares = 0;
        for (size_t k = 0; k < truth.size(); ++k) {
            const int err = std::abs(static_cast<int>(e.recon[k]) - static_cast<int>(truth[k]));
            maxError = std::max(maxError, err);
            squares += err * err;
        }
        e.stats.residualMaxError = std::max(e.stats.residualMaxError, maxError);
        e.stats.residualSquares += static_cast<double>(squares);
        e.stats.residualSamples += static_cast<int64_t>(truth.size());
    }

    const OrthoEncodeOptions& o_;
    int channels_ = 0, tileSize_ = 0;
    mutable std::mutex uniformMutex_;
    mutable std::map<UniformKey, EncodedTile> uniform_;
};

struct LevelTotals {
    int64_t tiles = 0;
    TileStats s;
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

    const Encoder encoder(levels, o);
    const int threads = levels.threads();
    std::vector<LevelTotals> totals(static_cast<size_t>(levels.maxLevel()) + 1);
    std::map<std::tuple<int, int, int>, std::vector<uint8_t>> shallowRecon; // levels 0..C
    const int64_t total = levels.tileCount();
    int64_t done = 0;
    auto parentOf = [](const TrueTile& t) { return std::make_tuple(t.level - 1, t.tx / 2, t.ty / 2); };

    // Writes one group's tiles in the walk's order and adds up their statistics.
    auto write = [&](std::vector<std::vector<EncodedTile>>& results) {
        for (auto& item : results) {
            for (EncodedTile& e : item) {
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
        std::vector<std::vector<EncodedTile>> results(group.size());
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
            for (const EncodedTile& e : results[0]) {
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
        const TileStats& s = totals[l].s;
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
