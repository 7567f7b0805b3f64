// DXT streams: the first two bytes choose the tile size (1 to 64 pixels a side) and the
// format, the rest is the block stream. Decoded tiles are encoded again (any size).
#include <cstdint>
#include <span>

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 2) {
        return 0;
    }
    const int width = 1 + (data[0] & 63);
    const int height = 1 + (data[1] & 63);
    const auto format = (data[0] & 64) ? pyramid::DxtFormat::Dxt5 : pyramid::DxtFormat::Dxt1;
    try {
        const auto pixels = pyramid::decodeDxt(std::span(data + 2, size - 2), width, height, format, "fuzz");
        const int channels = format == pyramid::DxtFormat::Dxt5 ? 4 : 3;
        pyramid::encodeDxt(pixels, width, height, channels, format, data[1] >> 6);
    } catch (const pyramid::Error&) {
    }
    return 0;
}
