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
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/runtime/level_heights.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/face_locate.hpp"
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

// The steps of a sector's search, in order: the distance in finest-level samples (1..radius on
// the finest level, then radius/2 + 1 .. radius samples of each coarser one, twice as far
// apart), while levels remain.
struct SearchStep {
    int level = 0;
    double distance = 0.0;
};

std::vector<SearchStep> searchSteps(const ApertureSearch& search, int finest) {
    std::vector<SearchStep> steps;
    for (int q = 0; q < search.levels && finest - q >= 0; ++q) {
        const double scale = std::ldexp(1.0, q);
        for (int k = q == 0 ? 1 : search.radius / 2 + 1; k <= search.radius; ++k) {
            steps.push_back({finest - q, k * scale});
        }
    }
    return steps;
}

// A sector's horizon: the largest of 0 and atan2(rise, run) over its steps (run > 0), taken step
// by step, nearest first. A step whose rise is not positive cannot raise the horizon, nor one
// whose slope is clearly below the steepest so far (by a millionth, far beyond atan2's rounding
// while the slope is below a million): atan2 is computed only for the others, and the horizon is
// bit for bit the largest of every step's atan2.
struct Horizon {
    double angle = 0.0, steepest = 0.0;

    void step(double rise, double run) {
        if (!(run > 0.0)) {
            angle = std::max(angle, std::atan2(rise, run)); // beyond the slopes' rule: taken as it is
            return;
        }
        if (!(rise > 0.0)) {
            return;
        }
        const double ratio = rise / run;
        if (ratio < steepest * (1.0 - 1e-6) && steepest <= 1e6) {
            return;
        }
        angle = std::max(angle, std::atan2(rise, run));
        steepest = std::max(steepest, ratio);
    }
};

// The heights of an elevation producer's levels, read bilinearly between vertices, with the
// tiles last used kept at hand (one per reading thread: no lock for most samples).
class HeightReader {
public:
    explicit HeightReader(ElevationProducer& producer) : producer_(producer), n_(producer.tileSize()) {}

    // Level `level` at vertex coordinates (x, y) of 0..n 2^level (runtime/level_heights.hpp:
    // beyond the map the edge continues).
    double at(int level, double x, double y) {
        const LevelCell cell = levelCell(n_, int64_t{1} << level, x, y);
        return cellHeight(tile(level, cell.tx, cell.ty), n_, cell);
    }

private:
    // Most reads fall in the tile of the read before: that one is looked at first.
    const float* tile(int level, int tx, int ty) {
        const Kept& last = kept_[last_];
        if (last.tile && last.level == level && last.tx == tx && last.ty == ty) {
            return last.tile->zf.data();
        }
        for (size_t i = 0; i < kept_.size(); ++i) {
            const Kept& k = kept_[i];
            if (k.tile && k.level == level && k.tx == tx && k.ty == ty) {
                last_ = i;
                return k.tile->zf.data();
            }
        }
        last_ = next_++ % kept_.size();
        kept_[last_] = {level, tx, ty, producer_.tile(level, tx, ty)};
        return kept_[last_].tile->zf.data();
    }

    struct Kept {
        int level = 0, tx = 0, ty = 0;
        std::shared_ptr<const ElevationTile> tile;
    };
    ElevationProducer& producer_;
    int n_;
    std::array<Kept, 16> kept_{};
    size_t next_ = 0, last_ = 0;
};

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

// The aperture at points of a planet whose heights are six faces' elevation producers, on a
// sphere of radius R: a point's observer stands at (R + z0) along its direction; the search
// walks great circles from it (s along the ground is the angle s / R), reading each point's
// height on the face that holds it (face_locate.hpp), at the finest face level and the coarser
// ones as the planar search does.
class PlanetAperture final : public GeodeticMap {
public:
    PlanetAperture(std::vector<std::shared_ptr<ElevationProducer>> faces, int finest, double radius,
                   const PlanetBody& body, const ApertureSearch& search)
        : faces_(std::move(faces)), finest_(finest), radius_(radius), body_(body), search_(search) {
        vertices_ = static_cast<double>(int64_t{faces_[0]->tileSize()} << finest);
        // The mean ground distance between a face's samples: a quarter of a great circle over N.
        spacing_ = std::numbers::pi / 2.0 * radius / vertices_;
        for (const SearchStep& step : searchSteps(search, finest)) {
            const double angle = step.distance * spacing_ / radius_;
            steps_.push_back({step.level, std::cos(angle), std::sin(angle), std::ldexp(vertices_, step.level - finest_)});
        }
        finestSide_ = std::ldexp(vertices_, 0);
        for (int k = 0; k < search.directions; ++k) {
            const double azimuth = 2.0 * std::numbers::pi * k / search.directions;
            cos_.push_back(std::cos(azimuth));
            sin_.push_back(std::sin(azimuth));
        }
    }
    int channels() const override { return 3; }
    const GeoExtent& extent() const override { return extent_; }
    double spacing() const { return spacing_; }

