// The build `pyramid serve` serves (served_build.hpp): its faces' producers, opened once.
#include "libpyramid/serve/served_build.hpp"

#include <algorithm>
#include <cmath>
#include <system_error>

#include "formats/error.hpp"
#include "formats/georeference_sidecar.hpp"
#include "formats/pyramid_set.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid::serve {

namespace fs = std::filesystem;

ServedOrtho::ServedOrtho(const std::string& path, size_t cacheTiles) : path_(path) {
    const PyramidSet set = openPyramidSet(path);
    if (set.kind != PyramidKind::Ortho) {
        fail(path, "a residual (DEM) pyramid, not an ortho pyramid");
    }
    tiles_ = openOrthoSet(set);
    const OrthoHeader& h = tiles_->header();
    // A colour residual file is in a `residuals/` directory (the name preprocessOrtho gives it;
    // preview/ reads it so too): its tiles are rebuilt by the colour producer.
    if (!h.dxt() && h.border() == 2 && fs::path(set.main).parent_path().filename() == "residuals") {
        colours_ = std::make_unique<ColourProducer>(tiles_, std::max<size_t>(cacheTiles, 1));
    }
    maxLevel_ = tiles_->maxLevel();
    tileSize_ = h.tileSize;
    side_ = h.tilePixels();
    border_ = h.border();
    channels_ = h.channels;
}

std::optional<std::vector<uint8_t>> ServedOrtho::tile(int level, int tx, int ty) const {
    if (colours_) {
        return *colours_->tile(level, tx, ty);
    }
    if (!tiles_->hasTile(level, tx, ty)) {
        return std::nullopt;
    }
    return tiles_->tile(level, tx, ty);
}

const ServedFace* ServedBuild::face(int number) const {
    for (const ServedFace& f : faces) {
        if (f.face == number) {
            return &f;
        }
    }
    return nullptr;
}

namespace {

bool isFile(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec);
}

// The face's elevation producer, as the C API's pyramid_elevation_open(path, 0, 0, cacheTiles)
// makes it: tiles of the file's tile size, zc on a grid of n.
ServedFace openFace(int number, const std::string& path, size_t cacheTiles) {
    const PyramidSet set = openPyramidSet(path);
    if (set.kind != PyramidKind::Residual) {
        fail(set.name(), "an ortho pyramid, not a DEM: serve the DEM (and give the imagery with --ortho)");
    }
    ServedFace f;
    f.face = number;
    f.elevationPath = set.main;
    f.header = ResidualFileReader::readHeader(set.main);
    f.fileMaxLevel = setMaxLevel(set);
    ElevationProducerOptions options;
    options.cacheCapacity = std::max<size_t>(cacheTiles, 1);
    f.elevation = openElevationSet(path, options);
    // The producer's level L is file level L + delta (doc/format.md, "Elevation arithmetic").
    f.maxLevel = f.fileMaxLevel - elevationDelta(f.header, f.elevation->tileSize(), set.main);
    const auto root = f.elevation->tile(0, 0, 0);
    const int side = root->size;
    f.rootMin = f.rootMax = root->zf[static_cast<size_t>(2 * side + 2)];
    for (int j = 2; j < side - 2; ++j) {
        for (int i = 2; i < side - 2; ++i) {
            const float z = root->zf[static_cast<size_t>(j * side + i)];
            f.rootMin = std::min(f.rootMin, z);
            f.rootMax = std::max(f.rootMax, z);
        }
    }
    return f;
}

// The first of `candidates` that is a file (a set's main file: its index is found beside it).
std::string firstFile(const std::vector<fs::path>& candidates) {
    for (const fs::path& p : candidates) {
        if (isFile(p)) {
            return p.string();
        }
    }
    return "";
}

// The ortho files looked for in a directory: NAME as stored, then colour residuals, then DXT.
std::vector<fs::path> orthoCandidates(const fs::path& directory, const std::string& file) {
    return {directory / file, directory / "residuals" / file, directory / "dxt" / file};
}

