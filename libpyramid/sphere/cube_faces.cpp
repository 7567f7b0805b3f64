#include "libpyramid/sphere/cube_faces.hpp"

#include <algorithm>
#include <filesystem>
#include <cstdlib>
#include <string>

#include "formats/error.hpp"

namespace pyramid {

std::string faceFileName(const std::string& name, int face) { return name + std::to_string(face) + ".dat"; }

std::string faceFilePath(const std::string& directory, const std::string& name, int face) {
    return (std::filesystem::path(directory) / faceFileName(name, face)).string();
}

void checkFaceList(const std::vector<int>& faces) {
    if (faces.empty()) {
        failOption("faces", "selects no face");
    }
    for (auto f = faces.begin(); f != faces.end(); ++f) {
        if (*f < 1 || *f > kCubeFaceCount) {
            failOption("faces", std::to_string(*f) + " is not a face number (1..6)");
        }
        if (std::find(faces.begin(), f, *f) != f) {
            failOption("faces", "face " + std::to_string(*f) + " is named twice");
        }
    }
}

namespace {

// A signed coordinate axis: axis 0, 1, 2 = x, y, z.
struct SignedAxis {
    int axis;
    int sign;
};

// Each face as cube point = U * u + V * v + n * normal (the table of cube_faces.hpp).
struct FaceFrame {
    SignedAxis u, v, normal;
};

constexpr FaceFrame kFrames[kCubeFaceCount] = {
    {{0, +1}, {1, +1}, {2, +1}}, // 1: ( u,  v,  1)
    {{0, +1}, {2, +1}, {1, -1}}, // 2: ( u, -1,  v)
    {{1, +1}, {2, +1}, {0, +1}}, // 3: ( 1,  u,  v)
    {{0, -1}, {2, +1}, {1, +1}}, // 4: (-u,  1,  v)
    {{1, -1}, {2, +1}, {0, -1}}, // 5: (-1, -u,  v)
    {{0, +1}, {1, -1}, {2, -1}}, // 6: ( u, -v, -1)
};

const FaceFrame& frameOf(int face) {
    if (face < 1 || face > kCubeFaceCount) {
        fail("cube face", std::to_string(face) + " is not a face number (1..6)");
    }
    return kFrames[face - 1];
}

int64_t& component(CubePoint& p, int axis) {
    return axis == 0 ? p.x : axis == 1 ? p.y : p.z;
}

int64_t component(const CubePoint& p, const SignedAxis& a) {
    const int64_t c = a.axis == 0 ? p.x : a.axis == 1 ? p.y : p.z;
    return a.sign * c;
}

// Grid column -> plane coordinate in half cells (u * n), and back.
int64_t planeCoordinate(const FaceGrid& g, int64_t x) {
    return (g.kind == FaceGridKind::Vertices ? 2 * x : 2 * x + 1) - g.n;
}

int64_t gridCoordinate(const FaceGrid& g, int64_t planeU) {
    const int64_t twice = planeU + g.n - (g.kind == FaceGridKind::Vertices ? 0 : 1);
    if (twice % 2 != 0) {
        fail("cube face", "cube point is not a sample of this grid");
    }
    return twice / 2;
}

} // namespace

std::array<double, 3> faceDirection(int face, double u, double v) {
    const FaceFrame& f = frameOf(face);
    std::array<double, 3> d{};
    d[static_cast<size_t>(f.u.axis)] += f.u.sign * u;
    d[static_cast<size_t>(f.v.axis)] += f.v.sign * v;
    d[static_cast<size_t>(f.normal.axis)] += f.normal.sign * 1.0;
    return d;
}

CubePoint cubePoint(const FaceGrid& grid, const FaceSample& s) {
    const FaceFrame& f = frameOf(s.face);
    const int64_t n = grid.n;
    int64_t U = planeCoordinate(grid, s.x);
    int64_t V = planeCoordinate(grid, s.y);
    int64_t N = n;
    const bool beyondU = std::llabs(U) > n;
    const bool beyondV = std::llabs(V) > n;
    if (beyondU != beyondV) {
        // Unfold across the edge: the distance d beyond it becomes the distance inside the
        // neighbour face, measured from the shared edge along the neighbour's plane.
        int64_t& overflowing = beyondU ? U : V;
        const int64_t d = std::llabs(overflowing) - n;
        if (d > n) {
            fail("cube face", "border sample too far beyond the face edge");
        }
        overflowing = overflowing > 0 ? n : -n;
        N = n - d;
    }
    CubePoint p;
    component(p, f.u.axis) = f.u.sign * U;
    component(p, f.v.axis) = f.v.sign * V;
    component(p, f.normal.axis) = f.normal.sign * N;
    return p;
}

FaceSample faceSampleAt(const FaceGrid& grid, int face, const CubePoint& p) {
    const FaceFrame& f = frameOf(face);
    if (component(p, f.normal) != grid.n) {
        fail("cube face", "cube point is not on face " + std::to_string(face));
    }
    return FaceSample{face, gridCoordinate(grid, component(p, f.u)), gridCoordinate(grid, component(p, f.v))};
}

FaceSample canonicalSample(const FaceGrid& grid, const FaceSample& s) {
    const int64_t n = grid.n;
    const int64_t U = planeCoordinate(grid, s.x);
    const int64_t V = planeCoordinate(grid, s.y);
    const bool beyondU = std::llabs(U) > n;
    const bool beyondV = std::llabs(V) > n;
    if (beyondU == beyondV) {
        return s; // on the face, or beyond a corner
    }
    // The neighbour across the crossed edge: its outward normal is the overflowing axis.
    const SignedAxis& crossed = beyondU ? kFrames[s.face - 1].u : kFrames[s.face - 1].v;
    const int outward = crossed.sign * ((beyondU ? U : V) > 0 ? 1 : -1);
    const CubePoint p = cubePoint(grid, s);
    for (int g = 1; g <= kCubeFaceCount; ++g) {
        const SignedAxis& normal = kFrames[g - 1].normal;
        if (normal.axis == crossed.axis && normal.sign == outward) {
            return faceSampleAt(grid, g, p);
        }
    }
    fail("cube face", "border sample has no neighbour face"); // unreachable for a valid fold
}

} // namespace pyramid
