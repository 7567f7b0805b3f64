#include "formats/pyramid_file_rules.hpp"

namespace pyramid::detail {

void requireHeader(const std::string& path, uint64_t fileBytes, size_t headerBytes) {
    if (fileBytes == 0) {
        fail(path, "empty file, not a pyramid");
    }
    if (fileBytes < headerBytes) {
        fail(path, "file of " + std::to_string(fileBytes) + " bytes, shorter than a pyramid header (" +
                       std::to_string(headerBytes) + " bytes)");
    }
}

std::string tileName(const std::string& path, int level, int tx, int ty) {
    return path + ": tile " + tileCoordinates(level, tx, ty);
}

void throwMissingTile(const std::string& path, int level, int tx, int ty) {
    throw MissingTileError(path + ": no tile " + tileCoordinates(level, tx, ty) + " in this file");
}

} // namespace pyramid::detail