std::optional<std::array<double, 2>> planeExtent(const std::string& mainFile) {
    const std::string sidecar = georeferenceSidecarPath(mainFile);
    if (!isFile(sidecar)) {
        return std::nullopt;
    }
    const SidecarPlacement p = readGeoreferenceSidecar(sidecar);
    if (p.geographic) {
        return std::nullopt; // degrees: no single size in metres
    }
    return std::array<double, 2>{(p.rootExtent[2] - p.rootExtent[0]) * p.unitInMetres,
                                 (p.rootExtent[3] - p.rootExtent[1]) * p.unitInMetres};
}

void openPlanet(const ServeSource& s, const fs::path& directory, ServedBuild& build) {
    build.planet = true;
    build.radius = PlanetBody::parse(s.body).equatorialRadius();
    for (int face = 1; face <= kCubeFaceCount; ++face) {
        const std::string file = faceFilePath(directory.string(), s.name, face);
        if (!isFile(file)) {
            continue;
        }
        ServedFace f = openFace(face, file, s.cacheTiles);
        const std::string orthoFile = faceFileName(s.orthoName, face);
        const std::string ortho = s.ortho.empty() ? firstFile(orthoCandidates(directory, orthoFile))
                                                  : firstFile({fs::path(s.ortho) / orthoFile});
        if (!ortho.empty()) {
            f.ortho = std::make_unique<ServedOrtho>(ortho, s.cacheTiles);
        }
        build.faces.push_back(std::move(f));
    }
}

} // namespace

ServedBuild openServedBuild(const ServeSource& s) {
    std::error_code ec;
    if (!fs::exists(s.path, ec)) {
        fail(s.path, "no such file or directory");
    }
    if (!s.ortho.empty() && !fs::exists(s.ortho, ec)) {
        fail(s.ortho, "no such file or directory (--ortho)");
    }
    ServedBuild build;
    const fs::path path = fs::absolute(s.path).lexically_normal();
    const bool directory = fs::is_directory(path, ec);
    build.root = fs::canonical(directory ? path : path.parent_path());
    build.name = (path.filename().empty() ? path.parent_path().filename() : path.filename()).string();
    const auto hasFaces = [&] {
        for (int face = 1; face <= kCubeFaceCount; ++face) {
            if (isFile(faceFilePath(path.string(), s.name, face))) {
                return true;
            }
        }
        return false;
    };
    if (directory && hasFaces()) {
        openPlanet(s, path, build);
        return build;
    }
    // A plane: the file, the set the path names, or NAME.dat in the directory.
    std::string dem = path.string();
    if (directory) {
        const fs::path named = path / (s.name + ".dat");
        if (isFile(named)) {
            dem = named.string();
        } else {
            try {
                findRegionIndex(dem);
            } catch (const Error&) {
                fail(s.path, "not a build: no " + s.name + ".dat, no faces " + faceFileName(s.name, 1) + ".." +
                                 faceFileName(s.name, 6) + " and no region index in it");
            }
        }
    }
    ServedFace f = openFace(0, dem, s.cacheTiles);
    build.extent = planeExtent(f.elevationPath);
    const std::string orthoFile = s.orthoName + ".dat";
    std::string ortho = s.ortho;
    if (ortho.empty()) {
        ortho = firstFile(orthoCandidates(fs::path(f.elevationPath).parent_path(), orthoFile));
    } else if (fs::is_directory(ortho, ec) && isFile(fs::path(ortho) / orthoFile)) {
        ortho = (fs::path(ortho) / orthoFile).string();
    }
    if (!ortho.empty()) {
        f.ortho = std::make_unique<ServedOrtho>(ortho, s.cacheTiles);
    }
    build.faces.push_back(std::move(f));
    return build;
}

} // namespace pyramid::serve
