#include "libpyramid/encode/ortho/ortho_encoder.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <utility>

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"
#include "formats/georeference_sidecar.hpp"
#include "formats/staging_directory.hpp"
#include "libpyramid/encode/ortho/ortho_build.hpp"

namespace pyramid {

// The checks that do not need the input, made before it is opened.
void OrthoEncodeOptions::validate() const {
    if (border != 0 && border != 2) {
        failOption("border", std::to_string(border) + " is not 0 or 2");
    }
    if (!writeTiff && !writeDxt && !writeResiduals) {
        failOption("outputs", "selects no output");
    }
    if (jpegQuality < 1 || jpegQuality > 100) {
        failOption("jpegQuality", std::to_string(jpegQuality) + " is not 1..100");
    }
    if (deflateLevel < 1 || deflateLevel > 12) {
        failOption("deflateLevel", std::to_string(deflateLevel) + " is not 1..12");
    }
    if (residualDeflateLevel < 0 || residualDeflateLevel > 12) {
        failOption("residualDeflateLevel", std::to_string(residualDeflateLevel) + " is not 0 (per tile) or 1..12");
    }
    if (dxtQuality < 0 || dxtQuality >= kDxtQualityLevels) {
        failOption("dxtQuality", std::to_string(dxtQuality) + " is not 0, 1, 2 or 3");
    }
    if (residualCompression != TilePolicy::Deflate && residualCompression != TilePolicy::Jpeg) {
        failOption("residualCompression", "must be deflate or jpeg");
    }
    if (name.empty() || name.find('/') != std::string::npos) {
        failOption("name", "'" + name + "' is not a plain file name");
    }
}

OrthoReport encodeOrtho(const std::string& input, const std::string& directory, const OrthoEncodeOptions& o) {
    return encodeOrtho(std::vector<std::string>{input}, directory, o);
}

namespace {

// A planar pyramid's outputs and its georeference sidecar, committed together (with o.share:
// the share's tiles, and the sidecar, into its part file).
OrthoReport encodePlanar(const OrthoLevels& levels, const std::string& directory, const OrthoEncodeOptions& o,
                         std::chrono::steady_clock::time_point start) {
    std::optional<PyramidGeoreference> georeference;
    std::vector<std::pair<std::string, std::string>> companions;
    if (const auto& g = levels.inputInfo().georeference; g && g->problem.empty() && !o.region) {
        // The finest level's pixels tile the root quad: the input's pixels, or its longer side's
        // square with the aspect kept (planar_pixels.hpp).
        const int w = levels.inputWidth(), h = levels.inputHeight(), longest = std::max(w, h);
        const std::array<double, 4> root{0.0, 0.0, static_cast<double>(o.levels.stretch ? w : longest),
                                         static_cast<double>(o.levels.stretch ? h : longest)};
        std::vector<int64_t> pixels;
        for (int l = 0; l <= levels.maxLevel(); ++l) {
            pixels.push_back(static_cast<int64_t>(levels.tileSize()) << l);
        }
        georeference = georeferencePyramid(*g, w, h, root, pixels, "pixel centres");
        companions.emplace_back(georeferenceSidecarPath(o.name + ".dat"),
                                georeferenceSidecarText(o.name + ".dat", *georeference));
    }
    std::unique_ptr<StagingDirectory> staging;
    if (!o.share) {
        staging = std::make_unique<StagingDirectory>(directory);
    }
    OrthoReport report = encodeOrthoLevels(levels, directory, staging.get(), o, companions, start);
    report.georeference = georeference;
    if (staging) {
        staging->commit(); // the outputs appear together, or none of them
    }
    return report;
}

} // namespace

OrthoReport encodeOrtho(const std::vector<std::string>& inputs, const std::string& directory, const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    o.validate();
    const OrthoLevels levels(inputs, o.levels);
    return encodePlanar(levels, directory, o, start);
}

OrthoReport encodeOrtho(const RasterSource& source, const std::string& directory, const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    o.validate();
    const OrthoLevels levels(source, o.levels);
    return encodePlanar(levels, directory, o, start);
}

OrthoReport encodeOrtho(const OrthoLevels& levels, const std::string& directory, StagingDirectory& staging,
                        const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    o.validate();
    return encodeOrthoLevels(levels, directory, o.share ? nullptr : &staging, o, {}, start);
}

OrthoReport encodeOrthoShare(const OrthoLevels& levels, const std::string& directory, const OrthoEncodeOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    o.validate();
    if (!o.share) {
        failOption("share", "encodeOrthoShare needs a share");
    }
    return encodeOrthoLevels(levels, directory, nullptr, o, {}, start);
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
    // The region sets' files, output after output, each main file first ([] without maxFileBytes).
    nlohmann::json files = nlohmann::json::array();
    for (const auto& set : r.files) {
        for (const auto& [name, bytes] : set) {
            files.push_back({{"file", name}, {"bytes", bytes}});
        }
    }
    return {{"input", {{"path", r.input}, {"width", r.inputWidth}, {"height", r.inputHeight}, {"channels", r.channels}}},
            {"directory", r.directory},
            {"outputs", r.outputs},
            {"bytes", r.bytes},
            {"files", files},
            {"shared_tiles", r.sharedTiles},
            {"sampling", r.sampling},
            {"tile_size", r.tileSize},
            {"max_level", r.maxLevel},
            {"region", r.region ? nlohmann::json::array({r.region->level, r.region->tx, r.region->ty}) : nlohmann::json()},
            {"border", r.border},
            {"tiles", r.tiles},
            {"levels", levels},
            {"georeference", r.georeference ? toJson(*r.georeference) : nlohmann::json()}, // null: not georeferenced
            {"threads", r.threads},
            {"seconds", r.seconds}};
}

} // namespace pyramid
