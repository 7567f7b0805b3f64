#include "formats/georeference_sidecar.hpp"

#include <fstream>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"

namespace pyramid {

std::string georeferenceSidecarPath(const std::string& path) { return path + ".georef.json"; }

SidecarPlacement readGeoreferenceSidecar(const std::string& sidecar) {
    std::ifstream in(sidecar);
    if (!in) {
        fail(sidecar, "no such file: the pyramid was not built from a georeferenced input");
    }
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        SidecarPlacement p;
        p.geographic = j.at("crs").at("kind").get<std::string>() == "geographic";
        const nlohmann::json& box = j.at("root_extent");
        p.rootExtent = {box.at("min_x").get<double>(), box.at("min_y").get<double>(), box.at("max_x").get<double>(),
                        box.at("max_y").get<double>()};
        const nlohmann::json& crs = j.at("crs");
        if (p.geographic) {
            p.unitInDegrees = crs.value("unit_degrees", 1.0);
            p.primeMeridian = crs.value("prime_meridian_degrees", 0.0);
        } else {
            p.unitInMetres = crs.value("unit_metres", 1.0);
        }
        p.rotated = j.value("rotated", false);
        return p;
    } catch (const nlohmann::json::exception& e) {
        fail(sidecar, std::string("not a georeference sidecar: ") + e.what());
    }
}

} // namespace pyramid
