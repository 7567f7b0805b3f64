#include "libpyramid/gl/gl_normal_producer.hpp"

#include <cmath>

#include "formats/error.hpp"
#include "libpyramid/gl/gl_coarse_mesh.hpp"
#include "libpyramid/runtime/tile_cache.hpp"

namespace pyramid {

namespace {

constexpr int kLocalSize = 8;

// filters/terrain_normals.hpp, operation for operation: float32 on a plane, float64 on a sphere.
const char* const kNormalKernel = R"(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D tileZ;   // RGBA32F (zf, zc, zm, 0)
layout(binding = 1) uniform sampler2D parentZ; // the parent's (bound to tileZ at level 0)
layout(rgba32f, binding = 0) writeonly uniform image2D result;
uniform int n;
uniform bool sphere;
uniform bool hasParent;
// Plane: twice the spacing (float32), of the tile and of its parent.
uniform float twoSpacing;
uniform float parentTwoSpacing;
// Sphere: the radius; per tile and parent, (X0, Y0) and N as exact doubles, the spacing h; the
// tile's frame.
uniform double radius;
uniform dvec3 first;       // (X0, Y0, N)
uniform dvec3 parentFirst;
uniform double spacing;
uniform double parentSpacing;
uniform dvec3 ux;
uniform dvec3 uy;

float zAt(bool ofParent, ivec2 p) {
    return ofParent ? texelFetch(parentZ, p, 0).b : texelFetch(tileZ, p, 0).b;
}

vec2 planeNormal(bool ofParent, ivec2 p) {
    float two = ofParent ? parentTwoSpacing : twoSpacing;
    precise float dzx = zAt(ofParent, p + ivec2(1, 0)) - zAt(ofParent, p - ivec2(1, 0));
    precise float dzy = zAt(ofParent, p + ivec2(0, 1)) - zAt(ofParent, p - ivec2(0, 1));
    precise float gx = dzx / two;
    precise float gy = dzy / two;
    precise float l = sqrt((gx * gx + gy * gy) + 1.0);
    precise float nx = -gx / l;
    precise float ny = -gy / l;
    return vec2(nx, ny);
}

dvec3 spherePoint(bool ofParent, ivec2 p) {
    dvec3 f = ofParent ? parentFirst : first;
    double h = ofParent ? parentSpacing : spacing;
    double R = radius;
    precise double X = f.x + double(p.x);
    precise double Y = f.y + double(p.y);
    precise double dx = X > f.z ? X - f.z : (X < 0.0 ? X : 0.0);
    precise double dy = Y > f.z ? Y - f.z : (Y < 0.0 ? Y : 0.0);
    precise double qx = -R + X * h;
    precise double qy = -R + Y * h;
    precise double qz = R;
    if (dx != 0.0 && dy == 0.0) {
        if (dx > 0.0) {
            qx = R;
            qz = R - dx * h;
        } else {
            qx = -R;
            qz = R + dx * h;
        }
    } else if (dy != 0.0 && dx == 0.0) {
        if (dy > 0.0) {
            qy = R;
            qz = R - dy * h;
        } else {
            qy = -R;
            qz = R + dy * h;
        }
    }
    precise double len = sqrt((qx * qx + qy * qy) + qz * qz);
    precise double k = (R + double(zAt(ofParent, p))) / len;
    precise double px = qx * k;
    precise double py = qy * k;
    precise double pz = qz * k;
    return dvec3(px, py, pz);
}

dvec3 sphereNormal(bool ofParent, ivec2 p) {
    dvec3 e = spherePoint(ofParent, p + ivec2(1, 0));
    dvec3 w = spherePoint(ofParent, p - ivec2(1, 0));
    dvec3 nn = spherePoint(ofParent, p + ivec2(0, 1));
    dvec3 s = spherePoint(ofParent, p - ivec2(0, 1));
    precise double a0 = e.x - w.x;
    precise double a1 = e.y - w.y;
    precise double a2 = e.z - w.z;
    precise double b0 = nn.x - s.x;
    precise double b1 = nn.y - s.y;
    precise double b2 = nn.z - s.z;
    precise double c0 = a1 * b2 - a2 * b1;
    precise double c1 = a2 * b0 - a0 * b2;
    precise double c2 = a0 * b1 - a1 * b0;
    precise double l = sqrt((c0 * c0 + c1 * c1) + c2 * c2);
    precise double r0 = c0 / l;
    precise double r1 = c1 / l;
    precise double r2 = c2 / l;
    return dvec3(r0, r1, r2);
}

vec2 frameComponents(dvec3 v) {
    precise double x = (v.x * ux.x + v.y * ux.y) + v.z * ux.z;
    precise double y = (v.x * uy.x + v.y * uy.y) + v.z * uy.z;
    return vec2(float(x), float(y));
}

void main() {
    ivec2 uv = ivec2(gl_GlobalInvocationID.xy);
    if (uv.x > n || uv.y > n) {
        return;
    }
    ivec2 p = uv + ivec2(2, 2);
    vec2 normal = sphere ? frameComponents(sphereNormal(false, p)) : planeNormal(false, p);
    vec2 coarse = normal;
    if (hasParent) {
        CoarseAt a = coarseAt(uv.x, uv.y);
        ivec2 p10 = ivec2(a.p1.x, a.p0.y);
        ivec2 p01 = ivec2(a.p0.x, a.p1.y);
        if (sphere) {
            dvec3 n00 = sphereNormal(true, a.p0);
            dvec3 n10 = sphereNormal(true, p10);
            dvec3 n01 = sphereNormal(true, p01);
            dvec3 n11 = a.lower ? dvec3(0.0) : sphereNormal(true, a.p1);
            dvec3 mixed = dvec3(coarseMixD(a, n00.x, n10.x, n01.x, n11.x), coarseMixD(a, n00.y, n10.y, n01.y, n11.y),
                                coarseMixD(a, n00.z, n10.z, n01.z, n11.z));
            coarse = frameComponents(mixed);
        } else {
            vec2 n00 = planeNormal(true, a.p0);
            vec2 n10 = planeNormal(true, p10);
            vec2 n01 = planeNormal(true, p01);
            vec2 n11 = a.lower ? vec2(0.0) : planeNormal(true, a.p1);
            coarse = vec2(coarseMixF(a, n00.x, n10.x, n01.x, n11.x), coarseMixF(a, n00.y, n10.y, n01.y, n11.y));
        }
    }
    imageStore(result, uv, vec4(normal, coarse));
}
)";

std::string normalSource() { return std::string("#version 430 core\n") + coarseMeshGlsl() + kNormalKernel; }

void setGeometry(const GlProgram& program, const NormalGeometry& g, bool parent) {
    if (g.deformation == Deformation::Plane) {
        glUniform1f(program.uniform(parent ? "parentTwoSpacing" : "twoSpacing"), g.twoSpacing);
        return;
    }
    glUniform3d(program.uniform(parent ? "parentFirst" : "first"), static_cast<double>(g.firstX),
                static_cast<double>(g.firstY), static_cast<double>(g.faceVertices));
    glUniform1d(program.uniform(parent ? "parentSpacing" : "spacing"), g.spacing);
    if (!parent) {
        glUniform1d(program.uniform("radius"), g.radius);
        glUniform3d(program.uniform("ux"), g.ux[0], g.ux[1], g.ux[2]);
        glUniform3d(program.uniform("uy"), g.uy[0], g.uy[1], g.uy[2]);
    }
}

} // namespace

