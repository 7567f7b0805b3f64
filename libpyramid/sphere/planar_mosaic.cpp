#include "libpyramid/sphere/planar_mosaic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "formats/error.hpp"
#include "libpyramid/input/raster_mosaic.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/sphere/planar_mosaic_pixels.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

// The ground size of the finest pixels of a group: the shorter of a pixel's two sides at the
// group's centre, in metres (a geographic pixel's east-west side shrinks with the latitude's cosine).
double groundSide(const Georeference& g, int width, int height, const GeoreferencedMap& map) {
    const auto& t = g.pixelToCrs;
    const double across = std::hypot(t[1], t[4]), down = std::hypot(t[2], t[5]);
    if (g.projected) {
        return std::min(across, down) * g.unitInMetres;
    }
    const double metresPerUnit = g.unitInDegrees * g.semiMajorAxis * std::numbers::pi / 180.0;
    const double latitude = map.geodeticOf(width / 2.0, height / 2.0).latitude;
    return std::min(across * std::cos(latitude * std::numbers::pi / 180.0), down) * metresPerUnit;
}

} // namespace

std::array<double, 4> PlanarTarget::parseExtent(const std::string& text) {
    const std::array<double, 4> v =
        parseOptionNumbers4(text, "extent", "MINX,MINY,MAXX,MAXY in the CRS's units", "a coordinate in the CRS's units");
    if (!(v[0] < v[2]) || !(v[1] < v[3])) {
        failOption("extent", "needs MINX < MAXX and MINY < MAXY, not " + text);
    }
    return v;
}

