// The answers of `pyramid serve` that do not depend on HTTP (doc/cli/pyramid-serve.md): the
// build's description and its tiles, each a status, a body and its headers. http_server.cpp
// sends them.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "libpyramid/serve/served_build.hpp"

namespace pyramid::serve {

struct Answer {
    int status = 200;
    std::string body;
    std::string contentType = "application/json";
    std::vector<std::pair<std::string, std::string>> headers;
};

// {"error": MESSAGE} with `status`.
Answer errorAnswer(int status, const std::string& message);

// GET /api/pyramid.json: the build's faces, levels, tile layouts and URL templates.
std::string describeBuild(const ServedBuild& build);

// GET /tiles/FACE/KIND/LEVEL/TX/TY.FORMAT, its parts as the URL gives them (KIND "elevation" or
// "ortho", FORMAT "f32" or "png"): 200 with the tile, 400 for coordinates that are not numbers
// or lie outside the pyramid's levels, 404 for a face, kind or format the build does not have
// or a tile a sparse pyramid does not hold.
Answer tileAnswer(const ServedBuild& build, const std::string& face, const std::string& kind, const std::string& level,
                  const std::string& tx, const std::string& ty, const std::string& format);

} // namespace pyramid::serve
