// The parent's render mesh at a child vertex in GLSL: filters/coarse_mesh.hpp's rule, operation
// for operation, for the GL elevation producer's coarse elevations and the GL normal producer's
// coarse normals. The snippet declares the uniforms cellSamples, cells, invCell and meshOrigin,
// which setCoarseMeshUniforms sets from the CPU's CoarseMesh.
#pragma once
#include <string>

#include "libpyramid/filters/coarse_mesh.hpp"
#include "libpyramid/gl/gl_objects.hpp"

namespace pyramid {

// GLSL: struct CoarseAt { ivec2 p0; ivec2 p1; float fx; float fy; bool lower; };
//       CoarseAt coarseAt(int u, int v);
//       float coarseMixF(CoarseAt a, float z00, float z10, float z01, float z11);
//       double coarseMixD(CoarseAt a, double z00, double z10, double z01, double z11);
const std::string& coarseMeshGlsl();

// The snippet's uniforms for `mesh` (tile (tx, ty) of n intervals, gridSize), on the program in use.
void setCoarseMeshUniforms(const GlProgram& program, const CoarseMesh& mesh, int n, int tx, int ty);

} // namespace pyramid
