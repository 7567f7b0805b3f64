#include "libpyramid/gl/gl_verify.hpp"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <functional>

#include "formats/dxt_codec.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/gl/egl_context.hpp"
#include "libpyramid/gl/gl_elevation_producer.hpp"
#include "libpyramid/gl/gl_ortho_producer.hpp"
#include "libpyramid/gl/gl_colour_producer.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"
#include "libpyramid/runtime/colour_producer.hpp"

namespace pyramid {

namespace {

// Tiles held while walking a pyramid depth first: an ancestor chain and its siblings.
constexpr size_t kCacheTiles = 64;

// Calls visit(level, tx, ty) for every tile of levels 0..last, depth first in Z order, so that
// each tile's ancestors were visited just before it (and are still cached).
void walk(int level, int tx, int ty, int last, const std::function<void(int, int, int)>& visit) {
    visit(level, tx, ty);
    if (level < last) {
        for (int q = 0; q < 4; ++q) {
            walk(level + 1, 2 * tx + (q & 1), 2 * ty + (q >> 1), last, visit);
        }
    }
}

int lastLevel(int fileMax, const GlVerifyOptions& options) {
    return options.maxLevel < 0 ? fileMax : std::min(fileMax, options.maxLevel);
}

void record(GlVerifyPart& part, double difference) {
    ++part.tiles;
    part.differingTiles += difference > 0.0 ? 1 : 0;
    part.maxDifference = std::max(part.maxDifference, difference);
}

double maxUlp(const std::vector<float>& a, const std::vector<float>& b) {
    uint64_t worst = a.size() == b.size() ? 0 : UINT32_MAX;
    for (size_t s = 0; s < std::min(a.size(), b.size()); ++s) {
        worst = std::max(worst, ulpDistance(a[s], b[s]));
    }
    return static_cast<double>(worst);
}

double maxAbs(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    int worst = a.size() == b.size() ? 0 : 255;
    for (size_t s = 0; s < std::min(a.size(), b.size()); ++s) {
        worst = std::max(worst, std::abs(static_cast<int>(a[s]) - static_cast<int>(b[s])));
    }
    return worst;
}

void verifyElevation(const std::string& path, const GlVerifyOptions& options, GlVerifyReport& report) {
    const ResidualHeader header = ResidualFileReader::open(path)->header();
    for (int k = 0; k <= header.minLevel; ++k) {
        const int n = header.tileSize >> k;
        if (n < 2 || n % 2 != 0 || (n << k) != header.tileSize) {
            break;
        }
        ResidualProducerOptions ro;
        ro.delta = elevationDelta(header, n);
        auto residuals = std::make_shared<const ResidualProducer>(path, std::vector<std::string>{}, ro);
        ElevationProducerOptions eo;
        eo.tileSize = n;
        eo.cacheCapacity = kCacheTiles;
        ElevationProducer cpu(residuals, eo);
        GlElevationProducer gl(residuals, eo);
        GlVerifyPart part{"elevation n=" + std::to_string(n) + " delta=" + std::to_string(ro.delta), "ulp"};
        walk(0, 0, 0, lastLevel(cpu.maxLevel(), options), [&](int level, int tx, int ty) {
            const auto c = cpu.tile(level, tx, ty);
            const GlElevationTexels g = GlElevationProducer::read(*gl.tile(level, tx, ty));
            record(part, std::max({maxUlp(c->zf, g.zf), maxUlp(c->zc, g.zc), maxUlp(c->zm(), g.zm)}));
        });
        report.parts.push_back(part);
    }
}

void verifyOrthoTiles(const std::shared_ptr<const OrthoProducer>& cpu, const GlVerifyOptions& options,
                      GlVerifyReport& report) {
    const OrthoHeader& h = cpu->header();
    GlOrthoProducer gl(cpu, kCacheTiles);
    GlVerifyPart bytes{"dxt blocks", "abs"};
    GlVerifyPart decoded{h.dxt() ? "dxt decoding" : "ortho tiles", "abs"};
    decoded.tolerance = h.dxt() ? kDxtDecodeTolerance : 0.0;
    walk(0, 0, 0, lastLevel(cpu->maxLevel(), options), [&](int level, int tx, int ty) {
        if (!cpu->hasTile(level, tx, ty)) {
            return;
        }
        const auto t = gl.tile(level, tx, ty);
        if (h.dxt()) {
            record(bytes, maxAbs(cpu->rawTile(level, tx, ty), GlOrthoProducer::readCompressed(*t)));
        }
        record(decoded, maxAbs(cpu->tile(level, tx, ty), gl.readPixels(*t)));
    });
    if (h.dxt()) {
        report.parts.push_back(bytes);
    }
    report.parts.push_back(decoded);
}

void verifyColourResiduals(const std::shared_ptr<const OrthoProducer>& residuals, const GlVerifyOptions& options,
                           GlVerifyReport& report) {
    ColourProducer cpu(residuals, kCacheTiles);
    GlColourProducer gl(residuals, kCacheTiles);
    GlVerifyPart part{"colour residuals", "abs"};
    walk(0, 0, 0, lastLevel(residuals->maxLevel(), options), [&](int level, int tx, int ty) {
        record(part, maxAbs(*cpu.tile(level, tx, ty), GlColourProducer::read(*gl.tile(level, tx, ty))));
    });
    report.parts.push_back(part);
}

} // namespace

uint64_t ulpDistance(float a, float b) {
    // Floats mapped to integers in the order of the values: -0 just below +0.
    auto ordered = [](float f) {
        const uint32_t u = std::bit_cast<uint32_t>(f);
        return (u & 0x80000000u) ? static_cast<int64_t>(0x7FFFFFFFu - (u & 0x7FFFFFFFu))
                                 : static_cast<int64_t>(u) + 0x80000000ll;
    };
    const int64_t d = ordered(a) - ordered(b);
    return static_cast<uint64_t>(d < 0 ? -d : d);
}

bool GlVerifyReport::ok() const {
    return !parts.empty() && std::all_of(parts.begin(), parts.end(), [](const GlVerifyPart& p) { return p.ok(); });
}

GlVerifyReport verifyOnGl(const std::string& path, const GlVerifyOptions& options) {
    const PyramidKind kind = detectPyramidKind(path);
    EglContext context;
    GlVerifyReport report;
    report.file = path;
    report.renderer = context.renderer();
    if (kind == PyramidKind::Residual) {
        verifyElevation(path, options, report);
    } else {
        const auto tiles = std::make_shared<const OrthoProducer>(path);
        verifyOrthoTiles(tiles, options, report);
        const OrthoHeader& h = tiles->header();
        if (!h.dxt() && h.border() == 2 && h.tileSize % 2 == 0) {
            verifyColourResiduals(tiles, options, report);
        }
    }
    return report;
}

nlohmann::json toJson(const GlVerifyReport& r) {
    nlohmann::json parts = nlohmann::json::array();
    for (const GlVerifyPart& p : r.parts) {
        parts.push_back({{"what", p.what},
                         {"unit", p.unit},
                         {"tiles", p.tiles},
                         {"differing_tiles", p.differingTiles},
                         {"max_difference", p.maxDifference},
                         {"tolerance", p.tolerance},
                         {"ok", p.ok()}});
    }
    return {{"file", r.file}, {"renderer", r.renderer}, {"ok", r.ok()}, {"parts", parts}};
}

} // namespace pyramid
