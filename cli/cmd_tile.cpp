// `pyramid tile SET LEVEL TX TY -o OUT [--residual]`: one tile out of a pyramid file or a region
// set (its main file, index or directory), served by the deepest file that holds it.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli/cli_common.hpp"
#include "formats/atomic_file.hpp"
#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_kind.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/input/image_io_module.hpp"
#include "libpyramid/input/pyramid_georeference.hpp"
#include "libpyramid/preview/png_writer.hpp"
#include "libpyramid/preview/preview.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/normal_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid::cli {

namespace {

// A tile as rows of samples, row 0 = the tile's bottom row (the stored order).
struct TileData {
    int side = 0;
    int channels = 1;
    SampleType type = SampleType::Float32;
    std::vector<uint8_t> bytes;
};

// Elevations or residuals as a 16-bit grey PNG, north up: the tile's smallest finite value is 0,
// its largest 65535 (non-finite values 0), and the range is in the PNG's text ("Minimum",
// "Maximum") so that a value can be read back: v = min + grey / 65535 * (max - min).
void writeNormalisedPng(const TileData& tile, const std::string& path, bool isFloat) {
    const size_t count = static_cast<size_t>(tile.side) * static_cast<size_t>(tile.side);
    std::vector<double> values(count);
    for (size_t k = 0; k < count; ++k) {
        if (isFloat) {
            float v;
            std::memcpy(&v, tile.bytes.data() + k * sizeof(float), sizeof(float));
            values[k] = v;
        } else {
            int16_t v;
            std::memcpy(&v, tile.bytes.data() + k * sizeof(int16_t), sizeof(int16_t));
            values[k] = v;
        }
    }
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const double v : values) {
        if (std::isfinite(v)) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    if (!(lo <= hi)) {
        lo = hi = 0.0;
    }
    const double span = hi > lo ? hi - lo : 1.0;
    PngWriter png(path, tile.side, tile.side, 1, 16,
                  {{"Software", "libpyramid pyramid tile"},
                   {"Samples", isFloat ? "elevations" : "residuals"},
                   {"Minimum", exactNumberText(lo)},
                   {"Maximum", exactNumberText(hi)}});
    std::vector<uint16_t> row(static_cast<size_t>(tile.side));
    for (int j = tile.side - 1; j >= 0; --j) {
        for (int i = 0; i < tile.side; ++i) {
            const double v = values[static_cast<size_t>(j) * static_cast<size_t>(tile.side) + static_cast<size_t>(i)];
            row[static_cast<size_t>(i)] =
                std::isfinite(v) ? static_cast<uint16_t>(std::lround((v - lo) / span * 65535.0)) : uint16_t{0};
        }
        png.writeRow16(row.data());
    }
    png.commit();
}

// Raw files keep the stored order (row 0 = bottom); images are written north-up.
void writeTile(const TileData& tile, const std::string& path) {
    const std::string ext = lowerExtension(path);
    const bool isFloat = tile.type == SampleType::Float32;
    const bool isInt16 = tile.type == SampleType::Int16;
    const bool isByte = tile.type == SampleType::UInt8;
    if (ext == ".f32" || ext == ".i16" || ext == ".u8") {
        const bool matches = (ext == ".f32" && isFloat) || (ext == ".i16" && isInt16) || (ext == ".u8" && isByte);
        if (!matches) {
            fail(path, std::string("this tile holds ") + (isFloat ? "float32 (.f32)" : isInt16 ? "int16 (.i16)" : "bytes (.u8)") +
                           " samples, not what " + ext + " holds");
        }
        AtomicFile out(path);
        out.writeAt(0, tile.bytes.data(), tile.bytes.size());
        out.commit();
        return;
    }
    if (ext != ".tif" && ext != ".tiff" && ext != ".exr" && ext != ".png") {
        fail(path, "unknown output extension '" + ext + "' (.f32, .i16, .u8, .tif, .exr or .png)");
    }
    if (ext == ".png" && !isByte) {
        writeNormalisedPng(tile, path, isFloat);
        return;
    }
    const size_t sampleBytes = isFloat ? 4 : isInt16 ? 2 : 1;
    const size_t rowBytes = static_cast<size_t>(tile.side) * static_cast<size_t>(tile.channels) * sampleBytes;
    std::vector<uint8_t> flipped(tile.bytes.size());
    for (int j = 0; j < tile.side; ++j) {
        std::copy_n(&tile.bytes[static_cast<size_t>(j) * rowBytes], rowBytes,
                    &flipped[static_cast<size_t>(tile.side - 1 - j) * rowBytes]);
    }
    // The image goes to a temporary with the same extension (the module chooses the format by
    // it), renamed into place when complete.
    AtomicFile out(path, ext);
    SampleType type = tile.type;
    const void* samples = flipped.data();
    std::vector<float> values;
    if (ext == ".exr" && !isFloat) { // EXR holds no integers: their values as float32, exactly
        values.resize(flipped.size() / sampleBytes);
        for (size_t i = 0; i < values.size(); ++i) {
            int16_t v = 0;
            if (isInt16) {
                std::memcpy(&v, &flipped[2 * i], 2);
            }
            values[i] = isInt16 ? static_cast<float>(v) : static_cast<float>(flipped[i]);
        }
        type = SampleType::Float32;
        samples = values.data();
    }
    std::string error;
    if (!imageIoModule(path).write(out.temporaryPath(), tile.side, tile.side, tile.channels, type, type, samples,
                                   error)) {
        fail(path, "cannot write the image: " + error);
    }
    out.commit();
}

TileData residualTile(const std::string& file, int level, int tx, int ty, bool raw) {
    const auto reader = ResidualFileReader::open(file);
    if (!reader->header().contains(level, tx, ty)) {
        fail(file, "no tile " + tileCoordinates(level, tx, ty));
    }
    TileData t;
    t.side = reader->header().tileSamples(level);
    if (raw) {
        const std::vector<int16_t> r = reader->readTile(level, tx, ty);
        t.type = SampleType::Int16;
        t.bytes.resize(r.size() * sizeof(int16_t));
        std::memcpy(t.bytes.data(), r.data(), t.bytes.size());
        return t;
    }
    const FileLevelProducer producer = makeFileLevelProducer(file, level, 16);
    const auto tile = producer.fileTile(level, tx, ty);
    t.type = SampleType::Float32;
    t.bytes.resize(tile->zf.size() * sizeof(float));
    std::memcpy(t.bytes.data(), tile->zf.data(), t.bytes.size());
    return t;
}

TileData orthoTile(const std::string& file, int level, int tx, int ty) {
    const auto reader = OrthoFileReader::open(file);
    TileData t;
    t.side = reader->header().tilePixels();
    t.channels = reader->header().channels;
    t.type = SampleType::UInt8;
    t.bytes = reader->readTile(level, tx, ty);
    return t;
}

// A tile of a region set: LEVEL, TX and TY are absolute (the main file's).
TileData setTile(const PyramidSet& set, int level, int tx, int ty, bool raw) {
    TileData t;
    if (set.kind == PyramidKind::Ortho) {
        const auto producer = openOrthoSet(set);
        t.side = producer->header().tilePixels();
        t.channels = producer->header().channels;
        t.type = SampleType::UInt8;
        t.bytes = producer->tile(level, tx, ty);
        return t;
    }
    if (raw) {
        const StoredResidualTile stored = storedResidualTile(set, level, tx, ty);
        t.side = stored.side;
        t.type = SampleType::Int16;
        t.bytes.resize(stored.residuals.size() * sizeof(int16_t));
        std::memcpy(t.bytes.data(), stored.residuals.data(), t.bytes.size());
        return t;
    }
    if (!residualSetHolds(set, level, tx, ty)) {
        fail(set.name(), "no tile " + tileCoordinates(level, tx, ty) + " in any file of the set");
    }
    const FileLevelProducer producer = makeSetLevelProducer(set, level, 16);
    const auto tile = producer.fileTile(level, tx, ty);
    t.side = tile->size;
    t.type = SampleType::Float32;
    t.bytes.resize(tile->zf.size() * sizeof(float));
    std::memcpy(t.bytes.data(), tile->zf.data(), t.bytes.size());
    return t;
}

// The normals of the elevation tile at file level LEVEL (a set's absolute level), by the CPU
// normal producer over the file's (or set's) elevations: (n+1)^2 x 4 floats, row 0 = south.
TileData normalTile(const std::string& path, int level, int tx, int ty, Deformation deformation, double size) {
    const PyramidSet set = openPyramidSet(path);
    if (set.kind != PyramidKind::Residual) {
        fail("--normals", "apply to residual (DEM) files only");
    }
    const ResidualHeader h = ResidualFileReader::readHeader(set.main);
    if (!residualSetHolds(set, level, tx, ty)) {
        fail(set.name(), "no tile " + tileCoordinates(level, tx, ty));
    }
    if (size <= 0.0 && deformation == Deformation::Plane) {
        // The root quad's side on the ground, from the georeference sidecar.
        size = groundSpacing(set.main, 0)[0] * static_cast<double>(h.tileSize >> h.minLevel);
        if (!(size > 0.0)) {
            fail("--normals", "the ground size of " + set.name() + " is unknown (no " +
                                  georeferenceSidecarPath(set.main) + "): give --size, the root quad's side in height units");
        }
    }
    const FileLevelProducer producer = makeSetLevelProducer(set, level, 16);
    NormalProducerOptions o;
    o.deformation = deformation;
    o.size = size;
    o.cacheCapacity = 4;
    NormalProducer normals(producer.producer, o);
    const auto tile = normals.tile(level - producer.delta, tx, ty);
    TileData t;
    t.side = tile->size;
    t.channels = 4;
    t.type = SampleType::Float32;
    t.bytes.resize(tile->normals.size() * sizeof(float));
    std::memcpy(t.bytes.data(), tile->normals.data(), t.bytes.size());
    return t;
}

// Normals as an RGBA8 PNG, north up: (nx, ny, ncx, ncy) each mapped from -1..1 to 0..255 as
// (v + 1) / 2 * 255, rounded (the seeds' integer normal tiles).
void writeNormalPng(const TileData& tile, const std::string& path) {
    PngWriter png(path, tile.side, tile.side, 4, 8,
                  {{"Software", "libpyramid pyramid tile"}, {"Samples", "normals (nx, ny, ncx, ncy), (v + 1) / 2 * 255"}});
    std::vector<uint8_t> row(static_cast<size_t>(tile.side) * 4);
    for (int j = tile.side - 1; j >= 0; --j) {
        for (size_t k = 0; k < row.size(); ++k) {
            float v;
            std::memcpy(&v, tile.bytes.data() + (static_cast<size_t>(j) * row.size() + k) * sizeof(float), sizeof(float));
            row[k] = static_cast<uint8_t>(std::lround(std::clamp((static_cast<double>(v) + 1.0) / 2.0, 0.0, 1.0) * 255.0));
        }
        png.writeRow(row.data());
    }
    png.commit();
}

} // namespace