struct GlNormalProducer::Impl {
    std::shared_ptr<GlElevationProducer> elevations;
    NormalProducerOptions options;
    GlProgram program{"normal producer", normalSource()};
    TileCache<GlNormalTile> cache;

    Impl(std::shared_ptr<GlElevationProducer> e, const NormalProducerOptions& o)
        : elevations(std::move(e)), options(o), cache(o.cacheCapacity) {}
};

GlNormalProducer::GlNormalProducer(std::shared_ptr<GlElevationProducer> elevations,
                                   const NormalProducerOptions& options)
    : impl_(std::make_unique<Impl>(std::move(elevations), options)) {
    checkNormalOptions(options, impl_->elevations->path());
}

GlNormalProducer::~GlNormalProducer() = default;

int GlNormalProducer::tileSize() const { return impl_->elevations->tileSize(); }

std::shared_ptr<const GlNormalTile> GlNormalProducer::tile(int level, int tx, int ty) {
    if (auto hit = impl_->cache.find({level, tx, ty})) {
        return hit;
    }
    const int n = impl_->elevations->tileSize();
    const NormalProducerOptions& o = impl_->options;
    const auto heights = impl_->elevations->tile(level, tx, ty); // checks the coordinates
    std::shared_ptr<const GlElevationTile> parent;
    if (level > 0) {
        parent = impl_->elevations->tile(level - 1, tx / 2, ty / 2);
    }
    auto tile = std::make_shared<GlNormalTile>(GlNormalTile{level, tx, ty, n + 1, GlTexture(GL_RGBA32F, n + 1, n + 1)});
    const GlProgram& program = impl_->program;
    program.use();
    glUniform1i(program.uniform("n"), n);
    glUniform1i(program.uniform("sphere"), o.deformation == Deformation::Sphere ? 1 : 0);
    glUniform1i(program.uniform("hasParent"), parent ? 1 : 0);
    setGeometry(program, normalGeometry(o.deformation, o.size, n, level, tx, ty), false);
    if (parent) {
        setGeometry(program, normalGeometry(o.deformation, o.size, n, level - 1, tx / 2, ty / 2), true);
        setCoarseMeshUniforms(program, CoarseMesh(n, impl_->elevations->gridSize(), tx, ty), n, tx, ty);
    }
    heights->texture.bind(0);
    (parent ? parent->texture : heights->texture).bind(1);
    glBindImageTexture(0, tile->texture.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    program.dispatch(n + 1, n + 1, kLocalSize);
    return impl_->cache.insert({level, tx, ty}, std::move(tile));
}

NormalTile GlNormalProducer::read(const GlNormalTile& tile) {
    NormalTile out;
    out.level = tile.level;
    out.tx = tile.tx;
    out.ty = tile.ty;
    out.size = tile.size;
    out.normals.resize(static_cast<size_t>(tile.size) * static_cast<size_t>(tile.size) * 4);
    tile.texture.read(GL_RGBA, GL_FLOAT, out.normals.data());
    return out;
}

} // namespace pyramid
