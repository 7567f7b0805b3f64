// Tiles per second of the CPU runtime: residual tiles decoded (ResidualProducer, every tile of
// the file) and elevation tiles produced (ElevationProducer, every tile of the quadtree, each
// after its parent, for n = tileSize and n = 24), on one thread and on all threads.
//
//   runtime_bench [--n N] [DEM.dat ...]
//
// --n N: only the elevation tiles of N samples (no residual pass), e.g. to profile one of them.
//
// Without arguments: the original tools' tests/data/proland/DEM.dat, then a larger pyramid that
// encodeDem builds first from a synthetic 4097 x 4097 DEM in a temporary directory, then real
// terrain not tuned on, Mt Rainier's SRTM tile (../shared/fixtures/inputs, when it is there),
// encoded with the default Deflate tiles and with context coding.
#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "formats/error.hpp"
#include "formats/residual_codec.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/support/parallel.hpp"
#include "libpyramid/runtime/residual_producer.hpp"

namespace {

using namespace pyramid;
namespace fs = std::filesystem;

constexpr size_t kCacheTiles = 64; // elevation tiles cached by each producer
constexpr double kMinSeconds = 1.0; // each measurement repeats its pass until this much time passed

struct Tile {
    int level, tx, ty;
};

// Passes of `pass` (which returns the tiles it handled) until kMinSeconds have passed: tiles/s.
double rate(const std::function<int64_t()>& pass) {
    int64_t tiles = 0;
    const auto start = std::chrono::steady_clock::now();
    std::chrono::duration<double> seconds{};
    do {
        tiles += pass();
        seconds = std::chrono::steady_clock::now() - start;
    } while (seconds.count() < kMinSeconds);
    return static_cast<double>(tiles) / seconds.count();
}

double residualRate(const std::string& path, int threads) {
    const ResidualProducer residuals(path);
    std::vector<Tile> tiles;
    for (int level = 0; level <= residuals.maxLevel(); ++level) {
        const int side = 1 << std::max(0, level - residuals.header().minLevel);
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                if (residuals.hasTile(level, tx, ty)) {
                    tiles.push_back({level, tx, ty});
                }
            }
        }
    }
    return rate([&] {
        parallelFor(static_cast<int64_t>(tiles.size()), threads, [&](int64_t i) {
            const Tile& t = tiles[static_cast<size_t>(i)];
            residuals.tile(t.level, t.tx, t.ty);
        });
        return static_cast<int64_t>(tiles.size());
    });
}

// Every tile of the subtree of (level, tx, ty) down to `last`, depth first (as a renderer descends).
int64_t walk(ElevationProducer& producer, int level, int tx, int ty, int last) {
    producer.tile(level, tx, ty);
    int64_t tiles = 1;
    if (level < last) {
        for (int q = 0; q < 4; ++q) {
            tiles += walk(producer, level + 1, 2 * tx + (q & 1), 2 * ty + (q >> 1), last);
        }
    }
    return tiles;
}

// A fresh producer per pass (nothing cached from the last one), with a cache of kCacheTiles: the
// tiles of the last pass are filled again (runtime/tile_pool.hpp), as an engine's producer fills
// the tiles its cache evicts. The levels above `split` are
// produced first; the subtrees of level `split` are then the threads' work items.
double elevationRate(const std::string& path, int n, int threads) {
    const ResidualHeader h = ResidualFileReader::open(path)->header();
    ResidualProducerOptions ro;
    ro.delta = elevationDelta(h, n);
    auto residuals = std::make_shared<const ResidualProducer>(path, std::vector<std::string>{}, ro);
    ElevationProducerOptions eo;
    eo.tileSize = n;
    eo.cacheCapacity = kCacheTiles;
    const int last = ElevationProducer(residuals, eo).maxLevel();
    int split = 0;
    while (split < last && (int64_t{1} << (2 * split)) < 8 * threads) {
        ++split;
    }
    const int side = 1 << split;
    return rate([&] {
        ElevationProducer producer(residuals, eo);
        int64_t above = 0;
        for (int level = 0; level < split; ++level) {
            for (int t = 0; t < (1 << (2 * level)); ++t) {
                producer.tile(level, t % (1 << level), t >> level);
                ++above;
            }
        }
        std::vector<int64_t> below(static_cast<size_t>(side) * side, 0);
        parallelFor(static_cast<int64_t>(below.size()), threads, [&](int64_t i) {
            below[static_cast<size_t>(i)] = walk(producer, split, static_cast<int>(i % side), static_cast<int>(i / side), last);
        });
        for (int64_t b : below) {
            above += b;
        }
        return above;
    });
}

