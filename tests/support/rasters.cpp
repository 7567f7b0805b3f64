#include "tests/support/rasters.hpp"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <stdexcept>

namespace pyramid::test {

void writeFloatRaster(const std::string& path, int width, int height, const std::vector<float>& values) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
        throw std::runtime_error("cannot create " + path);
    }
    OIIO::ImageSpec spec(width, height, 1, OIIO::TypeFloat);
    spec.attribute("compression", "zip");
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeFloat, values.data()) || !out->close()) {
        throw std::runtime_error("cannot write " + path + ": " + out->geterror());
    }
}

std::vector<float> syntheticHeights(int width, int height, float amplitude) {
    std::vector<float> v(static_cast<size_t>(width) * static_cast<size_t>(height));
    uint32_t state = 12345u;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            state = state * 1664525u + 1013904223u;
            const double noise = static_cast<double>(state >> 8) / static_cast<double>(1u << 24) - 0.5;
            const double h = amplitude * std::sin(x / 23.0) * std::cos(y / 17.0) + 0.37 * x - 0.21 * y +
                             0.1 * amplitude * std::sin((x + 2 * y) / 5.0) + 3.0 * noise;
            v[static_cast<size_t>(x) + static_cast<size_t>(y) * static_cast<size_t>(width)] = static_cast<float>(h);
        }
    }
    return v;
}

std::vector<uint16_t> texturedColours(int width, int height) {
    std::vector<uint16_t> v(static_cast<size_t>(width) * static_cast<size_t>(height) * 3);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < 3; ++c) {
                const double s = 0.5 + 0.4 * std::sin(x / (5.0 + c) + y / 9.0) * std::cos((x - y) / 11.0);
                v[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3 + static_cast<size_t>(c)] =
                    static_cast<uint16_t>(std::lround(s * 230.0) + (x * 7 + y * 13 + c * 5) % 17);
            }
        }
    }
    return v;
}

void writeImage(const std::string& path, int width, int height, int channels, const std::vector<uint16_t>& values,
                bool sixteen) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
        throw std::runtime_error("cannot create " + path);
    }
    const OIIO::TypeDesc type = sixteen ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8;
    OIIO::ImageSpec spec(width, height, channels, type);
    bool ok = out->open(path, spec);
    if (ok && sixteen) {
        ok = out->write_image(OIIO::TypeDesc::UINT16, values.data());
    } else if (ok) {
        std::vector<uint8_t> bytes(values.begin(), values.end());
        ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    }
    if (!ok || !out->close()) {
        throw std::runtime_error("cannot write " + path + ": " + out->geterror());
    }
}

std::vector<float> overflowSpikes(int w) {
    std::vector<float> v(static_cast<size_t>(w) * w, 0.0f);
    for (int k = 0; k < 4; ++k) {
        const int column = w - 6 - 2 * k, row = 3 + 2 * k;
        v[static_cast<size_t>(column + row * w)] = 4.0e5f * static_cast<float>(k + 1);
    }
    return v;
}

} // namespace pyramid::test
