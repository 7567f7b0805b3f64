// The aperture of a planet (aperture.hpp, preprocessSphericalAperture) as the map the spherical
// ortho encoder samples: at points of the six faces' elevation producers, searched on a sphere.
// A planet whose faces have resolution only in places (sparse sets, several resolutions) is a map
// of several resolutions: a level's pixels are searched at that level's spacing, and the deeper
// levels only where a face's files hold them (ortho_levels.hpp, "Several resolutions").
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include "libpyramid/encode/aperture/aperture.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

// Where a planet's faces hold levels (relative to their minLevel): a face's main file holds levels
// 0..mainLast over the face, each region file its levels under its root tile.
struct FaceCoverage {
    struct Region {
        int first = 0, last = 0; // levels, inclusive; the root is tile (first, tx, ty)
        int64_t tx = 0, ty = 0;
    };
    int mainLast = 0;
    std::vector<Region> regions;
    bool holds(int level, int64_t tx, int64_t ty) const; // a file holds tile (level, tx, ty)
};

// The coverage of residual sets (the six faces DIR/NAME1..6.dat, or a plane's file or set), each of
// minLevel `minLevel`, or none when every one holds every level to `deepest` everywhere (one
// resolution).
std::optional<std::vector<FaceCoverage>> setCoverage(const std::vector<std::string>& faceFiles, int minLevel,
                                                        int deepest);

// The aperture at points of a planet whose heights are six faces' elevation producers, on a
// sphere of radius R: a point's observer stands at (R + z0) along its direction; the search walks
// great circles from it (s along the ground is the angle s / R), reading each point's height on
// the face that holds it (face_locate.hpp), at the point's level and the coarser ones as the
// planar search does. sample() searches at `finest`; sampleFor() at the level of the face grid
// asking (4 (tileSize << l) columns around: level l).
class PlanetAperture final : public GeodeticMap {
public:
    PlanetAperture(std::vector<std::shared_ptr<ElevationProducer>> faces, int finest, double radius,
                   const PlanetBody& body, const ApertureSearch& search,
                   std::optional<std::vector<FaceCoverage>> coverage = std::nullopt);

    int channels() const override { return 3; }
    const GeoExtent& extent() const override { return extent_; }
    double spacing() const { return spacing_; } // the finest level's mean sample distance

    void sample(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const override;
    void sampleFor(double columnsAround, const GeodeticPoint* points, size_t count, float* out,
                   uint8_t* valid) const override;
    bool severalResolutions() const override { return coverage_.has_value(); }
    // Level l (columnsAround 2 (tileSize << l), as FacePixels asks) is needed where a file of the
    // face holds its tiles: face by face (mayCoverFaceFinerThan); a geographic box says nothing.
    std::optional<bool> mayCoverFaceFinerThan(double columnsAround, int face, const FaceGrid& grid, int64_t x0,
                                              int64_t y0, int64_t x1, int64_t y1) const override;

private:
    // A step of the search: its level, the cosine and sine of its angle along the great circle,
    // and its level's vertex intervals across a face.
    struct Step {
        int level;
        double c, s, side;
    };
    void sampleLevel(int level, const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const;
    // The level of a grid `columnsAround` pixels around the equator of `perFace` pixels per tile
    // side per face at level 0.
    int levelOf(double columnsAround, double perFace) const;

    std::vector<std::shared_ptr<ElevationProducer>> faces_;
    int finest_;
    double radius_;
    PlanetBody body_;
    ApertureSearch search_;
    double spacing_ = 0.0;
    std::vector<std::vector<Step>> steps_; // by level 0..finest
    std::vector<double> cos_, sin_;
    std::optional<std::vector<FaceCoverage>> coverage_;
    GeoExtent extent_; // the globe
};

} // namespace pyramid
