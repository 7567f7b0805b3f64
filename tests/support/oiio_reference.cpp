#include "tests/support/oiio_reference.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <map>

#include "libpyramid/input/raster_source.hpp"

namespace pyramid::test {

std::vector<double> referenceSamples(const std::string& path, OIIO::ImageSpec& spec, std::string& formatName) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) {
        return {};
    }
    spec = in->spec();
    formatName = in->format_name();
    std::vector<double> native(spec.image_pixels() * static_cast<size_t>(spec.nchannels));
    // Read in the file's type, then widen by value (a direct read as double would normalise).
    // (Half floats are read as float32, which holds them exactly.)
    const OIIO::TypeDesc type = spec.format == OIIO::TypeDesc::HALF ? OIIO::TypeDesc(OIIO::TypeDesc::FLOAT) : spec.format;
    std::vector<uint8_t> raw(native.size() * type.size());
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, type, raw.data())) << in->geterror();
    for (size_t k = 0; k < native.size(); ++k) {
        const uint8_t* p = raw.data() + k * type.size();
        switch (type.basetype) {
        case OIIO::TypeDesc::UINT8: native[k] = *p; break;
        case OIIO::TypeDesc::INT8: native[k] = *reinterpret_cast<const int8_t*>(p); break;
        case OIIO::TypeDesc::UINT16: native[k] = *reinterpret_cast<const uint16_t*>(p); break;
        case OIIO::TypeDesc::INT16: native[k] = *reinterpret_cast<const int16_t*>(p); break;
        case OIIO::TypeDesc::INT32: native[k] = *reinterpret_cast<const int32_t*>(p); break;
        case OIIO::TypeDesc::FLOAT: native[k] = *reinterpret_cast<const float*>(p); break;
        case OIIO::TypeDesc::DOUBLE: native[k] = *reinterpret_cast<const double*>(p); break;
        default: ADD_FAILURE() << "unexpected type"; break;
        }
    }
    return native;
}

void expectSameAsOpenImageIO(const std::string& path, int cacheMegabytes) {
    SCOPED_TRACE(path);
    OIIO::ImageSpec spec;
    std::string formatName;
    const std::vector<double> expected = referenceSamples(path, spec, formatName);
    const auto source = RasterSource::open(path, cacheMegabytes);
    const RasterInfo& info = source->info();
    ASSERT_EQ(info.width, spec.width);
    ASSERT_EQ(info.height, spec.height);
    ASSERT_EQ(info.channels, spec.nchannels);
    const bool eightBit = spec.format == OIIO::TypeDesc::UINT8;
    const bool sixteenBit = spec.format == OIIO::TypeDesc::UINT16;
    const std::map<std::string, std::string> names = {{"uint8", "uint8"}, {"int8", "int8"},   {"uint16", "uint16"},
                                                      {"int16", "int16"}, {"uint", "uint32"}, {"int", "int32"},
                                                      {"half", "float16"}, {"float", "float32"}, {"double", "float64"}};
    EXPECT_EQ(sampleTypeName(info.type), names.at(spec.format.c_str()));
    EXPECT_EQ(info.formatName, formatName);
    const int w = info.width, h = info.height, n = info.channels;
    // A window away from the corners, and the whole image.
    for (const auto& [x0, y0, x1, y1] : {std::array{3, 2, w - 4, h - 5}, std::array{0, 0, w, h}}) {
        const int ww = x1 - x0, wh = y1 - y0;
        const auto at = [&](int x, int y, int c) {
            return expected[(static_cast<size_t>(y0 + y) * static_cast<size_t>(w) + static_cast<size_t>(x0 + x)) *
                                static_cast<size_t>(n) + static_cast<size_t>(c)];
        };
        for (int c = 0; c < n; ++c) {
            std::vector<float> f(static_cast<size_t>(ww * wh));
            source->readFloat(x0, y0, x1, y1, c, f.data());
            for (int y = 0; y < wh; ++y) {
                for (int x = 0; x < ww; ++x) {
                    ASSERT_EQ(f[static_cast<size_t>(y * ww + x)], static_cast<float>(at(x, y, c)))
                        << "readFloat channel " << c << " at " << x0 + x << "," << y0 + y;
                }
            }
        }
        if (eightBit || sixteenBit) {
            std::vector<uint16_t> u(static_cast<size_t>(ww * wh * n));
            source->readUInt16(x0, y0, x1, y1, 0, n, u.data());
            for (size_t k = 0; k < u.size(); ++k) {
                const int x = static_cast<int>(k / static_cast<size_t>(n)) % ww;
                const int y = static_cast<int>(k / static_cast<size_t>(n)) / ww;
                ASSERT_EQ(u[k], at(x, y, static_cast<int>(k % static_cast<size_t>(n)))) << "readUInt16 sample " << k;
            }
        }
        if (eightBit) {
            // The last channel only, stored bottom up through a negative stride.
            std::vector<uint8_t> b(static_cast<size_t>(ww * wh));
            source->readUInt8(x0, y0, x1, y1, n - 1, n, b.data() + static_cast<size_t>((wh - 1) * ww), -ww);
            for (int y = 0; y < wh; ++y) {
                for (int x = 0; x < ww; ++x) {
                    ASSERT_EQ(b[static_cast<size_t>((wh - 1 - y) * ww + x)], at(x, y, n - 1)) << "readUInt8";
                }
            }
        }
    }
}

} // namespace pyramid::test
