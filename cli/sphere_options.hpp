// The options the spherical commands share: the map's extent, the planet's body and the faces
// to build, declared once and checked once the command line is parsed.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "libpyramid/api/encoders.hpp"

namespace CLI {
class App;
}

namespace pyramid::cli {

struct SphereArgs {
    std::string extent;
    std::string body = "wgs84";
    std::string faces = "1,2,3,4,5,6";
};

void addSphereOptions(CLI::App& app, const std::shared_ptr<SphereArgs>& args);

struct SphereChoice {
    std::optional<GeoExtent> extent; // given: a georeferenced input's must agree with it
    std::string body;
    std::vector<int> faces;
};
// Throws Error naming the option when a value is not valid.
SphereChoice resolveSphereOptions(const SphereArgs& args);

// A positive or negative number written as "X" or "A/B" (e.g. "10000/255"); throws Error
// naming `option` otherwise.
double parseRatio(const std::string& text, const std::string& option);

} // namespace pyramid::cli
