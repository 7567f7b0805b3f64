#include "libpyramid/verify/ortho_verify.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/encode/ortho/ortho_levels.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/input/input_list.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

struct TileResult {
    int level = 0;
    int maxError = 0;
    double squares = 0.0;
    int64_t samples = 0;
    bool lossy = false;
};

// The true tile as the file stores it: without border when the file has none, grey expanded
// to RGB for DXT files.
std::vector<uint8_t> expected(const TrueTile& t, const OrthoHeader& h, int sourceChannels) {
    const int b = h.border();
    const int side = h.tilePixels();
    const Image8& image = t.image();
    const int c = image.channels;
    const int outC = h.dxt() ? (c == 4 ? 4 : 3) : c;
    std::vector<uint8_t> out(static_cast<size_t>(side) * side * outC);
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            const uint8_t* p = image.at(x + 2 - b, y + 2 - b);
            uint8_t* q = &out[(static_cast<size_t>(y) * side + static_cast<size_t>(x)) * outC];
            for (int k = 0; k < outC; ++k) {
                q[k] = p[sourceChannels < 3 && outC == 3 ? 0 : k];
            }
        }
    }
    return out;
}

// A whole ortho pyramid: a file alone, or the region set it, its index or its directory names
// (tiles read from the deepest file holding them), and its header with the set's deepest level.
struct WholeOrtho {
    std::shared_ptr<const OrthoProducer> reader;
    OrthoHeader header;
    bool set = false; // a region set (which may be sparse), not a file alone
};

WholeOrtho wholeOrtho(const std::string& file) {
    WholeOrtho w;
    if (findRegionIndex(file).empty()) {
        if (OrthoFileReader::open(file)->header().rootLevel != 0) {
            fail(file, "a region file cannot be verified on its own against a whole-map source");
        }
        w.reader = std::make_shared<OrthoProducer>(file);
    } else {
        w.reader = openOrthoSet(file);
        w.set = true;
    }
    w.header = w.reader->header();
    w.header.maxLevel = w.reader->maxLevel();
    return w;
}

// The channels of the true tiles a pyramid of header `h` is compared with, from a source of
// `sourceChannels`: a DXT1 file says 3 whatever the source had (1 to 3, expanded to RGB).
int comparedChannels(const OrthoHeader& h, int sourceChannels, const std::string& source) {
    if (h.dxt() && h.channels == 3) {
        return std::min(3, sourceChannels);
    }
    if (sourceChannels < h.channels) {
        fail(source, std::to_string(sourceChannels) + (sourceChannels == 1 ? " channel" : " channels") +
                         ", the pyramid's tiles have " + std::to_string(h.channels));
    }
    return h.channels;
}

// Every tile of `whole` compared with the true tiles `levels` gives.
OrthoVerifyReport compareOrtho(const std::string& file, const std::string& source, const WholeOrtho& whole,
                               const OrthoLevels& levels, const OrthoVerifyOptions& options);

} // namespace

OrthoVerifyReport verifyOrtho(const std::string& file, const std::string& source, const OrthoVerifyOptions& options) {
    const WholeOrtho whole = wholeOrtho(file);
    const OrthoHeader& h = whole.header;
    OrthoLevelsOptions lo;
    lo.tileSize = h.tileSize;
    lo.maxLevel = h.maxLevel;
    lo.colourSpace = options.colourSpace;
    lo.stretch = options.stretch;
    lo.threads = options.threads;
    lo.target = options.target;
    // The source as the preprocessor read it: a file, or the files a VRT, directory or glob names.
    const std::vector<std::string> sources = expandInputs({source}).paths;
    lo.channels = comparedChannels(h, RasterSource::describe(sources[0]).channels, source);
    const OrthoLevels levels(sources, lo);
    return compareOrtho(file, source, whole, levels, options);
}

