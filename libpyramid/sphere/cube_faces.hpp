// The six faces a planet is split into, numbered and oriented as the original Proland
// spherical tools do (doc/spherical.md), and the exact integer geometry of their sample grids,
// including the tile borders that lie beyond a face's edges.
//
// Face f maps its plane coordinates (u, v) in [-1, 1]^2 to the cube point
//     face 1 ( u,  v,  1)   north pole          face 4 (-u,  1,  v)   longitude 90 E
//     face 2 ( u, -1,  v)   longitude 90 W      face 5 (-1, -u,  v)   longitude 180
//     face 3 ( 1,  u,  v)   longitude 0         face 6 ( u, -v, -1)   south pole
// in geocentric axes: +z north, +x towards longitude 0, +y towards longitude 90 E. Seen from
// outside, u grows to the right and v upwards on every face (u x v is the outward normal), and
// on the four equatorial faces u points east and v north.
//
// A face grid has n cells per side. Its samples sit on the cell vertices (DEM: x in 0..n,
// u = 2x/n - 1) or on the pixel centres (ortho: x in 0..n-1, u = (2x+1)/n - 1). Tile borders
// reach beyond the face: a border sample at distance d beyond an edge IS the neighbouring
// face's sample at distance d inside that edge, at the same position along the edge (the cube
// is unfolded across the edge). So the border samples of every face are exactly the samples of
// its neighbours, quarter-turn rotations included, at every level of a pyramid whose grids are
// nested. The only samples with no neighbour are those beyond two edges at once (beyond a cube
// corner, where three faces meet): they take the direction of the extended face plane point
// (u, v, 1) with |u|, |v| > 1, which continues the face smoothly; no sample is snapped.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pyramid {

inline constexpr int kCubeFaceCount = 6;

// A list of faces to build (an option of the spherical encoders): at least one, each 1..6,
// none twice. Throws OptionError("faces", ...) otherwise.
void checkFaceList(const std::vector<int>& faces);

// The file of face `face` (1..6) of a planet's pyramids named `name`: "NAMEi.dat" (DEM1.dat ..
// DEM6.dat; proland-compat, "Spherical (cube) variants"), and the same in `directory`.
std::string faceFileName(const std::string& name, int face);
std::string faceFilePath(const std::string& directory, const std::string& name, int face);

enum class FaceGridKind {
    Vertices,     // DEM samples: n + 1 per side
    PixelCentres, // ortho pixels: n per side
};

struct FaceGrid {
    int64_t n = 0; // cells per face side
    FaceGridKind kind = FaceGridKind::Vertices;
};

// A point of a face's plane in exact integer units of half a cell: the cube is [-n, n]^3, so
// the face plane coordinate u corresponds to u * n. Samples of any face that denote the same
// 3-D point have the same CubePoint, which is what makes their values identical.
struct CubePoint {
    int64_t x = 0, y = 0, z = 0;
    friend bool operator==(const CubePoint&, const CubePoint&) = default;
};

// A sample of face `face` (1..6) at column x, row y of a face grid (row 0 at the bottom, v = -1).
struct FaceSample {
    int face = 1;
    int64_t x = 0, y = 0;
    friend bool operator==(const FaceSample&, const FaceSample&) = default;
};

// The unnormalised direction of face plane coordinates (u, v) by the table above.
std::array<double, 3> faceDirection(int face, double u, double v);

// The cube point of a sample, borders folded onto the neighbouring face. Border samples must
// lie within n half-cells of the face (|x|, |y| up to about n/2 beyond an edge).
CubePoint cubePoint(const FaceGrid& grid, const FaceSample& sample);

// The inverse on one face: the grid sample of `face` at cube point p (which must lie on that
// face's plane). Used to name the neighbour's sample that a border sample is.
FaceSample faceSampleAt(const FaceGrid& grid, int face, const CubePoint& p);

// The face holding a sample's cube point as an ordinary (non-border) sample: the sample itself
// inside the face, the neighbour's sample for a border sample beyond one edge. A sample beyond
// two edges has no such face and is returned as is.
FaceSample canonicalSample(const FaceGrid& grid, const FaceSample& sample);

// The geocentric direction (not normalised) of a cube point.
inline std::array<double, 3> direction(const CubePoint& p) {
    return {static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z)};
}

} // namespace pyramid
