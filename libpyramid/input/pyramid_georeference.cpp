#include "libpyramid/input/pyramid_georeference.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "formats/atomic_file.hpp"
#include "formats/error.hpp"

namespace pyramid {

namespace {

// The min/max box of the images of pixel-coordinate corners.
std::array<double, 4> boxOf(const Georeference& g, std::initializer_list<std::array<double, 2>> corners) {
    const auto& t = g.pixelToCrs;
    std::array<double, 4> box{1e300, 1e300, -1e300, -1e300};
    for (const auto& [c, r] : corners) {
        const double x = t[0] + t[1] * c + t[2] * r, y = t[3] + t[4] * c + t[5] * r;
        box = {std::min(box[0], x), std::min(box[1], y), std::max(box[2], x), std::max(box[3], y)};
    }
    return box;
}

nlohmann::json boxJson(const std::array<double, 4>& b) {
    return {{"min_x", b[0]}, {"min_y", b[1]}, {"max_x", b[2]}, {"max_y", b[3]}};
}

} // namespace

PyramidGeoreference georeferencePyramid(const Georeference& crs, int width, int height, const std::array<double, 4>& root,
                                        const std::vector<int64_t>& cellsPerLevel, const std::string& samples) {
    PyramidGeoreference p;
    p.crs = crs;
    p.samples = samples;
    const auto [c0, r0, c1, r1] = root;
    p.rootExtent = boxOf(crs, {{c0, r0}, {c1, r0}, {c0, r1}, {c1, r1}});
    const double W = width, H = height;
    p.dataExtent = boxOf(crs, {{0, 0}, {W, 0}, {0, H}, {W, H}});
    const auto& t = crs.pixelToCrs;
    const double column = std::hypot(t[1], t[4]), row = std::hypot(t[2], t[5]); // CRS units per input pixel
    for (const int64_t cells : cellsPerLevel) {
        const double n = static_cast<double>(cells);
        p.unitsPerSample.push_back({(c1 - c0) / n * column, (r1 - r0) / n * row});
    }
    return p;
}

nlohmann::json toJson(const PyramidGeoreference& g) {
    nlohmann::json levels = nlohmann::json::array();
    for (size_t l = 0; l < g.unitsPerSample.size(); ++l) {
        levels.push_back({{"level", l}, {"x", g.unitsPerSample[l][0]}, {"y", g.unitsPerSample[l][1]}});
    }
    const Georeference& c = g.crs;
    nlohmann::json crs = {{"epsg", c.epsg > 0 ? nlohmann::json(c.epsg) : nlohmann::json()},
                          {"name", c.name},
                          {"kind", c.projected ? "projected" : "geographic"},
                          {"semi_major_axis_metres", c.semiMajorAxis},
                          {"inverse_flattening", c.flattening > 0 ? nlohmann::json(1.0 / c.flattening) : nlohmann::json()}};
    if (c.heightUnit) {
        crs["heights"] = heightUnitJson(c);
    }
    if (c.projected) {
        crs["projection"] = c.projection.name;
        crs["unit_metres"] = c.unitInMetres;
    } else {
        crs["unit_degrees"] = c.unitInDegrees;
        crs["prime_meridian_degrees"] = c.primeMeridian;
    }
    return {{"crs", crs},
            {"rotated", !c.axisAligned()},
            {"samples", g.samples},
            {"root_extent", boxJson(g.rootExtent)},
            {"data_extent", boxJson(g.dataExtent)},
            {"units_per_sample", levels}};
}

nlohmann::json heightUnitJson(const Georeference& g) {
    if (!g.heightUnit) {
        return nullptr;
    }
    const HeightUnit& u = *g.heightUnit;
    return {{"unit", u.name.empty() ? nlohmann::json() : nlohmann::json(u.name)},
            {"unit_metres", u.metres > 0.0 ? nlohmann::json(u.metres) : nlohmann::json()},
            {"from", u.source},
            {"scaled_by", g.heightsToGround()}};
}

std::string georeferenceSidecarText(const std::string& pyramid, const PyramidGeoreference& g) {
    nlohmann::json j = toJson(g);
    j["pyramid"] = std::filesystem::path(pyramid).filename().string();
    return j.dump(2) + "\n";
}

void writeGeoreferenceSidecar(const std::string& sidecar, const std::string& pyramid, const PyramidGeoreference& g) {
    const std::string text = georeferenceSidecarText(pyramid, g);
    AtomicFile file(sidecar);
    file.writeAt(0, text.data(), text.size());
    file.commit();
}

std::array<double, 2> groundSpacing(const std::string& main, int level) {
    const std::string sidecar = georeferenceSidecarPath(main);
    std::ifstream in(sidecar);
    if (!in) {
        return {0.0, 0.0};
    }
    try {
        const nlohmann::json g = nlohmann::json::parse(in);
        for (const auto& entry : g.at("units_per_sample")) {
            if (entry.at("level").get<int>() != level) {
                continue;
            }
            double x = entry.at("x").get<double>(), y = entry.at("y").get<double>();
            const auto& crs = g.at("crs");
            if (crs.at("kind") == "geographic") {
                const double a = crs.at("semi_major_axis_metres").get<double>();
                const double degree = a * std::numbers::pi / 180.0 * crs.value("unit_degrees", 1.0);
                const auto& root = g.at("root_extent");
                const double middle = (root.at("min_y").get<double>() + root.at("max_y").get<double>()) / 2.0;
                x *= degree * std::cos(middle * std::numbers::pi / 180.0);
                y *= degree;
            } else {
                x *= crs.value("unit_metres", 1.0);
                y *= crs.value("unit_metres", 1.0);
            }
            return {std::abs(x), std::abs(y)};
        }
    } catch (const nlohmann::json::exception&) {
        fail(sidecar, "not a georeference sidecar");
    }
    return {0.0, 0.0};
}

} // namespace pyramid
