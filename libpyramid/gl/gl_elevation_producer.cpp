#include "libpyramid/gl/gl_elevation_producer.hpp"

#include <optional>

#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "libpyramid/gl/gl_coarse_mesh.hpp"
#include "libpyramid/gl/gl_elevation_upsample.hpp"
#include "libpyramid/runtime/tile_cache.hpp"

namespace pyramid {

namespace {

constexpr int kLocalSize = 8;

// zf as in gl_elevation_upsample, and zc exactly as coarseElevations() in
// libpyramid/runtime/elevation_producer.cpp: the parent's render mesh (gl_coarse_mesh.hpp) evaluated at
// the interior samples, in the same float32 order.
const char* const kProducerKernel = R"(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 1) uniform sampler2D residual; // R32F, the whole residual tile
layout(rgba32f, binding = 0) writeonly uniform image2D result;
uniform ivec2 parentOffset;   // quadrant offsets (px, py)
uniform ivec2 residualOrigin; // the elevation tile's window in the residual tile
uniform bool hasResidual;
uniform int n;

float parentZm(ivec2 p) {
    return texelFetch(parentTile, p, 0).b;
}

void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= n + 5 || ij.y >= n + 5) {
        return;
    }
    precise float r = hasResidual ? texelFetch(residual, ij + residualOrigin, 0).r : 0.0;
    precise float zf = predictElevation(parentOffset, ij) + r;
    precise float zc = zf; // border samples are not rendered
    int u = ij.x - 2;
    int v = ij.y - 2;
    if (u >= 0 && v >= 0 && u <= n && v <= n) {
        CoarseAt a = coarseAt(u, v);
        float z11 = a.lower ? 0.0 : parentZm(a.p1);
        zc = coarseMixF(a, parentZm(a.p0), parentZm(ivec2(a.p1.x, a.p0.y)), parentZm(ivec2(a.p0.x, a.p1.y)), z11);
    }
    imageStore(result, ij, vec4(zf, zc, zf, 0.0));
}
)";

std::string producerSource() {
    return "#version 430 core\n#define PARENT_Z(x, y) texelFetch(parentTile, ivec2(x, y), 0).r\n"
           "layout(binding = 0) uniform sampler2D parentTile; // RGBA32F (zf, zc, zm, 0)\n" +
           elevationPredictionGlsl() + coarseMeshGlsl() + kProducerKernel;
}

} // namespace

struct GlElevationProducer::Impl {
    std::shared_ptr<const ResidualProducer> residuals;
    int n = 0;
    int k = 0; // residual tiles are 2^k elevation tiles wide
    int gridSize = 0;
    GlProgram program{"elevation producer", producerSource()};
    TileCache<GlElevationTile> cache;
    // The last residual tile uploaded: 4^k elevation tiles share each one.
    std::optional<TileKey> residualKey;
    std::optional<GlTexture> residualTexture;

    explicit Impl(size_t capacity) : cache(capacity) {}

    // The residual tile holding elevation tile (level, tx, ty), uploaded, or null without residuals
    // there (ResidualProducer::hasTile: beyond every file, or left out as an empty byte range).
    const GlTexture* residualTile(int level, int tx, int ty) {
        const TileKey key{level, tx >> k, ty >> k};
        if (!residuals->hasTile(key.level, key.tx, key.ty)) {
            return nullptr;
        }
        if (residualKey != key) {
            const int side = residuals->tileSize() + 5;
            const std::vector<float> r = residuals->tile(key.level, key.tx, key.ty);
            residualKey.reset();
            residualTexture.emplace(GL_R32F, side, side);
            residualTexture->upload(GL_RED, GL_FLOAT, r.data());
            residualKey = key;
        }
        return &*residualTexture;
    }

