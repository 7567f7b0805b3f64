// What `pyramid serve` serves (doc/cli/pyramid-serve.md): a build opened once, as the runtime's
// producers over its files. A plane is one face (0): a residual file or region set, with an ortho
// found beside it or named; a planet is the faces (1..6) of a directory of NAME1..6.dat, each
// with its ortho face when there is one. The producers are the runtime's own (the C API's, with
// the C API's default options), shared by every request: they are thread-safe.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "formats/residual_file.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"

namespace pyramid::serve {

struct ServeSource {
    std::string path;           // a residual file or region set, or a planet's directory
    std::string ortho;          // an ortho file, set or (planet) directory; "" = looked for beside
    std::string name = "DEM";   // a planet's elevation faces: NAME1..6.dat
    std::string orthoName = "RGB"; // the ortho files looked for: NAME.dat (plane), NAME1..6.dat
    std::string body = "wgs84"; // a planet's body (sphere/planet_body.hpp): its radius
    size_t cacheTiles = 256;    // tiles each producer keeps
};

// An ortho pyramid's producer: its tiles as stored (decoded), or rebuilt from colour residuals
// (a file in a `residuals/` directory, as preprocessOrtho names it).
class ServedOrtho {
public:
    ServedOrtho(const std::string& path, size_t cacheTiles);
    const std::string& path() const { return path_; }
    int maxLevel() const { return maxLevel_; }
    int tileSize() const { return tileSize_; } // pixels without borders
    int side() const { return side_; }         // pixels per side of a served tile
    int border() const { return border_; }
    int channels() const { return channels_; }
    bool colourResiduals() const { return colours_ != nullptr; }
    // side^2 x channels bytes, row 0 = south; nullopt for a tile no file holds (a sparse
    // pyramid's, without colour residuals). Levels 0..maxLevel.
    std::optional<std::vector<uint8_t>> tile(int level, int tx, int ty) const;

private:
    std::string path_;
    std::shared_ptr<OrthoProducer> tiles_;
    std::unique_ptr<ColourProducer> colours_;
    int maxLevel_ = 0, tileSize_ = 0, side_ = 0, border_ = 0, channels_ = 0;
};

struct ServedFace {
    int face = 0;             // 0: a plane; 1..6: a planet's face
    std::string elevationPath; // the main file (of its set)
    ResidualHeader header;    // the main file's
    int maxLevel = 0;         // the elevation producer's deepest level with residuals
    int fileMaxLevel = 0;     // the deepest level a file of the set holds (file levels)
    std::shared_ptr<ElevationProducer> elevation;
    std::unique_ptr<ServedOrtho> ortho; // null: no ortho
    float rootMin = 0.0f, rootMax = 0.0f; // the root tile's heights over its quad
};

struct ServedBuild {
    bool planet = false;
    std::string name;                    // PATH's file or directory name
    std::filesystem::path root;          // /files serves what lies under it (canonical)
    std::optional<double> radius;        // planets: metres
    std::optional<std::array<double, 2>> extent; // planes: the root quad's size in metres
    std::vector<ServedFace> faces;
    const ServedFace* face(int number) const;
};

// Throws Error naming the path when it is not a build (not a DEM file or set, no faces, an
// ortho of the wrong kind).
ServedBuild openServedBuild(const ServeSource& source);

} // namespace pyramid::serve
