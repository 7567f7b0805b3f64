#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>

#include "formats/error.hpp"
#include "formats/staging_directory.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/sphere/map_sources.hpp"
#include "libpyramid/sphere/planet_body.hpp"
#include "libpyramid/input/raster_source.hpp"

namespace pyramid {

SphericalOrthoReport encodeSphericalOrtho(const std::string& input, const std::string& directory,
                                          const SphericalOrthoOptions& o) {
    return encodeSphericalOrtho(std::vector<std::string>{input}, directory, o);
}

namespace {

// Checks the options that do not need the input; throws OptionError.
void checkSphericalOrthoOptions(const SphericalOrthoOptions& o) {
    (void)PlanetBody::parse(o.body);
    checkFaceList(o.faces);
    if (o.extent) {
        o.extent->validate();
    }
    if (o.ortho.region && o.faces.size() != 1) {
        failOption("faces", "a region build encodes one face: give a single face, not " + std::to_string(o.faces.size()));
    }
    if (o.ortho.name.empty()) {
        failOption("name", "'' is not a plain file name"); // the face number alone would pass for one
    }
}

// Every face of `source` (sampled through `map` when not null), placed by `placement`.
SphericalOrthoReport encodeFaces(const RasterSource& source, const GeodeticMap* map, const std::string& input,
                                 const MapPlacement& placement, const std::vector<std::string>& inputs,
                                 const std::string& directory, const SphericalOrthoOptions& o,
                                 std::chrono::steady_clock::time_point start) {
    const PlanetBody body = PlanetBody::parse(o.body);
    // Every face set up before any is written: the input and the options are checked once, and a
    // bad one leaves no file behind.
    std::vector<std::unique_ptr<OrthoLevels>> faces;
    int64_t total = 0;
    for (const int f : o.faces) {
        faces.push_back(std::make_unique<OrthoLevels>(source, placement, body, f, o.ortho.levels, map));
        total += faces.back()->tileCount();
    }

    SphericalOrthoReport report;
    report.input = input;
    report.inputs = inputs;
    report.directory = directory;
    report.body = body.describe();
    report.extent = placement.extent;
    report.crs = placement.crs;
    report.threads = faces.front()->threads();
    // The faces appear together at the end, or none of them; a split build's share writes its part.
    std::optional<StagingDirectory> staging;
    if (!o.ortho.share) {
        staging.emplace(directory);
    }
    int64_t done = 0;
    for (size_t k = 0; k < faces.size(); ++k) {
        const OrthoLevels& levels = *faces[k];
        const int f = o.faces[k];
        OrthoEncodeOptions fo = o.ortho;
        fo.name = o.ortho.name + std::to_string(f);
        fo.pyramid = static_cast<int>(k);
        fo.pyramids = static_cast<int>(faces.size());
        if (o.ortho.progress) {
            fo.progress = [&o, before = done, total](int64_t tiles, int64_t faceTotal) {
                o.ortho.progress(before + tiles, o.ortho.region ? faceTotal : total); // a region: its one face's tiles
            };
        }
        SphericalOrthoFaceReport r;
        r.face = f;
        r.ortho = staging ? encodeOrtho(levels, directory, *staging, fo) : encodeOrthoShare(levels, directory, fo);
        for (int l = 0; l <= levels.maxLevel(); ++l) {
            const FaceGrid grid{static_cast<int64_t>(levels.tileSize()) << l, FaceGridKind::PixelCentres};
            r.gsd.push_back(faceGroundSampleDistance(body, f, grid));
        }
        done += levels.tileCount();
        report.faces.push_back(std::move(r));
    }
    if (staging) {
        staging->commit();
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace

OrthoMap openOrthoMap(const std::vector<std::string>& inputs, const std::optional<GeoExtent>& extent,
                      const PlanetBody& body, int cacheMegabytes,
                      const std::function<int(const RasterInfo&)>& channelsOf) {
    if (inputs.empty()) {
        fail("input", "no input files");
    }
    // The bands and sample type every file must have: the first file's.
    const RasterInfo first = RasterSource::describe(inputs[0]);
    OrthoMap m;
    m.sources = openMapSources(inputs, extent, body, cacheMegabytes, SampleRead::UInt16, 0, channelsOf(first),
                               [&](const RasterInfo& info, const std::string& name) -> std::optional<double> {
                                   if (info.channels != first.channels || info.type != first.type) {
                                       fail(name, std::to_string(info.channels) + " bands of " +
                                                      sampleTypeName(info.type) + ", not " +
                                                      std::to_string(first.channels) + " of " +
                                                      sampleTypeName(first.type) + " as " + inputs[0]);
                                   }
                                   return info.nodata; // colour_coverage.hpp's rule
                               });
    if (!m.sources.source) {
        m.described = RasterSource::open(inputs[0], cacheMegabytes);
    }
    return m;
}

SphericalOrthoReport encodeSphericalOrtho(const std::vector<std::string>& inputs, const std::string& directory,
                                          const SphericalOrthoOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    checkSphericalOrthoOptions(o);
    const PlanetBody body = PlanetBody::parse(o.body);
    // (A wrong channel count is refused by OrthoLevels, naming the option.)
    const OrthoMap map = openOrthoMap(inputs, o.extent, body, o.ortho.levels.cacheMegabytes, [&](const RasterInfo& first) {
        return std::min({std::max(1, o.ortho.levels.channels.value_or(4)), first.channels, 4});
    });
    const MapSources& sources = map.sources;
    sources.tell(o.warning);
    SphericalOrthoReport report =
        encodeFaces(map.source(), map.map(), sources.name, sources.placement, inputs, directory, o, start);
    report.warnings = sources.warnings;
    return report;
}

SphericalOrthoReport encodeSphericalOrtho(const MapSources& sources, const std::string& directory,
                                          const SphericalOrthoOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    checkSphericalOrthoOptions(o);
    if (!sources.source || !sources.map) {
        fail(sources.name, "a planet's map needs its description and its values");
    }
    return encodeFaces(*sources.source, sources.map.get(), sources.name, sources.placement, {sources.name}, directory,
                       o, start);
}

nlohmann::json toJson(const SphericalOrthoReport& r) {
    nlohmann::json faces = nlohmann::json::array();
    for (const SphericalOrthoFaceReport& f : r.faces) {
        nlohmann::json gsd = nlohmann::json::array();
        for (size_t l = 0; l < f.gsd.size(); ++l) {
            gsd.push_back({{"level", l}, {"min_metres", f.gsd[l].min}, {"max_metres", f.gsd[l].max}});
        }
        faces.push_back({{"face", f.face}, {"ortho", toJson(f.ortho)}, {"ground_sample_distance", gsd}});
    }
    return {{"input", r.input},
            {"inputs", r.inputs},
            {"directory", r.directory},
            {"body", r.body},
            {"crs", r.crs.empty() ? nlohmann::json() : nlohmann::json(r.crs)}, // null: not georeferenced
            {"extent", {{"west", r.extent.west}, {"south", r.extent.south}, {"east", r.extent.east},
                        {"north", r.extent.north}}},
            {"faces", faces},
            {"warnings", r.warnings},
            {"threads", r.threads},
            {"seconds", r.seconds}};
}

} // namespace pyramid