    std::shared_ptr<const GlElevationTile> produce(int level, int tx, int ty) {
        if (auto hit = cache.find({level, tx, ty})) {
            return hit;
        }
        const int side = n + 5;
        const int x0 = (tx & ((1 << k) - 1)) * n;
        const int y0 = (ty & ((1 << k) - 1)) * n;
        auto tile = std::make_shared<GlElevationTile>(GlElevationTile{level, tx, ty, side, GlTexture(GL_RGBA32F, side, side)});
        if (level == 0) {
            // The root is its residuals (no arithmetic): zf = zc = zm = r.
            std::vector<float> texels(static_cast<size_t>(side) * static_cast<size_t>(side) * 4, 0.0f);
            if (residuals->hasTile(0, 0, 0)) {
                const std::vector<float> r = residuals->tile(0, 0, 0);
                const size_t stride = static_cast<size_t>(residuals->tileSize()) + 5;
                for (size_t j = 0; j < static_cast<size_t>(side); ++j) {
                    for (size_t i = 0; i < static_cast<size_t>(side); ++i) {
                        const float z = r[i + static_cast<size_t>(x0) + (j + static_cast<size_t>(y0)) * stride];
                        float* t = &texels[4 * (i + j * static_cast<size_t>(side))];
                        t[0] = t[1] = t[2] = z;
                    }
                }
            }
            tile->texture.upload(GL_RGBA, GL_FLOAT, texels.data());
        } else {
            const std::shared_ptr<const GlElevationTile> parent = produce(level - 1, tx / 2, ty / 2);
            const GlTexture* residual = residualTile(level, tx, ty);
            program.use();
            glUniform2i(program.uniform("parentOffset"), quadrantOffset(tx, n), quadrantOffset(ty, n));
            glUniform2i(program.uniform("residualOrigin"), x0, y0);
            glUniform1i(program.uniform("hasResidual"), residual != nullptr ? 1 : 0);
            glUniform1i(program.uniform("n"), n);
            setCoarseMeshUniforms(program, CoarseMesh(n, gridSize, tx, ty), n, tx, ty);
            parent->texture.bind(0);
            // The sampler needs a float texture even when unused: bind the parent again.
            (residual != nullptr ? *residual : parent->texture).bind(1);
            glBindImageTexture(0, tile->texture.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
            program.dispatch(side, side, kLocalSize);
        }
        return cache.insert({level, tx, ty}, std::move(tile));
    }
};

GlElevationProducer::GlElevationProducer(std::shared_ptr<const ResidualProducer> residuals,
                                         const ElevationProducerOptions& options)
    : impl_(std::make_unique<Impl>(options.cacheCapacity)) {
    const ElevationTiling t = elevationTiling(*residuals, options);
    impl_->residuals = std::move(residuals);
    impl_->n = t.n;
    impl_->k = t.k;
    impl_->gridSize = t.gridSize;
}

GlElevationProducer::~GlElevationProducer() = default;

int GlElevationProducer::tileSize() const { return impl_->n; }
int GlElevationProducer::gridSize() const { return impl_->gridSize; }
int GlElevationProducer::maxLevel() const { return impl_->residuals->maxLevel(); }
const std::string& GlElevationProducer::path() const { return impl_->residuals->path(); }

std::shared_ptr<const GlElevationTile> GlElevationProducer::tile(int level, int tx, int ty) {
    if (!isQuadtreeTile(level, tx, ty)) {
        fail(impl_->residuals->path(), "no elevation tile " + tileCoordinates(level, tx, ty));
    }
    return impl_->produce(level, tx, ty);
}

GlElevationTexels GlElevationProducer::read(const GlElevationTile& tile) {
    const size_t count = static_cast<size_t>(tile.size) * static_cast<size_t>(tile.size);
    std::vector<float> texels(count * 4);
    tile.texture.read(GL_RGBA, GL_FLOAT, texels.data());
    GlElevationTexels out;
    out.level = tile.level;
    out.tx = tile.tx;
    out.ty = tile.ty;
    out.size = tile.size;
    out.zf.resize(count);
    out.zc.resize(count);
    out.zm.resize(count);
    for (size_t s = 0; s < count; ++s) {
        out.zf[s] = texels[4 * s];
        out.zc[s] = texels[4 * s + 1];
        out.zm[s] = texels[4 * s + 2];
    }
    return out;
}

} // namespace pyramid