std::unique_ptr<RasterSource> openPlanarMosaic(const std::vector<std::string>& inputs, int cacheMegabytes,
                                               bool sameSamples, const PlanarTarget& target) {
    if (inputs.size() <= 1 && target.empty()) {
        return openNorthUp(inputs, cacheMegabytes);
    }
    if (target.extent) {
        const auto& e = *target.extent;
        if (!std::all_of(e.begin(), e.end(), [](double v) { return std::isfinite(v); }) || !(e[0] < e[2]) ||
            !(e[1] < e[3])) {
            throw OptionError("extent", "must be MINX,MINY,MAXX,MAXY with MINX < MAXX and MINY < MAXY");
        }
    }
    const std::vector<std::vector<std::string>> groups = groupByGrid(inputs);
    if (sameSamples && groups.size() > 1) {
        const RasterInfo first = RasterSource::describe(groups[0][0]);
        for (size_t k = 1; k < groups.size(); ++k) {
            const RasterInfo info = RasterSource::describe(groups[k][0]);
            if (info.channels != first.channels || info.type != first.type) {
                fail(groups[k][0], std::to_string(info.channels) + " bands of " + sampleTypeName(info.type) + ", not " +
                                       std::to_string(first.channels) + " of " + sampleTypeName(first.type) + " as " +
                                       groups[0][0]);
            }
        }
    }
    if (groups.size() == 1 && target.empty()) {
        return openNorthUp(groups[0], cacheMegabytes);
    }
    // Every group described, the finest of all, and the CRS and finest group on it.
    std::vector<std::unique_ptr<RasterSource>> described;
    std::vector<GeoreferencedMap> maps;
    size_t finest = 0;
    for (size_t k = 0; k < groups.size(); ++k) {
        described.push_back(openNorthUp(groups[k], 1));
        const RasterInfo& info = described.back()->info();
        maps.emplace_back(*info.georeference, info.width, info.height, described.back()->path());
        if (maps[k].metresPerPixel() < maps[finest].metresPerPixel() * (1.0 - 1e-9)) {
            finest = k;
        }
    }
    const Georeference crs = target.crs.empty() ? *described[0]->info().georeference : georeferenceOfCrs(target.crs);
    std::optional<size_t> onGrid; // the finest group in the CRS, when it is the finest of all
    for (size_t k = 0; k < groups.size(); ++k) {
        if (sameCrs(*described[k]->info().georeference, crs) &&
            maps[k].metresPerPixel() <= maps[finest].metresPerPixel() * (1.0 + 1e-9) &&
            (!onGrid || maps[k].metresPerPixel() < maps[*onGrid].metresPerPixel() * (1.0 - 1e-9))) {
            onGrid = k;
        }
    }
    // The grid: that group's, or square pixels of the finest ground size on whole multiples of
    // it, with pixel (0, 0) near the first group's centre (where a geographic CRS's longitudes
    // are taken from).
    Georeference grid = crs;
    int64_t gridWidth = 1, gridHeight = 1;
    if (onGrid) {
        grid = *described[*onGrid]->info().georeference;
        gridWidth = described[*onGrid]->info().width;
        gridHeight = described[*onGrid]->info().height;
    } else {
        const RasterInfo& f = described[finest]->info();
        const double metres = groundSide(*f.georeference, f.width, f.height, maps[finest]);
        const double side = crs.projected ? metres / crs.unitInMetres
                                          : metres / (crs.semiMajorAxis * std::numbers::pi / 180.0) / crs.unitInDegrees;
        grid.pixelToCrs = {0.0, 1.0, 0.0, 0.0, 0.0, -1.0};
        const RasterInfo& first = described[0]->info();
        double x = 0.0, y = 0.0;
        if (!GeoreferencedMap(grid, 1, 1, target.crs).cornerPixelOf(maps[0].geodeticOf(first.width / 2.0, first.height / 2.0), x, y)) {
            throw OptionError("crs", target.crs + " cannot place " + described[0]->path() + " (beyond its projection)");
        }
        grid.pixelToCrs = {std::floor(x / side) * side, side, 0.0, std::ceil(-y / side) * side, 0.0, -side};
    }
    const std::string gridName = onGrid ? described[*onGrid]->path() : target.crs;
    const GeoreferencedMap gridMap(grid, gridWidth, gridHeight, gridName);
    // The groups on that grid, in list order, with their pixel (0, 0) on it: that group, and any
    // other there whose sample type or nodata value kept it apart (groupByGrid).
    std::vector<std::pair<size_t, std::array<int64_t, 2>>> onTheGrid;
    for (size_t k = 0; onGrid && k < groups.size(); ++k) {
        if (const auto at = offsetOnGrid(described[*onGrid]->info(), described[k]->info())) {
            onTheGrid.emplace_back(k, *at);
        }
    }

    // The mosaic's pixels on that grid: the extent asked for, or the union of the footprints.
    constexpr double kSnap = 1e-6; // a pixel edge within this of an extent's edge is on it
    double minX = std::numeric_limits<double>::infinity(), minY = minX, maxX = -minX, maxY = -minX;
    auto add = [&](double col, double row) {
        minX = std::min(minX, col);
        maxX = std::max(maxX, col);
        minY = std::min(minY, row);
        maxY = std::max(maxY, row);
    };
    // Group k's footprint on the grid, added to the box.
    const auto addFootprint = [&](size_t k) {
        const RasterInfo& info = described[k]->info();
        const auto on = std::find_if(onTheGrid.begin(), onTheGrid.end(), [&](const auto& g) { return g.first == k; });
        if (on != onTheGrid.end()) {
            const auto [dx, dy] = on->second;
            add(static_cast<double>(dx), static_cast<double>(dy));
            add(static_cast<double>(dx + info.width), static_cast<double>(dy + info.height));
            return;
        }
        constexpr int kSide = 32; // points along each edge of the group's outline
        for (int s = 0; s <= kSide; ++s) {
            const double u = static_cast<double>(s) / kSide;
            for (const auto& [c, r] : {std::pair{u * info.width, 0.0}, std::pair{u * info.width, 1.0 * info.height},
                                       std::pair{0.0, u * info.height}, std::pair{1.0 * info.width, u * info.height}}) {
                double col = 0.0, row = 0.0;
                if (gridMap.cornerPixelOf(maps[k].geodeticOf(c, r), col, row)) {
                    add(col, row);
                }
            }
        }
    };
    std::array<double, 4> inputBox{minX, minY, maxX, maxY};
    // Each group's footprint on the grid (the box of its outline's points).
    std::vector<std::array<double, 4>> footprints;
    for (size_t k = 0; k < groups.size(); ++k) {
        const std::array<double, 4> before{minX, minY, maxX, maxY};
        minX = minY = std::numeric_limits<double>::infinity();
        maxX = maxY = -minX;
        addFootprint(k);
        footprints.push_back({minX, minY, maxX, maxY});
        minX = std::min(minX, before[0]);
        minY = std::min(minY, before[1]);
        maxX = std::max(maxX, before[2]);
        maxY = std::max(maxY, before[3]);
    }
    if (target.extent) {
        inputBox = {minX, minY, maxX, maxY};
        minX = minY = std::numeric_limits<double>::infinity();
        maxX = maxY = -minX;
        const auto& e = *target.extent;
        const auto& t = grid.pixelToCrs;
        const double det = t[1] * t[5] - t[2] * t[4];
        for (const auto& [x, y] : {std::pair{e[0], e[1]}, std::pair{e[2], e[1]}, std::pair{e[0], e[3]}, std::pair{e[2], e[3]}}) {
            add((t[5] * (x - t[0]) - t[2] * (y - t[3])) / det, (t[1] * (y - t[3]) - t[4] * (x - t[0])) / det);
        }
        if (maxX <= inputBox[0] || minX >= inputBox[2] || maxY <= inputBox[1] || minY >= inputBox[3]) {
            throw OptionError("extent", "covers none of the inputs (in " + grid.crsText() + ")");
        }
    }
    const double x0 = std::floor(minX + kSnap), y0 = std::floor(minY + kSnap);
    const double x1 = std::ceil(maxX - kSnap), y1 = std::ceil(maxY - kSnap);
    if (x1 - x0 > std::numeric_limits<int>::max() || y1 - y0 > std::numeric_limits<int>::max()) {
        fail(inputs[0], "the mosaic would be " + numberText(x1 - x0) + " x " + numberText(y1 - y0) + " pixels on the grid of " +
                            gridName + ", beyond 2^31 - 1 a side");
    }
    RasterInfo info = described[finest]->info();
    info.georeference = grid;
    info.width = static_cast<int>(x1 - x0);
    info.height = static_cast<int>(y1 - y0);
    if (onGrid && groups.size() == 1 && x0 == 0.0 && y0 == 0.0 && info.width == gridWidth && info.height == gridHeight) {
        return openNorthUp(groups[0], cacheMegabytes); // the group as it is
    }
    auto& t = info.georeference->pixelToCrs;
    t[0] += t[1] * x0 + t[2] * y0;
    t[3] += t[4] * x0 + t[5] * y0;
    if (!info.nodata && info.type != SampleType::UInt8 && info.type != SampleType::UInt16) {
        info.nodata = std::numeric_limits<double>::quiet_NaN(); // gaps are holes
    }
    // Groups of several resolutions: where each may have samples and how coarse it is
    // (RasterInfo::parts), so that a pyramid goes no deeper than each where it alone is (a
    // coarse base is not encoded at an inset's level). Each footprint widened by the pixels its
    // interpolation reaches and a hundredth of its size (its outline is known at points).
    const double fine = maps[finest].metresPerPixel();
    if (std::any_of(maps.begin(), maps.end(), [&](const GeoreferencedMap& m) { return m.metresPerPixel() > fine * (1.0 + 1e-6); })) {
        for (size_t k = 0; k < groups.size(); ++k) {
            const std::array<double, 4>& f = footprints[k];
            if (!(f[0] <= f[2] && f[1] <= f[3])) {
                continue; // placed nowhere on the grid
            }
            const double widen = 2.0 + 0.01 * std::max(f[2] - f[0], f[3] - f[1]);
            const auto clampTo = [](double v, int64_t hi) {
                return static_cast<int64_t>(std::clamp(v, 0.0, static_cast<double>(hi)));
            };
            RasterPart part;
            part.x0 = clampTo(std::floor(f[0] - widen) - x0, info.width);
            part.y0 = clampTo(std::floor(f[1] - widen) - y0, info.height);
            part.x1 = clampTo(std::ceil(f[2] + widen) - x0, info.width);
            part.y1 = clampTo(std::ceil(f[3] + widen) - y0, info.height);
            part.pixelsPerSample = maps[k].metresPerPixel() / fine;
            if (part.x0 < part.x1 && part.y0 < part.y1) {
                info.parts.push_back(part);
            }
        }
    }
    const std::string name = inputs.size() == 1 ? inputs[0] : inputs[0] + " and " + std::to_string(inputs.size() - 1) + " more";
    const PlanetBody body(crs.name + "'s ellipsoid", crs.semiMajorAxis, crs.flattening);
    std::vector<OwnGroup> own;
    for (const auto& [k, at] : onTheGrid) {
        const int share = std::max(2, cacheMegabytes / 2 / static_cast<int>(onTheGrid.size()));
        own.push_back({openNorthUp(groups[k], share), at[0] - static_cast<int64_t>(x0),
                       at[1] - static_cast<int64_t>(y0)});
    }
    auto pixels = resampledPixels(groups, std::move(own), static_cast<int>(-x0), static_cast<int>(-y0),
                                  info, body, std::max(2, cacheMegabytes / 2), grid, gridWidth,
                                  gridHeight, gridName);
    return RasterSource::fromPixels(name, info, std::move(pixels));
}

} // namespace pyramid
