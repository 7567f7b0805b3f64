#include "libpyramid/encode/aperture/planet_aperture.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <cmath>
#include <numbers>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/aperture/aperture_search.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/face_locate.hpp"

namespace pyramid {

namespace {

std::array<double, 3> unit(const std::array<double, 3>& v) {
    const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return {v[0] / l, v[1] / l, v[2] / l};
}

} // namespace

bool FaceCoverage::holds(int level, int64_t tx, int64_t ty) const {
    if (level <= mainLast) {
        return true;
    }
    return std::any_of(regions.begin(), regions.end(), [&](const Region& r) {
        return r.first <= level && level <= r.last && (tx >> (level - r.first)) == r.tx && (ty >> (level - r.first)) == r.ty;
    });
}

std::optional<std::vector<FaceCoverage>> setCoverage(const std::vector<std::string>& faceFiles, int minLevel,
                                                        int deepest) {
    std::vector<FaceCoverage> coverage;
    bool uniform = true;
    for (const std::string& file : faceFiles) {
        const PyramidSet set = openPyramidSet(file);
        FaceCoverage& c = coverage.emplace_back();
        c.mainLast = ResidualFileReader::readHeader(set.main).maxLevel - minLevel;
        // The share of the face the files hold at the deepest level (one file holds a tile at most).
        double held = c.mainLast == deepest ? 1.0 : 0.0;
        for (size_t k = 0; k < set.regions.size(); ++k) {
            const RegionRoot& r = set.roots[k];
            const int first = r.level - minLevel;
            const int last = first + ResidualFileReader::readHeader(set.regions[k]).maxLevel;
            c.regions.push_back({first, last, r.tx, r.ty});
            if (first <= deepest && deepest <= last) {
                held += std::ldexp(1.0, -2 * first);
            }
        }
        uniform = uniform && held == 1.0;
    }
    if (uniform) {
        return std::nullopt;
    }
    return coverage;
}

PlanetAperture::PlanetAperture(std::vector<std::shared_ptr<ElevationProducer>> faces, int finest, double radius,
                               const PlanetBody& body, const ApertureSearch& search,
                               std::optional<std::vector<FaceCoverage>> coverage)
    : faces_(std::move(faces)), finest_(finest), radius_(radius), body_(body), search_(search),
      coverage_(std::move(coverage)) {
    const int T = faces_[0]->tileSize();
    // The mean ground distance between a face's samples: a quarter of a great circle over N.
    spacing_ = std::numbers::pi / 2.0 * radius / static_cast<double>(int64_t{T} << finest);
    for (int l = 0; l <= finest; ++l) {
        const auto vertices = static_cast<double>(int64_t{T} << l);
        const double spacing = std::numbers::pi / 2.0 * radius / vertices;
        std::vector<Step>& steps = steps_.emplace_back();
        for (const aperture::SearchStep& step : aperture::searchSteps(search, l)) {
            const double angle = step.distance * spacing / radius_;
            steps.push_back({step.level, std::cos(angle), std::sin(angle), std::ldexp(vertices, step.level - l)});
        }
    }
    for (int k = 0; k < search.directions; ++k) {
        const double azimuth = 2.0 * std::numbers::pi * k / search.directions;
        cos_.push_back(std::cos(azimuth));
        sin_.push_back(std::sin(azimuth));
    }
}

int PlanetAperture::levelOf(double columnsAround, double perFace) const {
    const double l = std::log2(columnsAround / (perFace * static_cast<double>(faces_[0]->tileSize())));
    const auto level = static_cast<int>(std::lround(l));
    if (std::fabs(l - level) > 1e-9 || level < 0 || level > finest_) {
        throw std::logic_error("PlanetAperture: no level of " + std::to_string(columnsAround) + " columns around");
    }
    return level;
}

void PlanetAperture::sample(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const {
    sampleLevel(finest_, points, count, out, valid);
}

void PlanetAperture::sampleFor(double columnsAround, const GeodeticPoint* points, size_t count, float* out,
                               uint8_t* valid) const {
    sampleLevel(levelOf(columnsAround, 4.0), points, count, out, valid);
}

std::optional<bool> PlanetAperture::mayCoverFaceFinerThan(double columnsAround, int face, const FaceGrid& grid,
                                                          int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    if (!coverage_) {
        return true;
    }
    const int level = levelOf(columnsAround, 2.0);
    const int64_t T = faces_[0]->tileSize(), last = (int64_t{1} << level) - 1;
    if (grid.n != T << level) {
        throw std::logic_error("PlanetAperture: a grid of " + std::to_string(grid.n) + " pixels at level " +
                               std::to_string(level));
    }
    const FaceCoverage& c = (*coverage_)[static_cast<size_t>(face - 1)];
    for (int64_t ty = std::max<int64_t>(0, y0 / T); ty <= std::min(last, y1 / T); ++ty) {
        for (int64_t tx = std::max<int64_t>(0, x0 / T); tx <= std::min(last, x1 / T); ++tx) {
            if (c.holds(level, tx, ty)) {
                return true;
            }
        }
    }
    return false;
}

void PlanetAperture::sampleLevel(int level, const GeodeticPoint* points, size_t count, float* out,
                                 uint8_t* valid) const {
    std::vector<aperture::HeightReader> readers;
    for (const auto& f : faces_) {
        readers.emplace_back(*f);
    }
    // At level `l`, `side` vertex intervals across a face.
    const auto heightAt = [&](const std::array<double, 3>& d, int l, double side) {
        const FacePoint p = facePointOf(d);
        return readers[static_cast<size_t>(p.face - 1)].at(l, (p.u + 1.0) / 2.0 * side, (p.v + 1.0) / 2.0 * side);
    };
    const double side0 = static_cast<double>(int64_t{faces_[0]->tileSize()} << level);
    const std::vector<Step>& steps = steps_[static_cast<size_t>(level)];
    std::vector<aperture::Horizon> sectors(static_cast<size_t>(search_.directions));
    std::vector<double> horizons(sectors.size());
    std::vector<std::array<double, 3>> tangents(sectors.size());
    for (size_t n = 0; n < count; ++n) {
        const std::array<double, 3> d0 = unit(directionOf(body_, points[n]));
        const double r0 = radius_ + heightAt(d0, level, side0);
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
        std::fill(sectors.begin(), sectors.end(), aperture::Horizon{});
        for (const Step& step : steps) {
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

} // namespace pyramid