    void sample(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const override {
        std::vector<HeightReader> readers;
        for (const auto& f : faces_) {
            readers.emplace_back(*f);
        }
        // At level `level`, `side` vertex intervals across a face.
        const auto heightAt = [&](const std::array<double, 3>& d, int level, double side) {
            const FacePoint p = facePointOf(d);
            return readers[static_cast<size_t>(p.face - 1)].at(level, (p.u + 1.0) / 2.0 * side, (p.v + 1.0) / 2.0 * side);
        };
        std::vector<Horizon> sectors(static_cast<size_t>(search_.directions));
        std::vector<double> horizons(sectors.size());
        std::vector<std::array<double, 3>> tangents(sectors.size());
        for (size_t n = 0; n < count; ++n) {
            const std::array<double, 3> d0 = unit(directionOf(body_, points[n]));
            const double r0 = radius_ + heightAt(d0, finest_, finestSide_);
            // The point's frame: east (z x up; at a pole, the x axis' choice), north = up x east.
            std::array<double, 3> east{-d0[1], d0[0], 0.0};
            if (std::hypot(east[0], east[1]) < 1e-12) {
                east = {0.0, 1.0, 0.0};
            }
            east = unit(east);
            const std::array<double, 3> north{d0[1] * east[2] - d0[2] * east[1], d0[2] * east[0] - d0[0] * east[2],
                                              d0[0] * east[1] - d0[1] * east[0]};
            for (size_t k = 0; k < tangents.size(); ++k) {
                tangents[k] = {cos_[k] * east[0] + sin_[k] * north[0], cos_[k] * east[1] + sin_[k] * north[1],
                               cos_[k] * east[2] + sin_[k] * north[2]};
            }
            // Step by step, every sector at each: the sectors' reads are independent, and the face
            // lookups and reads of one overlap the others'. Each sector still takes its steps
            // outward, in order, so its horizon is the one it has alone.
            std::fill(sectors.begin(), sectors.end(), Horizon{});
            for (const Step& step : steps_) {
                for (size_t k = 0; k < sectors.size(); ++k) {
                    const std::array<double, 3>& t = tangents[k];
                    const std::array<double, 3> d{step.c * d0[0] + step.s * t[0], step.c * d0[1] + step.s * t[1],
                                                  step.c * d0[2] + step.s * t[2]};
                    const double r = radius_ + heightAt(d, step.level, step.side);
                    sectors[k].step(r * step.c - r0, r * step.s);
                }
            }
            for (size_t k = 0; k < sectors.size(); ++k) {
                horizons[k] = sectors[k].angle;
            }
            const std::array<uint8_t, 3> pixel = encodeAperture(apertureOfHorizons(horizons.data(), search_.directions));
            for (size_t c = 0; c < 3; ++c) {
                out[n * 3 + c] = pixel[c];
            }
            valid[n] = 1;
        }
    }

private:
    static std::array<double, 3> unit(const std::array<double, 3>& v) {
        const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        return {v[0] / l, v[1] / l, v[2] / l};
    }

    // A step of the search: its level, the cosine and sine of its angle along the great circle,
    // and its level's vertex intervals across a face.
    struct Step {
        int level;
        double c, s, side;
    };
    std::vector<std::shared_ptr<ElevationProducer>> faces_;
    int finest_;
    double radius_;
    PlanetBody body_;
    ApertureSearch search_;
    double vertices_ = 0.0, spacing_ = 0.0, finestSide_ = 0.0;
    std::vector<double> cos_, sin_;
    std::vector<Step> steps_;
    GeoExtent extent_; // the globe
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
    std::vector<std::shared_ptr<ElevationProducer>> faces;
    int finest = -1, tileSize = 0;
    for (int f = 1; f <= kCubeFaceCount; ++f) {
        const std::string file = faceFilePath(directory, options.name, f);
        const PyramidSet set = openPyramidSet(file);
        if (set.kind != PyramidKind::Residual) {
            fail(set.name(), "holds an ortho pyramid, not elevations");
        }
        const ResidualHeader h = ResidualFileReader::readHeader(set.main);
        const int deepest = setMaxLevel(set) - h.minLevel;
        if (f == 1) {
            finest = deepest;
            tileSize = h.tileSize;
        } else if (deepest != finest || h.tileSize != tileSize) {
            fail(set.name(), "does not have face 1's tile size and levels");
        }
        ElevationProducerOptions eo;
        eo.cacheCapacity = 64; // per face: about 30 MB at n = 192
        faces.push_back(openElevationSet(file, eo));
    }
    if (finest < 0) {
        fail(directory, "the faces have no level of full tiles (maxLevel below minLevel)");
    }
    auto map = std::make_unique<PlanetAperture>(faces, finest, radius, body, options.search);
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
