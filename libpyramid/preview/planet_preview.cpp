#include "libpyramid/preview/planet_preview.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <vector>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"
#include "libpyramid/preview/png_writer.hpp"
#include "libpyramid/preview/preview_levels.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/face_locate.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid::preview {

namespace fs = std::filesystem;

std::string PlanetFaces::describe() const { return (fs::path(directory) / (name + "1..6.dat")).string(); }

namespace {

PlanetFaces family(const std::string& directory, const std::string& name) {
    PlanetFaces faces;
    faces.directory = directory;
    faces.name = name;
    for (int k = 0; k < kCubeFaceCount; ++k) {
        faces.files[static_cast<size_t>(k)] = faceFilePath(directory, name, k + 1);
    }
    return faces;
}

// "DEM3.dat" -> "DEM": the name of a face file NAMEk.dat, k = 1..6, in `directory`; nullopt for
// any other name, and for a region file of a main file beside it (RGB-L4-0-1.dat of RGB.dat,
// DEM3-L2-1-3.dat of DEM3.dat: formats/pyramid_set.hpp), which a set (or a face) holds.
std::optional<std::string> faceFamily(const std::string& directory, const std::string& file) {
    std::error_code ec;
    if (const auto region = parseRegionFilePath((fs::path(directory) / file).string());
        region && fs::is_regular_file(region->mainFile, ec)) {
        return std::nullopt;
    }
    const std::string suffix = ".dat";
    if (file.size() < suffix.size() + 1 || file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0) {
        return std::nullopt;
    }
    const char k = file[file.size() - suffix.size() - 1];
    if (k < '1' || k > '6') {
        return std::nullopt;
    }
    return file.substr(0, file.size() - suffix.size() - 1);
}

bool complete(const PlanetFaces& faces) {
    std::error_code ec;
    return std::all_of(faces.files.begin(), faces.files.end(),
                       [&](const std::string& f) { return fs::is_regular_file(f, ec); });
}

} // namespace

std::optional<PlanetFaces> planetFacesIn(const std::string& directory) {
    std::set<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(directory, ec)) {
        const auto name = faceFamily(directory, entry.path().filename().string());
        if (name && entry.is_regular_file(ec) && complete(family(directory, *name))) {
            names.insert(*name);
        }
    }
    if (ec) {
        fail(directory, "cannot list the directory: " + ec.message());
    }
    if (names.empty()) {
        return std::nullopt;
    }
    if (names.size() > 1) {
        std::string list;
        for (const std::string& n : names) {
            list += (list.empty() ? "" : ", ") + n + "1..6.dat";
        }
        fail(directory, "holds several planets (" + list + "); name one face file, e.g. " +
                            family(directory, *names.begin()).files[0]);
    }
    return family(directory, *names.begin());
}

PlanetFaces planetFacesOf(const std::string& target) {
    std::error_code ec;
    if (fs::is_directory(target, ec)) {
        const auto faces = planetFacesIn(target);
        if (!faces) {
            fail(target, "holds no planet: no six cube faces NAME1.dat .. NAME6.dat");
        }
        return *faces;
    }
    const fs::path parentPath = fs::path(target).parent_path();
    const std::string directory = parentPath.empty() ? "." : parentPath.string();
    const auto name = faceFamily(directory, fs::path(target).filename().string());
    if (!name) {
        fail(target, "is not a cube face of a planet (NAME1.dat .. NAME6.dat)");
    }
    PlanetFaces faces = family(directory, *name);
    for (const std::string& f : faces.files) {
        if (!fs::is_regular_file(f, ec)) {
            fail(target, "is not one of six cube faces: " + f + " is missing");
        }
    }
    return faces;
}

