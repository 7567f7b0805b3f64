#include "libpyramid/sphere/map_placement.hpp"

#include <GeographicLib/Math.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "formats/error.hpp"

namespace pyramid {

namespace {

using GeographicLib::Math;

std::string extentText(const GeoExtent& e) {
    char text[128];
    std::snprintf(text, sizeof text, "%.10g,%.10g,%.10g,%.10g", e.west, e.south, e.east, e.north);
    return text;
}

// Border points per edge from which the bounds are measured; the bounds are padded well beyond
// what a projection bends between them.
constexpr int kBorderProbes = 64;

} // namespace

GeoreferencedMap::GeoreferencedMap(const Georeference& crs, int64_t width, int64_t height, const std::string& path)
    : crs_(crs), width_(width), height_(height) {
    if (crs.projected) {
        projection_ = MapProjection::of(crs, path);
    }
    const auto& t = crs.pixelToCrs;
    const double det = t[1] * t[5] - t[2] * t[4];
    crsToPixel_ = {t[5] / det, -t[2] / det, -t[4] / det, t[1] / det, t[0], t[3]};
    const double cx = static_cast<double>(width) / 2.0, cy = static_cast<double>(height) / 2.0;
    referenceLongitude_ = geodeticOf(cx, cy).longitude;
    const double side = std::sqrt(std::fabs(det));
    metresPerPixel_ = crs.projected ? side * crs.unitInMetres : side * crs.unitInDegrees * crs.semiMajorAxis * Math::degree();

    // The box of the border's points, longitudes unwrapped around the centre's.
    double south = 90.0, north = -90.0, west = 360.0, east = -360.0;
    auto add = [&](double c, double r) {
        const GeodeticPoint p = geodeticOf(c, r);
        if (std::isfinite(p.latitude) && std::isfinite(p.longitude)) {
            south = std::min(south, p.latitude);
            north = std::max(north, p.latitude);
            const double lon = referenceLongitude_ + Math::AngDiff(referenceLongitude_, p.longitude);
            west = std::min(west, lon);
            east = std::max(east, lon);
        }
    };
    const double W = static_cast<double>(width), H = static_cast<double>(height);
    for (int k = 0; k <= kBorderProbes; ++k) {
        const double s = static_cast<double>(k) / kBorderProbes;
        add(s * W, 0.0);
        add(s * W, H);
        add(0.0, s * H);
        add(W, s * H);
    }
    bool allLongitudes = false;
    for (const double pole : {-90.0, 90.0}) { // a pole on the map: every longitude reaches it
        double x = 0.0, y = 0.0;
        if (crsOf(pole, referenceLongitude_, x, y)) {
            const double c = crsToPixel_[0] * (x - t[0]) + crsToPixel_[1] * (y - t[3]);
            const double r = crsToPixel_[2] * (x - t[0]) + crsToPixel_[3] * (y - t[3]);
            if (c >= 0.0 && c <= W && r >= 0.0 && r <= H) {
                (pole < 0.0 ? south : north) = pole;
                allLongitudes = true;
            }
        }
    }
    const double pixelDegrees = metresPerPixel_ / (crs.semiMajorAxis * Math::degree());
    const double latPad = 0.05 * (north - south) + 2.0 * pixelDegrees;
    bounds_.south = std::max(-90.0, south - latPad);
    bounds_.north = std::min(90.0, north + latPad);
    const double polewards = std::max(std::fabs(bounds_.south), std::fabs(bounds_.north));
    const double lonPad = 0.05 * (east - west) + 2.0 * pixelDegrees / std::max(Math::cosd(polewards), 0.01);
    if (allLongitudes || polewards > 89.0 || east - west + 2.0 * lonPad >= 360.0) {
        bounds_.west = referenceLongitude_ - 180.0;
        bounds_.east = referenceLongitude_ + 180.0;
    } else {
        bounds_.west = west - lonPad;
        bounds_.east = east + lonPad;
    }
}

bool GeoreferencedMap::crsOf(double latitude, double longitude, double& x, double& y) const {
    if (projection_) {
        if (!projection_->forward(latitude, longitude, x, y)) {
            return false;
        }
        x /= crs_.unitInMetres;
        y /= crs_.unitInMetres;
        return true;
    }
    x = (referenceLongitude_ + Math::AngDiff(referenceLongitude_, longitude) - crs_.primeMeridian) / crs_.unitInDegrees;
    y = latitude / crs_.unitInDegrees;
    return true;
}

GeodeticPoint GeoreferencedMap::geodeticOf(double cornerCol, double cornerRow) const {
    const auto& t = crs_.pixelToCrs;
    const double x = t[0] + t[1] * cornerCol + t[2] * cornerRow;
    const double y = t[3] + t[4] * cornerCol + t[5] * cornerRow;
    GeodeticPoint p;
    if (projection_) {
        projection_->reverse(x * crs_.unitInMetres, y * crs_.unitInMetres, p.latitude, p.longitude);
    } else {
        p.latitude = y * crs_.unitInDegrees;
        p.longitude = x * crs_.unitInDegrees + crs_.primeMeridian;
    }
    return p;
}

bool GeoreferencedMap::pixelOf(const GeodeticPoint& p, double& col, double& row) const {
    if (!(p.latitude >= bounds_.south && p.latitude <= bounds_.north)) {
        return false;
    }
    const double lon = referenceLongitude_ + Math::AngDiff(referenceLongitude_, p.longitude);
    if (!bounds_.global() && (lon < bounds_.west || lon > bounds_.east)) {
        return false;
    }
    double c = 0.0, r = 0.0;
    if (!cornerPixelOf(p, c, r)) {
        return false;
    }
    if (!(c >= 0.0 && c <= static_cast<double>(width_) && r >= 0.0 && r <= static_cast<double>(height_))) {
        return false;
    }
    col = c - 0.5;
    row = r - 0.5;
    return true;
}

bool GeoreferencedMap::cornerPixelOf(const GeodeticPoint& p, double& cornerCol, double& cornerRow) const {
    double x = 0.0, y = 0.0;
    if (!crsOf(p.latitude, p.longitude, x, y)) {
        return false;
    }
    const auto& t = crs_.pixelToCrs;
    cornerCol = crsToPixel_[0] * (x - t[0]) + crsToPixel_[1] * (y - t[3]);
    cornerRow = crsToPixel_[2] * (x - t[0]) + crsToPixel_[3] * (y - t[3]);
    return true;
}

MapPlacement placeMap(const RasterInfo& info, const std::string& path, const std::optional<GeoExtent>& extent,
                      const PlanetBody& body) {
    const double W = static_cast<double>(info.width), H = static_cast<double>(info.height);
    if (!info.georeference) {
        MapPlacement m(extent.value_or(GeoExtent{}));
        m.extent.validate();
        m.columnsAround = W * 360.0 / (m.extent.east - m.extent.west);
        return m;
    }
    const Georeference& g = *info.georeference;
    if (!g.problem.empty()) {
        fail(path, g.problem);
    }
    MapPlacement m;
    m.crs = g.crsText();
    const auto& t = g.pixelToCrs;
    const GeoExtent file{t[0], t[3] + H * t[5], t[0] + W * t[1], t[3]};
    const bool plateCarree = !g.projected && g.axisAligned() && t[1] > 0.0 && t[5] < 0.0 && g.unitInDegrees == 1.0 &&
                             g.primeMeridian == 0.0 && file.brokenRule() == nullptr;
    if (plateCarree) {
        // Within half a pixel the extent says the same: grid- or cell-registered.
        if (extent && (std::fabs(extent->west - file.west) > 0.5 * t[1] || std::fabs(extent->east - file.east) > 0.5 * t[1] ||
                       std::fabs(extent->south - file.south) > -0.5 * t[5] ||
                       std::fabs(extent->north - file.north) > -0.5 * t[5])) {
            failOption("extent", extentText(*extent) + " contradicts the file's georeferencing (" + extentText(file) +
                                     " in " + m.crs + "); leave --extent out");
        }
        m.extent = file;
        m.columnsAround = W * 360.0 / (file.east - file.west);
        return m;
    }
    if (extent) {
        failOption("extent", "the file places itself (" + m.crs + "); leave --extent out");
    }
    auto map = std::make_shared<const GeoreferencedMap>(g, info.width, info.height, path);
    m.extent = map->bounds();
    m.columnsAround = 2.0 * Math::pi() * body.equatorialRadius() / map->metresPerPixel();
    m.map = std::move(map);
    return m;
}

} // namespace pyramid
