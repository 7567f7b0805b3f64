#include "cli/sphere_options.hpp"

#include <cmath>

#include <CLI/CLI.hpp>

#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid::cli {

void addSphereOptions(CLI::App& app, const std::shared_ptr<SphereArgs>& args) {
    app.add_option("--extent", args->extent,
                   "WEST,SOUTH,EAST,NORTH in degrees covered by a map without georeferencing (default: the whole "
                   "globe); the rest is nodata. A GeoTIFF places itself: --extent may only repeat its extent");
    app.add_option("--body", args->body,
                   "wgs84, sphere (the original tools' mapping), moon, mars, or A,F (equatorial radius in metres, "
                   "flattening or inverse flattening)")
        ->capture_default_str();
    app.add_option("--faces", args->faces, "Cube faces to build, e.g. 1,3 (1 = north pole, 6 = south pole)")
        ->capture_default_str();
}

SphereChoice resolveSphereOptions(const SphereArgs& args) {
    SphereChoice c;
    if (!args.extent.empty()) {
        c.extent = GeoExtent::parse(args.extent);
    }
    c.body = args.body;
    (void)PlanetBody::parse(args.body); // a bad body fails before the input is opened
    size_t start = 0;
    while (start <= args.faces.size()) {
        const size_t comma = std::min(args.faces.find(',', start), args.faces.size());
        const std::string part = args.faces.substr(start, comma - start);
        if (part.size() != 1 || part[0] < '1' || part[0] > '0' + kCubeFaceCount) {
            fail("--faces", "'" + args.faces + "' is not a list of face numbers from 1 to 6");
        }
        c.faces.push_back(part[0] - '0');
        start = comma + 1;
    }
    return c;
}

double parseRatio(const std::string& text, const std::string& option) {
    const size_t slash = text.find('/');
    const std::optional<double> a = tryParseNumber(text.substr(0, slash));
    const std::optional<double> b = slash == std::string::npos ? 1.0 : tryParseNumber(text.substr(slash + 1));
    if (!a || !b) {
        fail(option, "'" + text + "' is not a number or a ratio A/B");
    }
    if (*b == 0.0) {
        fail(option, "'" + text + "' divides by zero");
    }
    return *a / *b;
}

} // namespace pyramid::cli
