#include "libpyramid/encode/aperture/aperture.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <vector>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/input/pyramid_georeference.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/encode/aperture/aperture_search.hpp"
#include "libpyramid/encode/aperture/planet_aperture.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/map_sources.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

void ApertureSearch::validate() const {
    if (directions < 4 || directions > 256) {
        failOption("directions", std::to_string(directions) + " is not 4 to 256 azimuths");
    }
    if (radius < 2 || radius > 1024 || radius % 2 != 0) {
        failOption("radius", std::to_string(radius) + " is not an even number of steps from 2 to 1024");
    }
    if (levels < 1 || levels > 16) {
        failOption("levels", std::to_string(levels) + " is not 1 to 16 levels");
    }
}

Aperture apertureOfHorizons(const double* horizons, int count) {
    const double sector = 2.0 * std::numbers::pi / count;
    double open = 0.0, bx = 0.0, by = 0.0, bz = 0.0;
    for (int k = 0; k < count; ++k) {
        const double h = horizons[k];
        const double azimuth = sector * k;
        open += sector * (1.0 - std::sin(h));
        const double horizontal = sector * ((std::numbers::pi / 2.0 - h) / 2.0 - std::sin(2.0 * h) / 4.0);
        bx += horizontal * std::cos(azimuth);
        by += horizontal * std::sin(azimuth);
        bz += sector * std::cos(h) * std::cos(h) / 2.0;
    }
    Aperture a;
    a.visible = open / (2.0 * std::numbers::pi);
    const double l = std::sqrt(bx * bx + by * by + bz * bz);
    if (l > 0.0) {
        a.direction = {bx / l, by / l, bz / l};
    }
    return a;
}

std::array<uint8_t, 3> encodeAperture(const Aperture& a) {
    const auto component = [](double v) { return static_cast<uint8_t>(std::lround(128.0 + 127.0 * std::clamp(v, -1.0, 1.0))); };
    return {static_cast<uint8_t>(std::lround(std::clamp(a.visible, 0.0, 1.0) * 255.0)), component(a.direction[0]),
            component(a.direction[1])};
}

namespace {

using aperture::HeightReader;
using aperture::Horizon;
using aperture::SearchStep;
using aperture::searchSteps;

// The finest level's aperture as the raster the ortho encoder reads: pixel (i, j), row 0 the
// north, centred at vertex coordinates (i + 0.5, W - j - 0.5) of producer level `finest`.
class AperturePixels final : public BytePixels {
public:
    AperturePixels(std::shared_ptr<ElevationProducer> producer, int finest, double spacing, const ApertureSearch& search)
        : producer_(std::move(producer)), finest_(finest), spacing_(spacing), search_(search) {
        for (const SearchStep& step : searchSteps(search, finest)) {
            steps_.push_back({step.level, step.distance, std::ldexp(1.0, step.level - finest_), step.distance * spacing_});
        }
        for (int k = 0; k < search.directions; ++k) {
            const double azimuth = 2.0 * std::numbers::pi * k / search.directions;
            cos_.push_back(std::cos(azimuth));
            sin_.push_back(std::sin(azimuth));
        }
        width_ = int64_t{producer_->tileSize()} << finest;
    }

    void readBytes(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out) const override {
        HeightReader heights(*producer_);
        std::vector<double> horizons(static_cast<size_t>(search_.directions));
        for (int j = y0; j < y1; ++j) {
            for (int i = x0; i < x1; ++i) {
                const double x = i + 0.5, y = static_cast<double>(width_ - j) - 0.5;
                const double z0 = heights.at(finest_, x, y);
                // Sector by sector, its steps outward: the reads of one sector follow each other
                // through the same rows of the same tiles.
                for (size_t d = 0; d < horizons.size(); ++d) {
                    Horizon h;
                    for (const Step& step : steps_) {
                        const double z = heights.at(step.level, (x + step.distance * cos_[d]) * step.shrink,
                                                    (y + step.distance * sin_[d]) * step.shrink);
                        h.step(z - z0, step.run);
                    }
                    horizons[d] = h.angle;
                }
                const std::array<uint8_t, 3> pixel = encodeAperture(apertureOfHorizons(horizons.data(), search_.directions));
                out = std::copy(pixel.begin() + c0, pixel.begin() + c1, out);
            }
        }
    }

private:
    struct Step {
        int level;
        // shrink: 2^(level - finest), exact, so that a product by it is the quotient by 2^(finest -
        // level); run: the ground distance
        double distance, shrink, run;
    };
    std::shared_ptr<ElevationProducer> producer_;
    int finest_;
    double spacing_;
    ApertureSearch search_;
    int64_t width_ = 0;
    std::vector<double> cos_, sin_;
    std::vector<Step> steps_;
};

} // namespace