namespace {

// The face level drawn: every face must give it the same side (the same tiling).
template <class SideOf>
int planetLevel(const PreviewOptions& o, const PlanetFaces& faces, const std::vector<PyramidSet>& sets,
                const SideOf& sideOf) {
    int deepest = setMaxLevel(sets[0]);
    for (const PyramidSet& s : sets) {
        deepest = std::min(deepest, setMaxLevel(s));
    }
    const int level = chooseLevel(o, deepest, std::max(1, o.size / 4), [&](int l) { return sideOf(0, l); },
                                  faces.describe());
    for (size_t k = 1; k < sets.size(); ++k) {
        if (sideOf(k, level) != sideOf(0, level)) {
            fail(faces.files[k], "level " + std::to_string(level) + " is " + std::to_string(sideOf(k, level)) +
                                     " samples a side, not face 1's " + std::to_string(sideOf(0, level)));
        }
    }
    return level;
}

// Pixel centres of an equirectangular image of width x height: longitude and latitude, degrees.
double longitudeOf(int64_t column, int64_t width) {
    return -180.0 + (static_cast<double>(column) + 0.5) * 360.0 / static_cast<double>(width);
}
double latitudeOf(int64_t row, int64_t height) {
    return 90.0 - (static_cast<double>(row) + 0.5) * 180.0 / static_cast<double>(height);
}

// Where the surface point under a pixel lies on the cube.
struct Located {
    int face = 1;
    double u = 0.0, v = 0.0;
};
std::vector<Located> locateRow(const PlanetBody& body, int64_t row, int64_t width, int64_t height) {
    std::vector<Located> out(static_cast<size_t>(width));
    const double latitude = latitudeOf(row, height);
    for (int64_t c = 0; c < width; ++c) {
        const FacePoint p = facePointOf(directionOf(body, {latitude, longitudeOf(c, width)}));
        out[static_cast<size_t>(c)] = {p.face, p.u, p.v};
    }
    return out;
}

std::array<double, 3> unit(const std::array<double, 3>& d) {
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return {d[0] / n, d[1] / n, d[2] / n};
}

// The cross: which face (1..6, 0 for none) sits in band b (0..2), column c (0..3).
int crossFace(int band, int column) {
    if (band == 1) {
        return 2 + column;
    }
    return column == 0 ? (band == 0 ? 1 : 6) : 0;
}

// The six face images composed into the cross, strip by strip.
void writeCross(PngWriter& png, const std::vector<LevelImage>& images) {
    const LevelImage& first = images[0];
    const size_t faceRow = static_cast<size_t>(first.side) * static_cast<size_t>(first.channels);
    std::vector<uint8_t> row(faceRow * 4);
    std::vector<std::vector<uint8_t>> strips(4);
    for (int band = 0; band < 3; ++band) {
        for (int s = 0; s < first.strips; ++s) {
            int count = 0;
            for (int c = 0; c < 4; ++c) {
                const int face = crossFace(band, c);
                if (face) {
                    count = images[static_cast<size_t>(face - 1)].strip(s, strips[static_cast<size_t>(c)]);
                }
            }
            for (int r = 0; r < count; ++r) {
                std::fill(row.begin(), row.end(), uint8_t{0});
                for (int c = 0; c < 4; ++c) {
                    if (crossFace(band, c)) {
                        std::copy_n(strips[static_cast<size_t>(c)].data() + static_cast<size_t>(r) * faceRow, faceRow,
                                    row.data() + static_cast<size_t>(c) * faceRow);
                    }
                }
                png.writeRow(row.data());
            }
        }
    }
}

PreviewReport elevationPlanet(const PlanetFaces& faces, const std::vector<PyramidSet>& sets, const std::string& output,
                              const PreviewOptions& o, PreviewProjection projection, const PlanetBody& body) {
    const PreviewStyle style = elevationStyle(o, faces.describe());
    if (style == PreviewStyle::Residuals) {
        failOption("style", "residuals are drawn face by face: give one face file with --projection face");
    }
    std::vector<ResidualHeader> headers;
    for (const PyramidSet& s : sets) {
        headers.push_back(ResidualFileReader::readHeader(s.main));
    }
    const int level =
        planetLevel(o, faces, sets, [&](size_t k, int l) { return elevationLevelSide(headers[k], l); });
    const int64_t across = headers[0].tilesPerSide(level);
    // Enough tiles for the rows of tiles a row of pixels crosses, on the polar faces a ring.
    const auto cache = static_cast<size_t>(4 * across + 8);
    std::vector<std::unique_ptr<ElevationGrid>> grids;
    PreviewReport report;
    report.kind = "elevation";
    report.style = previewStyleName(style);
    report.level = level;
    report.projection = previewProjectionName(projection);
    report.body = body.describe();
    report.minimum = std::numeric_limits<double>::infinity();
    report.maximum = -report.minimum;
    for (const PyramidSet& s : sets) {
        grids.push_back(std::make_unique<ElevationGrid>(s, level, false, cache));
        const auto [lo, hi] = grids.back()->range();
        report.minimum = std::min(report.minimum, lo);
        report.maximum = std::max(report.maximum, hi);
    }
    const ElevationPaint paint(style, report.minimum, report.maximum, o);
    const double a = body.equatorialRadius();
    const int64_t N = grids[0]->side() - 1; // intervals a face side
    int64_t width = 0, height = 0;
    if (projection == PreviewProjection::Cube) {
        width = 4 * (N + 1);
        height = 3 * (N + 1);
    } else {
        width = 4 * N;
        height = 2 * N;
    }
    const auto legend = o.legend ? legendRows(width, paint) : std::vector<std::vector<uint8_t>>{};
    report.legendHeight = static_cast<int>(legend.size());
    report.width = static_cast<int>(width);
    report.height = static_cast<int>(height) + report.legendHeight;
    PngWriter png(output, report.width, report.height, 3, 8, previewText(faces.describe(), report));
    if (projection == PreviewProjection::Cube) {
        // Each face upright as its own preview draws it; slopes over the ground distance between
        // neighbouring samples on a sphere of the body's equatorial radius.
        std::vector<LevelImage> images;
        for (int f = 1; f <= kCubeFaceCount; ++f) {
            const SampleSpacing spacing = [f, N, a, n = grids[0]->n()](int tx, int ty, int i, int j) {
                const double u = 2.0 * static_cast<double>(int64_t{tx} * n + i) / static_cast<double>(N) - 1.0;
                const double v = 2.0 * static_cast<double>(int64_t{ty} * n + j) / static_cast<double>(N) - 1.0;
                const double h = 2.0 / static_cast<double>(N);
                const auto gap = [a](const std::array<double, 3>& p, const std::array<double, 3>& q) {
                    const auto up = unit(p), uq = unit(q);
                    return a * std::sqrt((up[0] - uq[0]) * (up[0] - uq[0]) + (up[1] - uq[1]) * (up[1] - uq[1]) +
                                         (up[2] - uq[2]) * (up[2] - uq[2])) / 2.0;
                };
                return std::array<double, 2>{gap(faceDirection(f, u + h, v), faceDirection(f, u - h, v)),
                                             gap(faceDirection(f, u, v + h), faceDirection(f, u, v - h))};
            };
            images.push_back(elevationImage(*grids[static_cast<size_t>(f - 1)], paint, spacing));
        }
        writeCross(png, images);
    } else {
        // Heights under the pixel centres, three rows at a time for the slopes.
        const auto heights = [&](int64_t row) {
            const std::vector<Located> at = locateRow(body, row, width, height);
            std::vector<double> z(at.size());
            for (size_t c = 0; c < at.size(); ++c) {
                const double x = (at[c].u + 1.0) / 2.0 * static_cast<double>(N);
                const double y = (at[c].v + 1.0) / 2.0 * static_cast<double>(N);
                z[c] = grids[static_cast<size_t>(at[c].face - 1)]->bilinear(x, y);
            }
            return z;
        };
        std::vector<double> north, here = heights(0), south = height > 1 ? heights(1) : here;
        north = here;
        std::vector<uint8_t> row(static_cast<size_t>(width) * 3);
        const double dLongitude = 2.0 * std::numbers::pi / static_cast<double>(width);
        const double dLatitude = std::numbers::pi / static_cast<double>(height);
        for (int64_t r = 0; r < height; ++r) {
            const double latitude = latitudeOf(r, height) * std::numbers::pi / 180.0;
            const double dx = 2.0 * a * std::max(std::cos(latitude), 1e-9) * dLongitude;
            const double dy = a * dLatitude * static_cast<double>((r > 0) + (r + 1 < height));
            for (int64_t c = 0; c < width; ++c) {
                const auto k = static_cast<size_t>(c);
                const size_t west = static_cast<size_t>((c + width - 1) % width), east = static_cast<size_t>((c + 1) % width);
                double dzdx = 0.0, dzdy = 0.0;
                if (paint.shading()) {
                    dzdx = (here[east] - here[west]) / dx;
                    dzdy = dy > 0.0 ? (north[k] - south[k]) / dy : 0.0;
                }
                const Rgb8 colour = paint.colour(here[k], dzdx, dzdy);
                std::copy(colour.begin(), colour.end(), row.begin() + static_cast<std::ptrdiff_t>(k * 3));
            }
            png.writeRow(row.data());
            north = std::move(here);
            here = std::move(south);
            south = r + 2 < height ? heights(r + 2) : here;
        }
    }
    for (const auto& rowBytes : legend) {
        png.writeRow(rowBytes.data());
    }
    png.commit();
    return report;
}

PreviewReport colourPlanet(const PlanetFaces& faces, const std::vector<PyramidSet>& sets, const std::string& output,
                           const PreviewOptions& o, PreviewProjection projection, const PlanetBody& body) {
    checkColourStyle(o, faces.describe());
    std::vector<std::shared_ptr<OrthoProducer>> producers;
    for (const PyramidSet& s : sets) {
        producers.push_back(openOrthoSet(s));
    }
    const int level = planetLevel(o, faces, sets,
                                  [&](size_t k, int l) { return orthoLevelSide(producers[k]->header(), l); });
    const auto cache = static_cast<size_t>(4 * (int64_t{1} << level) + 8);
    std::vector<std::unique_ptr<ColourGrid>> grids;
    for (size_t k = 0; k < sets.size(); ++k) {
        grids.push_back(std::make_unique<ColourGrid>(sets[k], producers[k], level, cache));
        if (grids.back()->channels() != grids[0]->channels()) {
            fail(faces.files[k], "has " + std::to_string(grids.back()->channels()) + " channels, not face 1's " +
                                     std::to_string(grids[0]->channels()));
        }
    }
    const int C = grids[0]->channels();
    const int64_t N = grids[0]->side(); // pixels a face side
    PreviewReport report;
    report.kind = grids[0]->residuals() ? "colour residuals" : "ortho";
    report.style = "colours";
    report.level = level;
    report.projection = previewProjectionName(projection);
    report.body = body.describe();
    report.maximum = 255.0;
    report.width = static_cast<int>(4 * N);
    report.height = static_cast<int>((projection == PreviewProjection::Cube ? 3 : 2) * N);
    PngWriter png(output, report.width, report.height, C, 8, previewText(faces.describe(), report));
    if (projection == PreviewProjection::Cube) {
        std::vector<LevelImage> images;
        for (auto& g : grids) {
            images.push_back(colourImage(*g));
        }
        writeCross(png, images);
    } else {
        std::vector<uint8_t> row(static_cast<size_t>(report.width) * static_cast<size_t>(C));
        for (int64_t r = 0; r < report.height; ++r) {
            const std::vector<Located> at = locateRow(body, r, report.width, report.height);
            for (size_t c = 0; c < at.size(); ++c) {
                // Pixel k's centre lies at u = (2k + 1) / N - 1.
                const double x = (at[c].u + 1.0) / 2.0 * static_cast<double>(N) - 0.5;
                const double y = (at[c].v + 1.0) / 2.0 * static_cast<double>(N) - 0.5;
                grids[static_cast<size_t>(at[c].face - 1)]->bilinear(x, y, row.data() + c * static_cast<size_t>(C));
            }
            png.writeRow(row.data());
        }
    }
    png.commit();
    return report;
}

} // namespace

PreviewReport planetPreview(const PlanetFaces& faces, const std::string& output, const PreviewOptions& o,
                            PreviewProjection projection) {
    const PlanetBody body = PlanetBody::parse(o.body);
    std::vector<PyramidSet> sets;
    for (const std::string& file : faces.files) {
        sets.push_back(openPyramidSet(file));
        if (sets.back().kind != sets[0].kind) {
            fail(file, std::string("holds a ") + kindName(sets.back().kind) + " pyramid, face 1 a " +
                           kindName(sets[0].kind) + " one");
        }
    }
    PreviewReport report = sets[0].kind == PyramidKind::Residual
                               ? elevationPlanet(faces, sets, output, o, projection, body)
                               : colourPlanet(faces, sets, output, o, projection, body);
    report.faces.assign(faces.files.begin(), faces.files.end());
    return report;
}

} // namespace pyramid::preview