std::vector<OrthoVerifyReport> verifySphericalOrtho(const std::string& directory, const std::vector<std::string>& inputs,
                                                    const SphericalOrthoVerifyOptions& options) {
    checkFaceList(options.faces);
    const PlanetBody body = PlanetBody::parse(options.body);
    const auto faceFile = [&](int face) {
        return faceFilePath(directory, options.name, face);
    };
    std::vector<WholeOrtho> faces;
    for (const int face : options.faces) {
        faces.push_back(wholeOrtho(faceFile(face)));
    }
    const OrthoHeader& h = faces.front().header;
    // The build's deepest level: a sparse face's set goes only as deep as its data (a face the
    // map does not reach is its level 0 alone), so the faces' deepest.
    int maxLevel = 0;
    for (const WholeOrtho& f : faces) {
        maxLevel = std::max(maxLevel, f.header.maxLevel);
    }
    // The map as preprocessSphericalOrtho opened it, with the channels the faces hold.
    int channels = 0;
    const OrthoMap opened = openOrthoMap(inputs, options.extent, body, 256, [&](const RasterInfo& first) {
        channels = comparedChannels(h, first.channels, inputs[0]);
        return channels;
    });
    const MapSources& sources = opened.sources;
    const RasterSource& source = opened.source();
    const GeodeticMap* map = opened.map();
    std::vector<OrthoVerifyReport> reports;
    int64_t before = 0; // tiles of the faces already compared
    for (size_t k = 0; k < faces.size(); ++k) {
        const OrthoHeader& fh = faces[k].header;
        if (fh.tileSize != h.tileSize || (fh.maxLevel != maxLevel && !faces[k].set) || fh.channels != h.channels) {
            fail(faceFile(options.faces[k]), "its tiles are not those of " + faceFile(options.faces.front()) +
                                                 ": the faces are not of one build");
        }
        OrthoLevelsOptions lo;
        lo.tileSize = fh.tileSize;
        lo.maxLevel = maxLevel;
        faces[k].header.maxLevel = maxLevel;
        lo.colourSpace = options.colourSpace;
        lo.threads = options.threads;
        lo.channels = channels;
        const OrthoLevels levels(source, sources.placement, body, options.faces[k], lo, map);
        OrthoVerifyOptions o;
        o.colourResiduals = options.colourResiduals;
        o.threads = options.threads;
        const auto count = static_cast<int64_t>(faces.size());
        int64_t faceTiles = 0;
        if (options.progress) {
            o.progress = [&, count](int64_t done, int64_t total) {
                faceTiles = total;
                options.progress(before + done, total * count);
            };
        }
        reports.push_back(compareOrtho(faceFile(options.faces[k]), sources.name, faces[k], levels, o));
        before += faceTiles;
    }
    return reports;
}