// A deterministic synthetic DEM (smooth hills plus finer ripples), written as a float32 TIFF.
void writeSyntheticDem(const std::string& path, int size) {
    auto out = OIIO::ImageOutput::create(path);
    const OIIO::ImageSpec spec(size, size, 1, OIIO::TypeDesc::FLOAT);
    if (!out || !out->open(path, spec)) {
        fail(path, "cannot write: " + OIIO::geterror());
    }
    std::vector<float> row(static_cast<size_t>(size));
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const double u = static_cast<double>(x) / size, v = static_cast<double>(y) / size;
            double h = 1500.0;
            for (int octave = 0; octave < 8; ++octave) {
                const double f = 3.0 * (1 << octave);
                h += 900.0 / (1 << octave) * std::sin(f * u * 6.2831853 + octave) * std::cos(f * v * 5.123 + 2.0 * octave);
            }
            row[static_cast<size_t>(x)] = static_cast<float>(h);
        }
        if (!out->write_scanline(y, 0, OIIO::TypeDesc::FLOAT, row.data())) {
            fail(path, "write failed: " + out->geterror());
        }
    }
    if (!out->close()) {
        fail(path, "close failed: " + out->geterror());
    }
}

// True when elevation tiles of n samples can be produced from the file (n = tileSize / 2^k, k <= minLevel).
bool producible(const ResidualHeader& h, int n) {
    for (int k = 0; k <= h.minLevel; ++k) {
        if ((h.tileSize >> k) == n && (n << k) == h.tileSize) {
            return true;
        }
    }
    return false;
}

int onlyN = 0; // --n

void bench(const std::string& path) {
    const ResidualHeader h = ResidualFileReader::open(path)->header();
    const int all = omp_get_max_threads();
    std::printf("%s: tileSize %d, minLevel %d, maxLevel %d, %lld tiles\n", path.c_str(), h.tileSize, h.minLevel,
                h.maxLevel, static_cast<long long>(h.tileCount()));
    std::printf("  %-26s %14s %14s\n", "tiles per second", "1 thread", (std::to_string(all) + " threads").c_str());
    if (onlyN == 0) {
        std::printf("  %-26s %14.0f %14.0f\n", "residual tiles decoded", residualRate(path, 1), residualRate(path, all));
    }
    for (int n : {static_cast<int>(h.tileSize), 24}) {
        if (!producible(h, n) || (onlyN != 0 && n != onlyN)) {
            continue;
        }
        const std::string label = "elevation tiles n = " + std::to_string(n);
        std::printf("  %-26s %14.0f %14.0f\n", label.c_str(), elevationRate(path, n, 1), elevationRate(path, n, all));
    }
}

} // namespace

int main(int argc, char** argv) {
    try {
        int first = 1;
        if (argc > 2 && std::string(argv[1]) == "--n") {
            onlyN = std::stoi(argv[2]);
            first = 3;
        }
        if (argc > first) {
            for (int i = first; i < argc; ++i) {
                bench(argv[i]);
            }
            return 0;
        }
        bench(std::string(PYRAMID_TEST_DATA) + "/proland/DEM.dat");
        struct TempDir {
            fs::path path = fs::temp_directory_path() / ("pyramid-runtime-bench-" + std::to_string(getpid()));
            TempDir() { fs::create_directories(path); }
            ~TempDir() { fs::remove_all(path); }
        } temp;
        const fs::path& dir = temp.path;
        const std::string input = (dir / "synthetic.tif").string(), output = (dir / "DEM.dat").string();
        writeSyntheticDem(input, 4097);
        DemEncodeOptions options;
        const DemReport report = encodeDem(input, output, options);
        std::printf("(encodeDem: 4097 x 4097 synthetic DEM in %.1f s)\n", report.seconds);
        bench(output);
        // Real terrain, not tuned on: Mt Rainier's SRTM tile, beside the checkout, with the
        // default (Deflate) tiles and with context coding.
        const std::string rainier = std::string(PYRAMID_SHARED_FIXTURES) + "/inputs/mt_rainier_90m.tif";
        if (!fs::exists(rainier)) {
            std::printf("(no %s: the real terrain files skipped)\n", rainier.c_str());
            return 0;
        }
        for (const ResidualCodec codec : {ResidualCodec::Deflate, ResidualCodec::Context}) {
            DemEncodeOptions real;
            real.tiles.codec = codec;
            const std::string file = (dir / (codec == ResidualCodec::Deflate ? "rainier.dat" : "rainier-context.dat")).string();
            encodeDem(rainier, file, real);
            bench(file);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
}