ApertureReport encodeApertureFile(const std::string& dem, const std::string& output, const ApertureEncodeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    options.search.validate();
    if (options.size && !(*options.size > 0.0 && std::isfinite(*options.size))) {
        failOption("size", numberText(*options.size) + " is not a positive, finite ground size");
    }
    const std::filesystem::path out(output);
    if (out.extension() != ".dat" || out.stem().empty()) {
        fail(output, "an aperture pyramid is an ortho file: name it NAME.dat");
    }
    const PyramidSet set = openPyramidSet(dem);
    if (set.kind != PyramidKind::Residual) {
        fail(set.name(), "holds an ortho pyramid, not elevations");
    }
    const ResidualHeader h = ResidualFileReader::readHeader(set.main);
    double size = options.size.value_or(0.0);
    if (!options.size) {
        size = groundSpacing(set.main, 0)[0] * static_cast<double>(h.tileSize >> h.minLevel);
        if (!(size > 0.0)) {
            failOption("size", "the ground size of " + set.name() + " is unknown (no " +
                                   georeferenceSidecarPath(set.main) + "): give the root quad's side in height units");
        }
    }
    if (!std::isfinite(size)) {
        failOption("size", "must be a finite ground size");
    }
    const int finest = setMaxLevel(set) - h.minLevel;
    if (finest < 0) {
        fail(set.name(), "has no level of full tiles (maxLevel below minLevel)");
    }
    if (setCoverage({dem}, h.minLevel, finest)) {
        // A planar mosaic of several resolutions: its finest level over the whole plane would be
        // the inset's resolution everywhere.
        fail(set.name(), "holds its finest level " + std::to_string(h.minLevel + finest) +
                             " only in places (a sparse set of several resolutions): preprocessAperture needs every tile "
                             "of its finest level (build the aperture's DEM with one resolution)");
    }
    ElevationProducerOptions eo;
    eo.cacheCapacity = 256; // elevation tiles of (n + 5)^2 x 3 floats: about 120 MB at n = 192
    auto producer = openElevationSet(dem, eo);
    const int T = producer->tileSize();
    const double spacing = size / static_cast<double>(int64_t{T} << finest);
    RasterInfo info;
    info.width = info.height = static_cast<int>(int64_t{T} << finest);
    info.channels = 3;
    info.type = SampleType::UInt8;
    info.formatName = "aperture";
    const auto raster = RasterSource::fromPixels(
        set.name() + " (aperture)", info, std::make_shared<AperturePixels>(producer, finest, spacing, options.search));
    OrthoEncodeOptions o;
    o.name = out.stem().string();
    o.writeDxt = false;
    o.writeResiduals = false;
    o.levels.tileSize = T;
    o.levels.maxLevel = finest;
    o.levels.colourSpace = ColourSpace::Linear;
    o.levels.threads = options.threads;
    o.deflateLevel = options.deflateLevel;
    o.progress = options.progress;
    const std::string directory = out.parent_path().empty() ? "." : out.parent_path().string();
    const OrthoReport r = encodeOrtho(*raster, directory, o);
    ApertureReport report;
    report.input = dem;
    report.output = output;
    report.tileSize = T;
    report.maxLevel = finest;
    report.size = size;
    report.spacing = spacing;
    report.search = options.search;
    report.tiles = r.tiles;
    report.bytes = r.bytes.empty() ? 0 : r.bytes[0];
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

nlohmann::json toJson(const ApertureRun& r) {
    return {{"input", r.input},
            {"tile_size", r.tileSize},
            {"max_level", r.maxLevel},
            {"spacing", r.spacing},
            {"directions", r.search.directions},
            {"radius_steps", r.search.radius},
            {"levels", r.search.levels},
            {"tiles", r.tiles},
            {"bytes", r.bytes},
            {"seconds", r.seconds}};
}

nlohmann::json toJson(const ApertureReport& r) {
    nlohmann::json j = toJson(static_cast<const ApertureRun&>(r));
    j["output"] = r.output;
    j["size"] = r.size;
    return j;
}

SphericalApertureReport encodeSphericalApertureFiles(const std::string& directory, const std::string& output,
                                                     const SphericalApertureOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    options.search.validate();
    const PlanetBody body = PlanetBody::parse(options.body);
    const double radius = options.radius > 0.0 ? options.radius : body.equatorialRadius();
    if (!std::isfinite(radius)) {
        failOption("radius", "must be a finite radius");
    }
    // The faces may stop at different levels, and hold their deepest ones in places (sparse sets
    // of several resolutions): the aperture then has each face's levels where the face has them
    // (planet_aperture.hpp).
    std::vector<std::shared_ptr<ElevationProducer>> faces;
    std::vector<std::string> files;
    int finest = -1, tileSize = 0, minLevel = 0;
    for (int f = 1; f <= kCubeFaceCount; ++f) {
        const std::string file = faceFilePath(directory, options.name, f);
        const PyramidSet set = openPyramidSet(file);
        if (set.kind != PyramidKind::Residual) {
            fail(set.name(), "holds an ortho pyramid, not elevations");
        }
        const ResidualHeader h = ResidualFileReader::readHeader(set.main);
        if (f == 1) {
            tileSize = h.tileSize;
            minLevel = h.minLevel;
        } else if (h.tileSize != tileSize || h.minLevel != minLevel) {
            fail(set.name(), "does not have face 1's tile size and minLevel");
        }
        finest = std::max(finest, setMaxLevel(set) - h.minLevel);
        ElevationProducerOptions eo;
        eo.cacheCapacity = 64; // per face: about 30 MB at n = 192
        faces.push_back(openElevationSet(file, eo));
        files.push_back(file);
    }
    if (finest < 0) {
        fail(directory, "the faces have no level of full tiles (maxLevel below minLevel)");
    }
    auto map = std::make_unique<PlanetAperture>(faces, finest, radius, body, options.search,
                                                setCoverage(files, minLevel, finest));
    const double spacing = map->spacing();
    SphericalOrthoOptions so;
    so.ortho.name = options.output;
    so.ortho.writeDxt = false;
    so.ortho.writeResiduals = false;
    so.ortho.levels.tileSize = tileSize;
    so.ortho.levels.maxLevel = finest;
    so.ortho.levels.colourSpace = ColourSpace::Linear;
    so.ortho.levels.threads = options.threads;
    so.ortho.deflateLevel = options.deflateLevel;
    so.ortho.progress = options.progress;
    so.body = options.body;
    const int resolution = static_cast<int>(std::min<int64_t>(int64_t{4} * (int64_t{tileSize} << finest), 1 << 30));
    const SphericalOrthoReport r = encodeSphericalOrtho(
        globalMapSources(directory + " (aperture)", std::move(map), 3, resolution, SampleType::UInt8), output, so);
    SphericalApertureReport report;
    report.input = directory;
    report.directory = output;
    report.tileSize = tileSize;
    report.maxLevel = finest;
    report.radius = radius;
    report.spacing = spacing;
    report.search = options.search;
    for (const SphericalOrthoFaceReport& f : r.faces) {
        report.outputs.push_back(faceFilePath(output, options.output, f.face));
        report.tiles += f.ortho.tiles;
        report.bytes += f.ortho.bytes.empty() ? 0 : f.ortho.bytes[0];
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

nlohmann::json toJson(const SphericalApertureReport& r) {
    nlohmann::json j = toJson(static_cast<const ApertureRun&>(r));
    j["directory"] = r.directory;
    j["outputs"] = r.outputs;
    j["radius"] = r.radius;
    return j;
}

} // namespace pyramid