CommandRunner setupTileCommand(CLI::App& app) {
    struct Args {
        std::string file, output;
        int level = 0, tx = 0, ty = 0;
        bool residual = false;
        bool hillshade = false;
        PreviewOptions shading;
        bool normals = false;
        std::string deform = "plane";
        double size = 0.0;
    };
    auto a = std::make_shared<Args>();
    app.add_option("FILE", a->file,
                   "Residual (DEM) or ortho pyramid file, or a region set (its main file, index or directory)")
        ->required();
    app.add_option("LEVEL", a->level, "Tile level in the file (0 = the file's root; a set's absolute level)")
        ->required();
    app.add_option("TX", a->tx, "Tile column, 0 = west")->required();
    app.add_option("TY", a->ty, "Tile row, 0 = south")->required();
    app.add_option("-o,--output", a->output,
                   "Output: .f32/.i16/.u8 raw little-endian, row 0 = the tile's bottom row; .tif/.exr/.png "
                   "images, north up")
        ->required();
    app.add_flag("--residual", a->residual, "Residual files: the stored int16 residuals instead of the elevations");
    auto* hillshade = app.add_flag("--hillshade", a->hillshade,
                                   "Elevations to .png: a hillshade over hypsometric colours (as pyramid preview draws a "
                                   "level) instead of 16-bit grey");
    app.add_option("--spacing", a->shading.spacing,
                   "With --hillshade: ground distance between samples in height units (default: from "
                   "FILE.georef.json in metres, else 1)")
        ->needs(hillshade);
    app.add_option("--z-factor", a->shading.zFactor, "With --hillshade: heights are multiplied by this")
        ->capture_default_str()
        ->needs(hillshade);
    auto* normals = app.add_flag("--normals", a->normals,
                                 "Residual files: the tile's normals, (n+1)^2 x (nx, ny, ncx, ncy) float32 (.png: RGBA8, "
                                 "(v + 1) / 2 * 255), as the normal producer makes them")
                        ->excludes(hillshade);
    app.add_option("--deform", a->deform, "With --normals: plane, or sphere (a cube face of a planet)")
        ->capture_default_str()
        ->check(CLI::IsMember({"plane", "sphere"}))
        ->needs(normals);
    app.add_option("--size", a->size,
                   "With --normals: the root quad's side (plane; default: from FILE.georef.json, in metres) or the "
                   "sphere's radius (default 6378137), in height units")
        ->needs(normals);
    app.footer("A residual file gives the reconstructed elevations of file tile (LEVEL, TX, TY), (size+5)^2 float32 "
               "samples with their borders, exactly as the CPU elevation producer rebuilds them; an ortho file gives "
               "the decoded tile, pixels^2 x channels bytes. A region set serves each tile from the deepest file "
               "that holds it.");
    return [a]() {
        if (a->hillshade) {
            if (a->residual) {
                fail("--hillshade", "draws elevations, not the stored residuals (--residual)");
            }
            if (lowerExtension(a->output) != ".png") {
                fail(a->output, "--hillshade draws a PNG: name it OUT.png");
            }
        }
        if (a->normals) {
            if (a->residual) {
                fail("--normals", "come from the elevations, not the stored residuals (--residual)");
            }
            const Deformation deformation = a->deform == "sphere" ? Deformation::Sphere : Deformation::Plane;
            const double size = a->size > 0.0 ? a->size : deformation == Deformation::Sphere ? 6378137.0 : 0.0;
            const TileData shading = normalTile(a->file, a->level, a->tx, a->ty, deformation, size);
            if (lowerExtension(a->output) == ".png") {
                writeNormalPng(shading, a->output);
            } else {
                writeTile(shading, a->output);
            }
            return kExitOk;
        }
        TileData tile;
        if (!findRegionIndex(a->file).empty()) {
            const PyramidSet set = openPyramidSet(a->file);
            if (a->residual && set.kind != PyramidKind::Residual) {
                fail("--residual", "applies to residual (DEM) files only");
            }
            tile = setTile(set, a->level, a->tx, a->ty, a->residual);
        } else if (detectPyramidKind(a->file) == PyramidKind::Residual) {
            tile = residualTile(a->file, a->level, a->tx, a->ty, a->residual);
        } else {
            if (a->residual) {
                fail("--residual", "applies to residual (DEM) files only");
            }
            tile = orthoTile(a->file, a->level, a->tx, a->ty);
        }
        if (a->hillshade) {
            if (tile.type != SampleType::Float32) {
                fail("--hillshade", "draws elevations; " + a->file + " holds orthos");
            }
            std::vector<float> heights(tile.bytes.size() / sizeof(float));
            std::memcpy(heights.data(), tile.bytes.data(), tile.bytes.size());
            const std::string main = findRegionIndex(a->file).empty() ? a->file : openPyramidSet(a->file).main;
            writeTilePreview(heights, tile.side, main, a->level, a->output, a->shading);
            return kExitOk;
        }
        writeTile(tile, a->output);
        return kExitOk;
    };
}

} // namespace pyramid::cli
