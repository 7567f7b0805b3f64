// The tile sizes the DEM and ortho encoders take: even (a tile's children each take half of it)
// and from 2 to the format's largest, kMaxTileSize. Throws OptionError("tileSize") otherwise.
#pragma once
#include <string>

#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"

namespace pyramid {

inline void requireEncodableTileSize(int tileSize) {
    if (tileSize < 2 || tileSize > kMaxTileSize || tileSize % 2 != 0) {
        failOption("tileSize",
                   std::to_string(tileSize) + " is not an even number from 2 to " + std::to_string(kMaxTileSize));
    }
}

} // namespace pyramid
