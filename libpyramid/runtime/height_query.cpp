#include "libpyramid/runtime/height_query.hpp"

#include <utility>

#include "formats/error.hpp"
#include "formats/georeference_sidecar.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/runtime/level_heights.hpp"

namespace pyramid {

PointHeight heightAt(ElevationProducer& producer, double u, double v, int level) {
    if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0)) {
        fail("", "point (" + std::to_string(u) + ", " + std::to_string(v) + ") is outside the root quad [0, 1]^2");
    }
    if (level > producer.maxLevel()) {
        fail("", "no level " + std::to_string(level) + " (levels 0.." + std::to_string(producer.maxLevel()) + ")");
    }
    const int n = producer.tileSize();
    const auto at = [&](int l) {
        const int64_t tiles = int64_t{1} << l;
        const double intervals = static_cast<double>(tiles * n);
        PointHeight p;
        p.level = l;
        p.x = u * intervals;
        p.y = v * intervals;
        return std::make_pair(p, levelCell(n, tiles, p.x, p.y));
    };
    if (level < 0) {
        // The deepest level whose tile holding the point has residuals: where a sparse set has no
        // more resolution, the deepest file holding the point answers.
        level = producer.maxLevel();
        while (level > 0) {
            const LevelCell c = at(level).second;
            if (producer.hasResiduals(level, c.tx, c.ty)) {
                break;
            }
            --level;
        }
    }
    auto [p, cell] = at(level);
    p.tx = cell.tx;
    p.ty = cell.ty;
    p.height = cellHeight(producer.tile(level, p.tx, p.ty)->zf.data(), n, cell);
    return p;
}

PointHeight fileHeightAt(const std::string& file, double u, double v) {
    const ResidualHeader header = ResidualFileReader::readHeader(file);
    const FileLevelProducer finest = makeFileLevelProducer(file, header.maxLevel, 4);
    try {
        PointHeight p = heightAt(*finest.producer, u, v);
        p.level += finest.delta; // the file's level
        return p;
    } catch (const Error& e) {
        fail(file, e.what());
    }
}

std::array<double, 2> crsToRootQuad(const std::string& file, double x, double y, bool geographic) {
    const std::string sidecar = georeferenceSidecarPath(file);
    const SidecarPlacement p = readGeoreferenceSidecar(sidecar);
    if (geographic && !p.geographic) {
        fail(sidecar, "the input's CRS is projected: give the point in its units, not as longitude and latitude");
    }
    if (p.rotated) {
        fail(sidecar, "the input's pixels are rotated off north-up: give the point with --grid or --pixel");
    }
    if (geographic) {
        // Degrees east of Greenwich to the CRS's units from its prime meridian (grads, Paris...).
        x = (x - p.primeMeridian) / p.unitInDegrees;
        y = y / p.unitInDegrees;
    }
    const auto& e = p.rootExtent;
    return {(x - e[0]) / (e[2] - e[0]), (y - e[1]) / (e[3] - e[1])};
}

} // namespace pyramid