namespace {

OrthoVerifyReport compareOrtho(const std::string& file, const std::string& source, const WholeOrtho& whole,
                               const OrthoLevels& levels, const OrthoVerifyOptions& options) {
    const std::shared_ptr<const OrthoProducer>& reader = whole.reader;
    const OrthoHeader& h = whole.header;
    std::shared_ptr<ColourProducer> residuals;
    if (options.colourResiduals) {
        residuals = std::make_shared<ColourProducer>(reader, 1024);
    }
    OrthoVerifyReport report;
    report.file = file;
    report.source = source;
    report.mode = options.colourResiduals ? "colour-residuals" : h.dxt() ? "dxt" : "tiles";
    const int threads = workerThreads(options.threads);
    int64_t total = 0; // every tile of levels 0..maxLevel
    for (int l = 0; l <= h.maxLevel; ++l) {
        total += int64_t{1} << (2 * l);
    }
    // The colour-residual producer is used by one thread at a time.
    std::mutex producer;
    const auto check = [&](const TrueTile& t) {
        TileResult r;
        r.level = t.level;
        if (t.beyond) {
            // Beyond the resolution of an input of several resolutions (ortho_levels.hpp): not a
            // tile of the pyramid. No file may store a picture there (a reader magnifies the
            // parent); colour residuals there are 128, which the producer rebuilds as it would.
            if (!residuals && reader->hasTile(t.level, t.tx, t.ty)) {
                fail(file, "tile (" + std::to_string(t.level) + "," + std::to_string(t.tx) + "," + std::to_string(t.ty) +
                               ") is stored, beyond the resolution the source has there");
            }
            r.level = -1;
            return r;
        }
        std::vector<uint8_t> got, want;
        // A tile no file holds (a sparse set's, doc/format.md 1.5) is no tile: it is right only
        // where the true tile is blank, so it is compared as a tile of 0s. Colour residuals are
        // rebuilt as the producer rebuilds them, residual 128 there.
        const bool held = reader->hasTile(t.level, t.tx, t.ty);
        if (residuals) {
            {
                std::lock_guard<std::mutex> lock(producer);
                got = *residuals->tile(t.level, t.tx, t.ty);
            }
            want.assign(t.image().pixels.begin(), t.image().pixels.end());
            r.lossy = held && describeTiff(reader->rawTile(t.level, t.tx, t.ty)).starts_with("jpeg");
        } else {
            want = expected(t, h, levels.channels());
            got = held ? reader->tile(t.level, t.tx, t.ty) : std::vector<uint8_t>(want.size(), 0);
            r.lossy = held && (h.dxt() || describeTiff(reader->rawTile(t.level, t.tx, t.ty)).starts_with("jpeg"));
        }
        if (got.size() != want.size()) {
            fail(file, "tile (" + std::to_string(t.level) + "," + std::to_string(t.tx) + "," + std::to_string(t.ty) +
                           ") does not match the source's channels");
        }
        for (size_t k = 0; k < got.size(); ++k) {
            const int e = std::abs(static_cast<int>(got[k]) - static_cast<int>(want[k]));
            r.maxError = std::max(r.maxError, e);
            r.squares += static_cast<double>(e) * e;
        }
        r.samples = static_cast<int64_t>(got.size());
        return r;
    };
    // Each item's results, summed up in the walk's order at the end (the same sums whatever
    // the thread count).
    std::map<int64_t, std::vector<TileResult>> byItem;
    int64_t checked = 0;
    std::mutex mutex;
    // A pruned walk's blank tile with nothing below counts the tiles below it as checked
    // (progress only): their true tiles are blank, as the tile's own.
    const auto covers = [&](const TrueTile& t) {
        return t.blankBelow ? ((int64_t{1} << (2 * (h.maxLevel - t.level + 1))) - 1) / 3 : int64_t{1};
    };
    const auto store = [&](int64_t index, std::vector<TileResult> results, int64_t tiles) {
        std::lock_guard<std::mutex> lock(mutex);
        checked += tiles;
        byItem.emplace(index, std::move(results));
        if (options.progress) {
            options.progress(checked, total);
        }
    };
    OrthoLevels::Sink sink;
    sink.level = [&](int64_t index, TileBatch& batch) {
        std::vector<TileResult> results(batch.size());
        parallelFor(static_cast<int64_t>(batch.size()), threads,
                    [&](int64_t i) { results[static_cast<size_t>(i)] = check(batch[static_cast<size_t>(i)]); });
        int64_t tiles = 0;
        for (const TrueTile& t : batch) {
            tiles += covers(t);
        }
        store(index, std::move(results), tiles);
        return true;
    };
    sink.subtree = [&](int64_t index, TileBatch& item) {
        std::vector<TileResult> results;
        results.reserve(item.size());
        int64_t tiles = 0;
        for (const TrueTile& t : item) {
            results.push_back(check(t));
            tiles += covers(t);
        }
        store(index, std::move(results), tiles);
        return true;
    };
    // A face's set (which may be sparse) is walked pruned: below a blank tile every true tile is
    // blank, and a sparse set holds none of them or blank ones. A file alone is compared whole.
    const bool pruned = whole.set && levels.isFace();
    levels.walk(sink, residuals ? OrthoLevels::WalkOrder::CoarseFirst : OrthoLevels::WalkOrder::SinglePass, nullptr,
                pruned);
    report.levels.resize(static_cast<size_t>(h.maxLevel) + 1);
    for (size_t l = 0; l < report.levels.size(); ++l) {
        report.levels[l].level = static_cast<int>(l);
    }
    std::vector<double> squares(report.levels.size(), 0.0);
    std::vector<int64_t> samples(report.levels.size(), 0);
    for (const auto& [index, results] : byItem) {
        for (const TileResult& r : results) {
            if (r.level < 0) {
                continue; // beyond the source's resolution: no tile
            }
            OrthoVerifyLevel& l = report.levels[static_cast<size_t>(r.level)];
            l.level = r.level;
            l.tiles += 1;
            l.maxError = std::max(l.maxError, r.maxError);
            l.lossyTiles += r.lossy;
            squares[static_cast<size_t>(r.level)] += r.squares;
            samples[static_cast<size_t>(r.level)] += r.samples;
            // Lossless tiles must match exactly; colour residuals are quantized in steps of 2.
            const int allowed = residuals ? 1 : 0;
            if (!r.lossy && r.maxError > allowed) {
                report.ok = false;
            }
        }
    }
    for (size_t l = 0; l < report.levels.size(); ++l) {
        const double mse = samples[l] ? squares[l] / static_cast<double>(samples[l]) : 0.0;
        report.levels[l].rmsError = std::sqrt(mse);
        report.levels[l].psnr = mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
    }
    return report;
}

} // namespace

nlohmann::json toJson(const OrthoVerifyReport& r) {
    nlohmann::json levels = nlohmann::json::array();
    for (const OrthoVerifyLevel& l : r.levels) {
        levels.push_back({{"level", l.level},
                          {"tiles", l.tiles},
                          {"max_error", l.maxError},
                          {"rms_error", l.rmsError},
                          {"psnr_db", l.psnr},
                          {"lossy_tiles", l.lossyTiles}});
    }
    return {{"file", r.file}, {"source", r.source}, {"mode", r.mode}, {"ok", r.ok}, {"levels", levels}};
}

} // namespace pyramid
