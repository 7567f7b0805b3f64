// ERDAS Imagine files (input/hfa_reader.hpp): GDAL's files of a window of samples/dem.tif, stored
// and run-length compressed, read back its samples, nodata and placement and build the pyramid of
// a GeoTIFF of them; without the ESRI WKT (ProjectionX) the projection parameters and datum place
// a file alike (UTM and geographic), and an unknown datum leaves it unplaced; imagery's three
// layers interleave as the GeoTIFF's channels, in windows across blocks read by many threads;
// blocks decode as the format lays them out (packed pixels, runs, values of 0 to 32 bits, the low
// bits of signed values); damaged files are refused, each in one line naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/hfa_blocks.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/gdal_window.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sidecar_files.hpp"
#include "tests/support/small_dem.hpp"

namespace pyramid {
namespace {

std::string errorOf(const std::string& path) {
    return test::errorMessage([&] { RasterSource::open(path)->info(); });
}

uint32_t le32(const std::vector<uint8_t>& b, size_t at) {
    return uint32_t{b[at]} | (uint32_t{b[at + 1]} << 8) | (uint32_t{b[at + 2]} << 16) | (uint32_t{b[at + 3]} << 24);
}

void put32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
    for (int k = 0; k < 4; ++k) {
        b[at + static_cast<size_t>(k)] = static_cast<uint8_t>(v >> (8 * k));
    }
}

// Where the entry of the node named `name` begins (its name lies 24 bytes in).
size_t entryOf(const std::vector<uint8_t>& bytes, const std::string& name) {
    const std::string key = name + std::string(1, '\0');
    const auto it = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
    EXPECT_NE(it, bytes.end()) << name;
    return static_cast<size_t>(it - bytes.begin()) - 24;
}

// `bytes` with node `from`'s name made `to` (as long, or shorter and NUL-padded).
std::vector<uint8_t> renamed(std::vector<uint8_t> bytes, const std::string& from, const std::string& to) {
    const size_t name = entryOf(bytes, from) + 24;
    std::fill_n(bytes.begin() + static_cast<std::ptrdiff_t>(name), 64, 0);
    std::copy(to.begin(), to.end(), bytes.begin() + static_cast<std::ptrdiff_t>(name));
    return bytes;
}

TEST(Hfa, GdalsFilesReadAsTheirTiff) {
    const std::vector<float> window = test::gdalWindow(true); // GDAL's -ot Int16
    test::TempDir dir;
    test::writeGeoTiff(dir.file("window.tif"), 65, 65, window, test::projectedTags(32610, 500000.0, 5200000.0, 40.0));
    DemEncodeOptions o = test::smallDemOptions();
    encodeDem(dir.file("window.tif"), dir.file("tif.dat"), o);
    for (const char* name : {"gdal/window-i16.img", "gdal/window-i16-rle.img", "gdal/window-i16-spill.img"}) {
        SCOPED_TRACE(name);
        const std::string path = test::dataPath(name);
        const auto img = RasterSource::open(path);
        EXPECT_EQ(img->info().formatName, "hfa");
        EXPECT_EQ(img->info().type, SampleType::Int16);
        EXPECT_EQ(img->info().nodata, -9999.0);
        test::expectGdalWindow(*img, window);
        EXPECT_EQ(RasterSource::describe(path).georeference->pixelToCrs, test::kGdalWindowPlace);

        // The pyramid and placement of a GeoTIFF of the same samples, byte for byte.
        encodeDem(path, dir.file("img.dat"), o);
        EXPECT_EQ(test::readFile(dir.file("img.dat")), test::readFile(dir.file("tif.dat")));
        EXPECT_EQ(test::placementOf(dir.file("img.dat")), test::placementOf(dir.file("tif.dat")));
    }
}

TEST(Hfa, ProjectionParametersPlaceAFileWithoutItsWkt) {
    test::TempDir dir;
    // UTM zone 10 north on WGS 84: proNumber 1, proZone 10.
    const std::vector<uint8_t> utm = renamed(test::bytesOf(test::dataPath("gdal/window-i16.img")), "ProjectionX", "Unused");
    test::writeBytes(dir.file("utm.img"), utm);
    auto g = RasterSource::open(dir.file("utm.img"))->info().georeference;
    ASSERT_TRUE(g);
    EXPECT_EQ(g->epsg, 32610);
    EXPECT_EQ(g->pixelToCrs, test::kGdalWindowPlace);

    // Geographic on WGS 84: proNumber 0.
    test::writeBytes(dir.file("geo.img"),
                     renamed(test::bytesOf(test::dataPath("gdal/bluemarble-rle.img")), "ProjectionX", "Unused"));
    g = RasterSource::open(dir.file("geo.img"))->info().georeference;
    ASSERT_TRUE(g);
    EXPECT_EQ(g->epsg, 4326);
    const std::array<double, 6> geo = {-30.0, 0.1, 0.0, 40.0, 0.0, -0.1};
    for (size_t k = 0; k < 6; ++k) {
        EXPECT_NEAR(g->pixelToCrs[k], geo[k], 1e-12) << k;
    }

    // A datum this reader has no code for: unplaced, as without a CRS.
    std::vector<uint8_t> other = utm;
    const std::string wgs = "WGS 84";
    const size_t datum = le32(other, entryOf(other, "Datum") + 16);
    const auto at = std::search(other.begin() + static_cast<std::ptrdiff_t>(datum), other.end(), wgs.begin(), wgs.end());
    ASSERT_NE(at, other.end());
    std::copy_n("Airy  ", 6, at);
    test::writeBytes(dir.file("other.img"), other);
    EXPECT_FALSE(RasterSource::open(dir.file("other.img"))->info().georeference);
}

void expectBlueMarbleCrop(const RasterSource& img);

TEST(Hfa, ImageryLayersAreTheChannels) {
    // Compressed blocks in the .img, and blocks stacked in a spill file (.ige), layer by layer.
    for (const char* name : {"gdal/bluemarble-rle.img", "gdal/bluemarble-spill.img"}) {
        SCOPED_TRACE(name);
        expectBlueMarbleCrop(*RasterSource::open(test::dataPath(name)));
    }
}

// The three layers of GDAL's Imagine files of bluemarble-crop.tif read as its channels.
void expectBlueMarbleCrop(const RasterSource& img) {
    const auto tif = RasterSource::open(test::dataPath("gdal/bluemarble-crop.tif"));
    ASSERT_EQ(img.info().channels, 3);
    EXPECT_EQ(img.info().type, SampleType::UInt8);
    ASSERT_EQ(img.info().width, 70);
    ASSERT_EQ(img.info().height, 50);
    for (int c = 0; c < 3; ++c) {
        std::vector<float> a(70 * 50), b(70 * 50);
        img.readFloat(0, 0, 70, 50, c, a.data());
        tif->readFloat(0, 0, 70, 50, c, b.data());
        EXPECT_EQ(a, b) << "channel " << c;
    }
    std::vector<uint16_t> a(70 * 50 * 3), b(70 * 50 * 3);
    img.readUInt16(0, 0, 70, 50, 0, 3, a.data());
    tif->readUInt16(0, 0, 70, 50, 0, 3, b.data());
    EXPECT_EQ(a, b);
}

// Windows of many shapes across the blocks' edges (GDAL's 64 x 64 blocks: two across), read by
// eight threads at once, each as the GeoTIFF crop's: as floats per channel, as 16-bit and 8-bit
// ranges of channels, and rows stored bottom up.
TEST(Hfa, WindowsAcrossBlocksFromManyThreadsReadAsTheTiff) {
    const auto img = RasterSource::open(test::dataPath("gdal/bluemarble-rle.img"), 1);
    const auto tif = RasterSource::open(test::dataPath("gdal/bluemarble-crop.tif"));
    struct Window {
        int x0, y0, x1, y1;
    };
    std::vector<Window> windows;
    for (int x0 : {0, 30, 63, 64, 69}) {
        for (int y0 : {0, 17, 49}) {
            for (const auto& [w, h] : {std::pair{1, 1}, std::pair{7, 33}, std::pair{70, 50}}) {
                windows.push_back({x0, y0, std::min(70, x0 + w), std::min(50, y0 + h)});
            }
        }
    }
    const auto differences = [&](const Window& w, int c0, int c1) {
        const size_t n = static_cast<size_t>(w.x1 - w.x0) * static_cast<size_t>(w.y1 - w.y0);
        const auto row = static_cast<std::ptrdiff_t>(w.x1 - w.x0) * (c1 - c0);
        int found = 0;
        std::vector<float> fa(n), fb(n);
        img->readFloat(w.x0, w.y0, w.x1, w.y1, c0, fa.data());
        tif->readFloat(w.x0, w.y0, w.x1, w.y1, c0, fb.data());
        found += fa != fb;
        std::vector<uint16_t> ua(n * static_cast<size_t>(c1 - c0)), ub(ua.size());
        img->readUInt16(w.x0, w.y0, w.x1, w.y1, c0, c1, ua.data());
        tif->readUInt16(w.x0, w.y0, w.x1, w.y1, c0, c1, ub.data());
        found += ua != ub;
        std::vector<uint8_t> ba(ua.size()), bb(ua.size());
        img->readUInt8(w.x0, w.y0, w.x1, w.y1, c0, c1, ba.data() + (ba.size() - static_cast<size_t>(row)), -row);
        tif->readUInt8(w.x0, w.y0, w.x1, w.y1, c0, c1, bb.data() + (bb.size() - static_cast<size_t>(row)), -row);
        found += ba != bb;
        return found;
    };
    std::atomic<int> found{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 8; ++t) {
        threads.emplace_back([&, t] {
            for (size_t k = 0; k < windows.size(); ++k) {
                const Window& w = windows[(k + static_cast<size_t>(t) * 5) % windows.size()];
                found += differences(w, t % 3, 3) + differences(w, 0, 1 + t % 3);
            }
        });
    }
    for (std::thread& t : threads) {
        t.join();
    }
    EXPECT_EQ(found.load(), 0);
}

// A spill file (.ige) that is missing, is no spill file, or is cut short before its validity map or
// within its blocks, and a layer placed outside its stack: each refused in one line naming the
// file at fault.
TEST(Hfa, DamagedSpillFilesAreRefused) {
    test::TempDir dir;
    const std::vector<uint8_t> img = test::bytesOf(test::dataPath("gdal/window-i16-spill.img"));
    const std::vector<uint8_t> ige = test::bytesOf(test::dataPath("gdal/window-i16-spill.ige"));
    const std::string p = dir.file("window-i16-spill.img"), spill = dir.file("window-i16-spill.ige");
    const auto read = [&](const std::vector<uint8_t>& spillBytes) {
        test::writeBytes(p, img);
        test::writeBytes(spill, spillBytes);
        return test::errorMessage([&] {
            const auto source = RasterSource::open(p);
            std::vector<float> v(65 * 65);
            source->readFloat(0, 0, 65, 65, 0, v.data());
        });
    };
    EXPECT_EQ(read(ige), "");

    test::writeBytes(p, img);
    std::filesystem::remove(spill);
    EXPECT_EQ(errorOf(p), p + ": its layer \"Layer_1\" keeps its pixels in the spill file " + spill + ", which is missing");

    std::vector<uint8_t> b = ige;
    b[0] = 'X';
    EXPECT_EQ(read(b), spill + ": is no ERDAS Imagine spill file: it does not begin with ERDAS_IMG_EXTERNAL_RASTER");

    b.assign(ige.begin(), ige.begin() + 60); // past the validity map's header, short of its row
    EXPECT_EQ(read(b).rfind(spill + ": is too short for the block validity map of layer \"Layer_1\"", 0), 0u) << read(b);

    b.assign(ige.begin(), ige.end() - 100); // the last block cut short
    EXPECT_EQ(read(b), spill + ": layer \"Layer_1\"'s block 3 lies beyond the end of the file (" +
                           std::to_string(ige.size() - 100) + " bytes): a file cut short or damaged");

    // The layer's place in the stack (layerStackIndex, after the file name, the two offsets and
    // the count) beyond the stack's one layer.
    std::vector<uint8_t> bad = img;
    const size_t node = le32(bad, entryOf(bad, "ExternalRasterDMS") + 16);
    const uint32_t name = le32(bad, node); // the file name's characters, after its count and pointer
    put32(bad, node + 8 + name + 20, 1);
    test::writeBytes(p, bad);
    test::writeBytes(spill, ige);
    EXPECT_EQ(errorOf(p), p + ": its layer \"Layer_1\"'s spill file node gives it place 1 among 1 stacked layers");
}

std::vector<uint8_t> compressedBlock(uint32_t minimum, int32_t runs, int bits, const std::vector<uint8_t>& counts,
                                     const std::vector<uint8_t>& values) {
    std::vector<uint8_t> b(13);
    put32(b, 0, minimum);
    put32(b, 4, static_cast<uint32_t>(runs));
    put32(b, 8, static_cast<uint32_t>(13 + counts.size()));
    b[12] = static_cast<uint8_t>(bits);
    b.insert(b.end(), counts.begin(), counts.end());
    b.insert(b.end(), values.begin(), values.end());
    return b;
}

template <typename T>
std::vector<T> decoded(HfaPixel p, bool compressed, const std::vector<uint8_t>& stored, size_t pixels) {
    std::vector<T> out(pixels);
    decodeHfaBlock(p, compressed, stored, pixels, reinterpret_cast<uint8_t*>(out.data()), "f.img", "block 0");
    return out;
}

TEST(Hfa, BlocksDecodeAsTheFormatLaysThemOut) {
    // Packed pixels, from each byte's low bits.
    EXPECT_EQ(decoded<uint8_t>(HfaPixel::U1, false, {0xb1}, 8), (std::vector<uint8_t>{1, 0, 0, 0, 1, 1, 0, 1}));
    EXPECT_EQ(decoded<uint8_t>(HfaPixel::U2, false, {0xe4}, 4), (std::vector<uint8_t>{0, 1, 2, 3}));
    EXPECT_EQ(decoded<uint8_t>(HfaPixel::U4, false, {0x21, 0x43}, 4), (std::vector<uint8_t>{1, 2, 3, 4}));
    EXPECT_EQ(decoded<int16_t>(HfaPixel::S8, false, {0x9c, 0x05}, 2), (std::vector<int16_t>{-100, 5}));
    EXPECT_EQ(decoded<float>(HfaPixel::S32, false, {0xff, 0xff, 0xff, 0xff}, 1), (std::vector<float>{-1.0f}));

    // Runs of 3 and 2 pixels (the second length in two bytes), 8-bit values above a minimum of -5.
    EXPECT_EQ(decoded<int16_t>(HfaPixel::S16, true, compressedBlock(uint32_t(-5), 2, 8, {0x03, 0x40, 0x02}, {7, 10}), 5),
              (std::vector<int16_t>{2, 2, 2, 5, 5}));
    // No runs: every value in turn, 16 bits big-endian.
    EXPECT_EQ(decoded<uint16_t>(HfaPixel::U16, true, compressedBlock(1000, -1, 16, {}, {0x01, 0x02, 0x00, 0x05}), 2),
              (std::vector<uint16_t>{1258, 1005}));
    // An int16 value as GDAL writes it: a minimum of 0 and its 16 bits.
    EXPECT_EQ(decoded<int16_t>(HfaPixel::S16, true, compressedBlock(0, 1, 16, {0x02}, {0xff, 0xf6}), 2),
              (std::vector<int16_t>{-10, -10}));
    // 4-bit values, one per run, from each byte's low bits; 0 bits: the minimum.
    EXPECT_EQ(decoded<uint8_t>(HfaPixel::U8, true, compressedBlock(200, 2, 4, {0x01, 0x01}, {0x3a}), 2),
              (std::vector<uint8_t>{210, 203}));
    EXPECT_EQ(decoded<uint8_t>(HfaPixel::U8, true, compressedBlock(7, 1, 0, {0x03}, {}), 3), (std::vector<uint8_t>{7, 7, 7}));
    EXPECT_EQ(decoded<float>(HfaPixel::U32, true, compressedBlock(0, 1, 32, {0x01}, {0x01, 0x00, 0x00, 0x01}), 1),
              (std::vector<float>{16777216.0f}));

    // Blocks the file never wrote: nodata where the type holds it, else 0.
    std::vector<int16_t> filled(3);
    fillHfaBlock(HfaPixel::S16, -9999.0, 3, reinterpret_cast<uint8_t*>(filled.data()));
    EXPECT_EQ(filled, (std::vector<int16_t>{-9999, -9999, -9999}));
    std::vector<uint8_t> bytes(2, 9);
    fillHfaBlock(HfaPixel::U8, 300.0, 2, bytes.data());
    EXPECT_EQ(bytes, (std::vector<uint8_t>{0, 0}));

    const auto error = [](HfaPixel p, const std::vector<uint8_t>& stored, size_t pixels) {
        return test::errorMessage([&] { decoded<float>(p, true, stored, pixels); });
    };
    EXPECT_EQ(error(HfaPixel::U8, compressedBlock(0, 1, 8, {0x04}, {1}), 5),
              "f.img: block 0 is damaged: its runs hold 4 of its 5 pixels");
    EXPECT_EQ(error(HfaPixel::U8, compressedBlock(0, 2, 8, {0x04, 0x04}, {1, 2}), 5),
              "f.img: block 0 is damaged: its runs hold more than its 5 pixels");
    EXPECT_EQ(error(HfaPixel::U8, compressedBlock(0, 2, 8, {0x04}, {}), 5),
              "f.img: block 0 is damaged: its values end before its runs");
    EXPECT_EQ(error(HfaPixel::U8, compressedBlock(0, 1, 3, {0x05}, {1}), 5),
              "f.img: block 0 is damaged: its values take 3 bits, not 0, 1, 2, 4, 8, 16 or 32");
    EXPECT_EQ(error(HfaPixel::U16, compressedBlock(0, -1, 16, {}, {0, 1}), 2),
              "f.img: block 0 is damaged: its values end before its pixels");
    EXPECT_EQ(error(HfaPixel::U8, {0, 0, 0}, 5), "f.img: block 0 is damaged: its compressed header is cut short");
    EXPECT_EQ(error(HfaPixel::F32, compressedBlock(0, 1, 8, {0x01}, {1}), 1),
              "f.img: block 0 holds run-length compressed floating-point values, which this reader does not decode: "
              "convert the file to a GeoTIFF first");
}

TEST(Hfa, DamagedFilesAreRefused) {
    test::TempDir dir;
    const std::vector<uint8_t> good = test::bytesOf(test::dataPath("gdal/window-i16.img"));
    const auto refusal = [&](const std::string& name, const std::vector<uint8_t>& bytes) {
        const std::string path = dir.file(name);
        test::writeBytes(path, bytes);
        const std::string e = errorOf(path);
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
        EXPECT_THROW(RasterSource::describe(path), Error);
        return e;
    };
    const std::string p = dir.file("x.img");

    const size_t layer = entryOf(good, "Layer_1");
    const size_t dms = le32(good, entryOf(good, "RasterDMS") + 16);
    std::vector<uint8_t> b = good;
    b[le32(good, le32(good, 16) + 14)] = 'X'; // the dictionary's first byte (Ehfa_File's dictionaryPtr)
    EXPECT_EQ(refusal("x.img", b), p + ": its ERDAS Imagine structure is damaged: its dictionary lacks a '{' at byte 0");

    b = good;
    b[le32(good, layer + 16) + 10] = 11; // pixelType c64
    EXPECT_EQ(refusal("x.img", b), p + ": its layer \"Layer_1\" holds complex pixels, which are no heights or colours");

    EXPECT_EQ(refusal("x.img", renamed(good, "RasterDMS", "ExternalRasterDMS")),
              p + ": its layer \"Layer_1\"'s spill file node (ExternalRasterDMS) names no file");

    b = good;
    put32(b, dms + 14, 3); // three blocks listed where the layer has four
    EXPECT_EQ(refusal("x.img", b), p + ": its layer \"Layer_1\" lists 3 blocks, not the 4 its size in blocks of 64 x 64 makes");

    b = good;
    put32(b, layer, static_cast<uint32_t>(layer)); // the layer's next node: itself
    EXPECT_EQ(refusal("x.img", b), p + ": its ERDAS Imagine structure is damaged: the nodes under \"root\" run in a loop");

    b = good;
    put32(b, dms + 22 + 2, 0x7fffff00); // block 0's offset, past the end
    EXPECT_EQ(errorOf(test::dataPath("gdal/window-i16.img")), "");
    test::writeBytes(p, b);
    const auto img = RasterSource::open(p);
    std::vector<float> v(65 * 65);
    const std::string e = test::errorMessage([&] { img->readFloat(0, 0, 65, 65, 0, v.data()); });
    EXPECT_EQ(e.rfind(p + ": ", 0), 0u) << e;

    b = good;
    b.resize(b.size() / 2);
    EXPECT_EQ(refusal("x.img", b).rfind(p + ": ", 0), 0u);
}

} // namespace
} // namespace pyramid
