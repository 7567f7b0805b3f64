// The values of a planet's map at the samples of one cube face: the bridge between a face grid
// (cube_faces.hpp), the body's geodesy (planet_body.hpp) and an equirectangular raster
// (equirect_sampler.hpp). Shared by the spherical DEM and ortho preprocessors.
//
// A face sample (x, y), borders included, is folded onto its cube point (so a border sample and
// the neighbour face's sample at the same point get the same integer point, hence bit-identical
// values), turned into a geocentric direction, mapped by the body to a geodetic latitude and
// longitude, and the map is sampled there (bilinear, pixel centres; doc/spherical.md).
#pragma once
#include <cstdint>
#include <vector>

#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

class FaceSampler {
public:
    // `scale` multiplies every sampled value (e.g. 10000/255 for heights stored as 8-bit red).
    FaceSampler(const GeodeticMap& map, const PlanetBody& body, int face, FaceGrid grid, double scale = 1.0);

    int face() const { return face_; }
    const FaceGrid& grid() const { return grid_; }
    int channels() const { return map_.channels(); }

    // The geodetic point of face sample (x, y), which may lie in a border beyond the face.
    GeodeticPoint geodeticOf(int64_t x, int64_t y) const;

    // Samples columns x0 + i * stride (0 <= i < nx) of rows y0 + j * stride (0 <= j < ny), row
    // j = 0 first (south first, as tiles are stored). out: nx * ny * channels() values,
    // interleaved; valid: nx * ny flags (1 = a value, 0 = outside the map's extent or nodata).
    // Thread-safe; reads the map block of points by block, so memory stays bounded.
    void sample(int64_t x0, int64_t y0, int64_t stride, int64_t nx, int64_t ny, float* out, uint8_t* valid) const;

    // False only when no sample of the rectangle [x0, x1] x [y0, y1] (face samples, borders
    // included, corners inclusive) can have a value: the rectangle lies wholly outside the map's
    // geographic extent. The latitudes and longitudes of 64 points per side of its outline are
    // taken, with a margin of twice the largest step between neighbours (the outline bounds the
    // rectangle's image unless a pole lies inside, which the outline's winding shows: then all
    // longitudes and the latitudes up to that pole). Conservative: true says nothing. A global
    // map: true.
    bool mayHaveValues(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const;
    // The same for the map's members more than `columnsAround` pixels around the equator fine
    // (GeodeticMap::mayCoverFinerThan): 0 asks for every member.
    bool mayHaveValuesFinerThan(double columnsAround, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const;
    bool severalResolutions() const { return map_.severalResolutions(); } // GeodeticMap::severalResolutions

private:
    const GeodeticMap& map_;
    const PlanetBody& body_;
    int face_;
    FaceGrid grid_;
    double scale_;
};

// A geographic box: latitudes [south, north], longitudes [west, east] unwrapped (west may be
// below -180, east above 180), or every longitude.
struct GeoBox {
    double south = -90.0, north = 90.0, west = -180.0, east = 180.0;
    bool allLongitudes = false;
};

// A box holding the geodetic points of face samples [x0, x1] x [y0, y1] of `grid` on `face`
// (borders beyond the face allowed): the latitudes and longitudes of 64 points per side of the
// outline, widened by twice the largest step between neighbours (the outline bounds the
// rectangle's image unless a pole lies inside, which the outline's winding shows: then every
// longitude and the latitudes up to that pole). Conservative. FaceSampler::mayHaveValues' box.
GeoBox faceGeographicBox(const PlanetBody& body, int face, FaceGrid grid, int64_t x0, int64_t y0, int64_t x1,
                         int64_t y1);

// The ground distance between neighbouring samples of a face grid, in metres: the smallest and
// largest over the face (the cube projection packs samples closer near the face corners than at
// the centre), measured as geodesics on the body between horizontal and vertical neighbours of
// a regular 33 x 33 subset of the face's samples.
struct GroundSampleDistance {
    double min = 0.0;
    double max = 0.0;
};
GroundSampleDistance faceGroundSampleDistance(const PlanetBody& body, int face, const FaceGrid& grid);

} // namespace pyramid
