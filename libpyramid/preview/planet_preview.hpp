// A planet's preview: the six cube-face pyramids the spherical preprocessors write
// (NAME1.dat .. NAME6.dat in one directory, each a file or a region set; doc/spherical.md for
// their numbering and orientation) drawn together as an equirectangular world map or an
// unfolded cube cross (preview.hpp, PreviewProjection).
#pragma once
#include <array>
#include <optional>
#include <string>

#include "formats/pyramid_kind.hpp"
#include "libpyramid/preview/preview.hpp"

namespace pyramid::preview {

struct PlanetFaces {
    std::string directory, name;
    std::array<std::string, 6> files; // DIR/NAME1.dat .. DIR/NAME6.dat
    std::string describe() const;     // "DIR/NAME1..6.dat"
};

// The one family of six faces in `directory` (names NAMEk.dat, k = 1..6, all present), nullopt
// when there is none. Throws Error naming the directory when it holds several.
std::optional<PlanetFaces> planetFacesIn(const std::string& directory);
// The planet `target` names: a directory (planetFacesIn), or one face file NAMEk.dat of a
// family whose six files are all beside it. Throws Error naming `target` otherwise.
PlanetFaces planetFacesOf(const std::string& target);

// Draws the planet in `projection` (Equirectangular or Cube). Throws Error or OptionError and
// writes nothing on error.
PreviewReport planetPreview(const PlanetFaces& faces, const std::string& output, const PreviewOptions& options,
                            PreviewProjection projection);

} // namespace pyramid::preview
