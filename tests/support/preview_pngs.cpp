#include "tests/support/preview_pngs.hpp"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <fstream>
#include <iterator>

#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid::test {

Png readPng(const std::string& path) {
    Png png;
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path;
    if (!in) {
        return png;
    }
    const OIIO::ImageSpec& spec = in->spec();
    png.width = spec.width;
    png.height = spec.height;
    png.channels = spec.nchannels;
    png.depth = static_cast<int>(spec.format.size()) * 8;
    png.samples.resize(static_cast<size_t>(png.width) * png.height * png.channels);
    EXPECT_TRUE(in->read_image(0, 0, 0, png.channels, OIIO::TypeDesc::UINT16, png.samples.data()));
    in->close();
    std::ifstream file(path, std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
    for (size_t at = 8; at + 12 <= bytes.size();) {
        const uint32_t n = (uint32_t{bytes[at]} << 24) | (uint32_t{bytes[at + 1]} << 16) |
                           (uint32_t{bytes[at + 2]} << 8) | bytes[at + 3];
        const std::string type(bytes.begin() + static_cast<long>(at) + 4, bytes.begin() + static_cast<long>(at) + 8);
        if (type == "tEXt") {
            const std::string chunk(bytes.begin() + static_cast<long>(at) + 8,
                                    bytes.begin() + static_cast<long>(at) + 8 + n);
            const size_t zero = chunk.find('\0');
            png.text[chunk.substr(0, zero)] = chunk.substr(zero + 1);
        }
        at += 12 + n;
    }
    return png;
}

std::string demOf(const TempDir& dir, const std::string& name, int w, double (*f)(double, double)) {
    std::vector<float> v(static_cast<size_t>(w) * w);
    for (int row = 0; row < w; ++row) {
        for (int x = 0; x < w; ++x) {
            v[static_cast<size_t>(row) * w + x] = static_cast<float>(f(x, w - 1 - row));
        }
    }
    writeFloatRaster(dir.file(name + ".tif"), w, w, v);
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 32;
    o.autoScale = true;
    encodeDem(dir.file(name + ".tif"), dir.file(name + ".dat"), o);
    return dir.file(name + ".dat");
}

} // namespace pyramid::test
