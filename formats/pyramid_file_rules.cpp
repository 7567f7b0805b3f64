#include "formats/pyramid_file_rules.hpp"

namespace pyramid::detail {

std::string tileName(const std::string& path, int level, int tx, int ty) {
    return path + ": tile " + tileCoordinates(level, tx, ty);
}

void throwMissingTile(const std::string& path, int level, int tx, int ty) {
    throw MissingTileError(path + ": no tile " + tileCoordinates(level, tx, ty) + " in this file");
}

} // namespace pyramid::detail
