// GET /api/pyramid.json (answers.hpp, describeBuild): what a viewer needs to draw the build.
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "libpyramid/serve/answers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"

namespace pyramid::serve {

namespace {

using json = nlohmann::ordered_json; // fields in the order the doc gives them

// The rotation taking face plane coordinates (u right, v up, 1 outward) to the planet's axes:
// faceDirection's table (sphere/cube_faces.hpp) is linear in (u, v, 1), so its columns are the
// directions of (1, 0, 0), (0, 1, 0) and (0, 0, 1). Rows of the matrix, XYZ = frame (u, v, 1).
json faceFrame(int face) {
    const auto origin = faceDirection(face, 0.0, 0.0);
    const auto du = faceDirection(face, 1.0, 0.0);
    const auto dv = faceDirection(face, 0.0, 1.0);
    json rows = json::array();
    for (int r = 0; r < 3; ++r) {
        const auto k = static_cast<size_t>(r);
        // + 0.0: a -0 of the table written as 0.
        rows.push_back({du[k] - origin[k] + 0.0, dv[k] - origin[k] + 0.0, origin[k] + 0.0});
    }
    return rows;
}

// A file's path under the served directory, as /files/ serves it; null when it lies elsewhere.
json servedPath(const ServedBuild& build, const std::string& file) {
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::canonical(file, ec);
    if (ec) {
        return nullptr;
    }
    const std::filesystem::path relative = canonical.lexically_relative(build.root);
    if (relative.empty() || *relative.begin() == "..") {
        return nullptr;
    }
    return relative.generic_string();
}

// Levels are the elevation producer's: level 0 is the root tile of n intervals, the file's level
// file_min_level (the file's coarser levels fold into it: doc/format.md, "Elevation arithmetic").
json elevationOf(const ServedBuild& build, const ServedFace& f) {
    const int n = f.elevation->tileSize();
    return {{"max_level", f.maxLevel},
            {"min_level", 0},
            {"file_min_level", f.header.minLevel},
            {"file_max_level", f.fileMaxLevel},
            {"tile_size", n},
            {"grid", f.elevation->gridSize()},
            {"side", n + 5},
            {"border", 2},
            {"scale", f.header.scale},
            {"min_height", nullptr},
            {"max_height", nullptr},
            {"root_min_height", f.rootMin},
            {"root_max_height", f.rootMax},
            {"file", servedPath(build, f.elevationPath)}};
}

json orthoOf(const ServedBuild& build, const ServedFace& f) {
    if (!f.ortho) {
        return nullptr;
    }
    const ServedOrtho& o = *f.ortho;
    return {{"max_level", o.maxLevel()},         {"tile_size", o.tileSize()},
            {"side", o.side()},                  {"border", o.border()},
            {"channels", o.channels()},          {"colour_residuals", o.colourResiduals()},
            {"file", servedPath(build, o.path())}};
}

} // namespace

std::string describeBuild(const ServedBuild& build) {
    json faces = json::array();
    for (const ServedFace& f : build.faces) {
        faces.push_back({{"face", f.face},
                         {"elevation", elevationOf(build, f)},
                         {"ortho", orthoOf(build, f)},
                         {"frame", build.planet ? faceFrame(f.face) : json(nullptr)}});
    }
    json extent = nullptr;
    if (build.extent) {
        extent = {{"size_x", (*build.extent)[0]}, {"size_y", (*build.extent)[1]}};
    }
    const json description = {
        {"format", "libpyramid-serve 1"},
        {"kind", build.planet ? "planet" : "plane"},
        {"name", build.name},
        {"radius", build.radius ? json(*build.radius) : json(nullptr)},
        {"faces", faces},
        {"extent", extent},
        {"tiles",
         {{"elevation", "/tiles/{face}/elevation/{level}/{tx}/{ty}.f32"},
          {"elevation_png", "/tiles/{face}/elevation/{level}/{tx}/{ty}.png"},
          {"ortho", "/tiles/{face}/ortho/{level}/{tx}/{ty}.png"}}},
        {"files", "/files/"}};
    return description.dump(2) + "\n";
}

} // namespace pyramid::serve
