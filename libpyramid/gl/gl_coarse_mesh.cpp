#include "libpyramid/gl/gl_coarse_mesh.hpp"

namespace pyramid {

const std::string& coarseMeshGlsl() {
    static const std::string source = R"(
uniform int cellSamples; // c = 2n / gridSize child samples per parent mesh cell
uniform int cells;       // gridSize / 2 cells across the child
uniform float invCell;   // 1.0f / c, rounded on the CPU exactly as CoarseMesh does
uniform ivec2 meshOrigin; // (tx%2, ty%2) * n/2 + 2: the parent sample of the child's vertex (0, 0)

struct CoarseAt {
    ivec2 p0; // the parent sample of corner 00
    ivec2 p1; // of corner 11
    float fx;
    float fy;
    bool lower;
};

CoarseAt coarseAt(int u, int v) {
    CoarseAt a;
    int cx = min(u / cellSamples, cells - 1);
    int cy = min(v / cellSamples, cells - 1);
    precise float fx = float(u - cx * cellSamples) * invCell;
    precise float fy = float(v - cy * cellSamples) * invCell;
    a.fx = fx;
    a.fy = fy;
    a.p0 = ivec2(cx * cellSamples / 2, cy * cellSamples / 2) + meshOrigin;
    a.p1 = ivec2((cx + 1) * cellSamples / 2, (cy + 1) * cellSamples / 2) + meshOrigin;
    precise float s = fx + fy;
    a.lower = s <= 1.0;
    return a;
}

float coarseMixF(CoarseAt a, float z00, float z10, float z01, float z11) {
    precise float z;
    if (a.lower) {
        precise float w0 = 1.0 - a.fx - a.fy;
        z = (w0 * z00 + a.fx * z10) + a.fy * z01;
    } else {
        precise float w1 = a.fx + a.fy - 1.0;
        precise float wy = 1.0 - a.fy;
        precise float wx = 1.0 - a.fx;
        z = (w1 * z11 + wy * z10) + wx * z01;
    }
    return z;
}

double coarseMixD(CoarseAt a, double z00, double z10, double z01, double z11) {
    precise double z;
    if (a.lower) {
        precise float w0 = 1.0 - a.fx - a.fy;
        z = (double(w0) * z00 + double(a.fx) * z10) + double(a.fy) * z01;
    } else {
        precise float w1 = a.fx + a.fy - 1.0;
        precise float wy = 1.0 - a.fy;
        precise float wx = 1.0 - a.fx;
        z = (double(w1) * z11 + double(wy) * z10) + double(wx) * z01;
    }
    return z;
}
)";
    return source;
}

void setCoarseMeshUniforms(const GlProgram& program, const CoarseMesh& mesh, int n, int tx, int ty) {
    glUniform1i(program.uniform("cellSamples"), mesh.cellSamples());
    glUniform1i(program.uniform("cells"), mesh.cells());
    glUniform1f(program.uniform("invCell"), mesh.invCell());
    glUniform2i(program.uniform("meshOrigin"), (tx & 1) * (n / 2) + 2, (ty & 1) * (n / 2) + 2);
}

} // namespace pyramid
