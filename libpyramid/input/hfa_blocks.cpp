#include "libpyramid/input/hfa_blocks.hpp"

#include <cfloat>
#include <cmath>
#include <cstring>

#include "formats/error.hpp"

namespace pyramid {

namespace {

int pixelBits(HfaPixel p) {
    static constexpr int kBits[] = {1, 2, 4, 8, 8, 16, 16, 32, 32, 32, 64, 64, 128};
    return kBits[static_cast<int>(p)];
}

uint32_t le32(const uint8_t* b) {
    return uint32_t{b[0]} | (uint32_t{b[1]} << 8) | (uint32_t{b[2]} << 16) | (uint32_t{b[3]} << 24);
}

// Writes the integer `v` as pixel `i` of the output; false when the pixel type cannot hold it.
bool storeInteger(HfaPixel p, int64_t v, size_t i, uint8_t* out) {
    switch (p) {
    case HfaPixel::U1:
    case HfaPixel::U2:
    case HfaPixel::U4:
    case HfaPixel::U8:
        if (v < 0 || v >= (int64_t{1} << pixelBits(p))) {
            return false;
        }
        out[i] = static_cast<uint8_t>(v);
        return true;
    case HfaPixel::S8:
    case HfaPixel::S16: {
        const int64_t lo = p == HfaPixel::S8 ? -128 : -32768;
        if (v < lo || v > -lo - 1) {
            return false;
        }
        const auto s = static_cast<int16_t>(v);
        std::memcpy(out + 2 * i, &s, 2);
        return true;
    }
    case HfaPixel::U16: {
        if (v < 0 || v > 65535) {
            return false;
        }
        const auto s = static_cast<uint16_t>(v);
        std::memcpy(out + 2 * i, &s, 2);
        return true;
    }
    case HfaPixel::U32:
    case HfaPixel::S32: {
        if (p == HfaPixel::U32 ? (v < 0 || v > UINT32_MAX) : (v < INT32_MIN || v > INT32_MAX)) {
            return false;
        }
        const auto f = static_cast<float>(v);
        std::memcpy(out + 4 * i, &f, 4);
        return true;
    }
    default:
        return false;
    }
}

// The sum of a compressed block's minimum and a value, as pixel `i` of the output: its low bits
// as the pixel type holds them (two's complement for the signed types), as writers store
// negative values (GDAL: a minimum of 0 and each int16 value's 16 bits).
void storeSum(HfaPixel p, uint32_t sum, size_t i, uint8_t* out) {
    switch (p) {
    case HfaPixel::U1:
    case HfaPixel::U2:
    case HfaPixel::U4:
    case HfaPixel::U8:
        out[i] = static_cast<uint8_t>(sum & ((1u << pixelBits(p)) - 1));
        return;
    case HfaPixel::S8:
    case HfaPixel::S16: {
        const auto s = p == HfaPixel::S8 ? int16_t{static_cast<int8_t>(sum & 0xff)} : static_cast<int16_t>(sum & 0xffff);
        std::memcpy(out + 2 * i, &s, 2);
        return;
    }
    case HfaPixel::U16: {
        const auto s = static_cast<uint16_t>(sum & 0xffff);
        std::memcpy(out + 2 * i, &s, 2);
        return;
    }
    default: { // u32, s32: float32, each to the nearest
        const auto f = p == HfaPixel::U32 ? static_cast<float>(sum) : static_cast<float>(static_cast<int32_t>(sum));
        std::memcpy(out + 4 * i, &f, 4);
        return;
    }
    }
}

// The value of `bits` bits number k of `values` (1, 2 and 4 bits from each byte's low bits; 16
// and 32 big-endian), or nothing past `end`.
std::optional<uint32_t> packed(const uint8_t* values, const uint8_t* end, int bits, size_t k) {
    const size_t bit = k * static_cast<size_t>(bits);
    const size_t bytes = (bits + 7) / 8;
    if (values > end || bit / 8 + bytes > static_cast<size_t>(end - values)) {
        return std::nullopt;
    }
    const uint8_t* b = values + bit / 8;
    switch (bits) {
    case 0:
        return 0;
    case 1:
    case 2:
    case 4:
        return (*b >> (bit % 8)) & ((1u << bits) - 1);
    case 8:
        return *b;
    case 16:
        return (uint32_t{b[0]} << 8) | b[1];
    default:
        return (uint32_t{b[0]} << 24) | (uint32_t{b[1]} << 16) | (uint32_t{b[2]} << 8) | b[3];
    }
}

void decodeCompressed(HfaPixel p, const std::vector<uint8_t>& stored, size_t pixels, uint8_t* out,
                      const std::string& path, const std::string& block) {
    const auto bad = [&](const std::string& what) {
        fail(path, block + " is damaged: " + what);
    };
    if (p == HfaPixel::F32 || p == HfaPixel::F64) {
        fail(path, block + " holds run-length compressed floating-point values, which this reader does not "
                           "decode: convert the file to a GeoTIFF first");
    }
    if (stored.size() < 13) {
        bad("its compressed header is cut short");
    }
    const uint8_t* data = stored.data();
    const uint8_t* end = data + stored.size();
    const uint32_t minimum = le32(data);
    const auto runs = static_cast<int32_t>(le32(data + 4));
    const uint32_t valuesAt = le32(data + 8);
    const int bits = data[12];
    if (bits != 0 && bits != 1 && bits != 2 && bits != 4 && bits != 8 && bits != 16 && bits != 32) {
        bad("its values take " + std::to_string(bits) + " bits, not 0, 1, 2, 4, 8, 16 or 32");
    }
    const auto store = [&](uint32_t v, size_t i) { storeSum(p, minimum + v, i, out); };
    if (runs == -1) {
        for (size_t i = 0; i < pixels; ++i) {
            const std::optional<uint32_t> v = packed(data + 13, end, bits, i);
            if (!v) {
                bad("its values end before its pixels");
            }
            store(*v, i);
        }
        return;
    }
    if (runs < 0 || valuesAt > stored.size()) {
        bad("its count of runs or its values' offset is out of range");
    }
    const uint8_t* counter = data + 13;
    size_t done = 0;
    for (int32_t r = 0; r < runs; ++r) {
        if (counter >= end) {
            bad("its run lengths end before its runs");
        }
        const int extra = *counter >> 6;
        if (end - counter < 1 + extra) {
            bad("its run lengths end before its runs");
        }
        uint32_t length = *counter++ & 0x3f;
        for (int k = 0; k < extra; ++k) {
            length = (length << 8) | *counter++;
        }
        const std::optional<uint32_t> v = packed(data + valuesAt, end, bits, static_cast<size_t>(r));
        if (!v) {
            bad("its values end before its runs");
        }
        if (length > pixels - done) {
            bad("its runs hold more than its " + std::to_string(pixels) + " pixels");
        }
        for (uint32_t k = 0; k < length; ++k) {
            store(*v, done++);
        }
    }
    if (done != pixels) {
        bad("its runs hold " + std::to_string(done) + " of its " + std::to_string(pixels) + " pixels");
    }
}

} // namespace

SampleType hfaSampleType(HfaPixel p) {
    switch (p) {
    case HfaPixel::U1:
    case HfaPixel::U2:
    case HfaPixel::U4:
    case HfaPixel::U8:
        return SampleType::UInt8;
    case HfaPixel::S8:
    case HfaPixel::S16:
        return SampleType::Int16;
    case HfaPixel::U16:
        return SampleType::UInt16;
    case HfaPixel::U32:
    case HfaPixel::S32:
    case HfaPixel::F32:
    case HfaPixel::F64:
        return SampleType::Float32;
    default:
        return SampleType::Other;
    }
}

size_t hfaStoredBytes(HfaPixel p, size_t pixels) { return (pixels * static_cast<size_t>(pixelBits(p)) + 7) / 8; }

void decodeHfaBlock(HfaPixel p, bool compressed, const std::vector<uint8_t>& stored, size_t pixels, uint8_t* out,
                    const std::string& path, const std::string& block) {
    if (compressed) {
        decodeCompressed(p, stored, pixels, out, path, block);
        return;
    }
    const uint8_t* in = stored.data(); // hfaStoredBytes(p, pixels) of them: the caller read so many
    const int bits = pixelBits(p);
    switch (p) {
    case HfaPixel::U1:
    case HfaPixel::U2:
    case HfaPixel::U4:
        for (size_t i = 0; i < pixels; ++i) {
            out[i] = *packed(in, in + stored.size(), bits, i);
        }
        return;
    case HfaPixel::U8:
    case HfaPixel::U16:
    case HfaPixel::S16:
    case HfaPixel::F32: // little-endian files on a little-endian host: the samples as stored
        std::memcpy(out, in, pixels * static_cast<size_t>(bits / 8));
        return;
    case HfaPixel::S8:
        for (size_t i = 0; i < pixels; ++i) {
            const int16_t s = static_cast<int8_t>(in[i]);
            std::memcpy(out + 2 * i, &s, 2);
        }
        return;
    case HfaPixel::U32:
    case HfaPixel::S32:
        for (size_t i = 0; i < pixels; ++i) {
            const uint32_t w = le32(in + 4 * i);
            const auto f = p == HfaPixel::U32 ? static_cast<float>(w) : static_cast<float>(static_cast<int32_t>(w));
            std::memcpy(out + 4 * i, &f, 4);
        }
        return;
    case HfaPixel::F64:
        for (size_t i = 0; i < pixels; ++i) {
            double d;
            std::memcpy(&d, in + 8 * i, 8);
            if (std::isfinite(d) && std::fabs(d) > FLT_MAX) {
                fail(path, block + " holds the value " + std::to_string(d) + ", beyond float32's range");
            }
            const auto f = static_cast<float>(d);
            std::memcpy(out + 4 * i, &f, 4);
        }
        return;
    default:
        fail(path, block + " holds complex values, which are no heights or colours");
    }
}

void fillHfaBlock(HfaPixel p, const std::optional<double>& nodata, size_t pixels, uint8_t* out) {
    const size_t bytes = p == HfaPixel::U16 || p == HfaPixel::S16 || p == HfaPixel::S8 ? 2
                         : hfaSampleType(p) == SampleType::Float32                    ? 4
                                                                                      : 1;
    std::memset(out, 0, pixels * bytes);
    if (!nodata || (std::isfinite(*nodata) && std::fabs(*nodata) > FLT_MAX)) {
        return;
    }
    if (bytes == 4) {
        for (size_t i = 0; i < pixels; ++i) {
            const auto f = static_cast<float>(*nodata);
            std::memcpy(out + 4 * i, &f, 4);
        }
        return;
    }
    const double v = *nodata;
    if (v != std::floor(v) || std::fabs(v) > 4294967296.0 || !storeInteger(p, static_cast<int64_t>(v), 0, out)) {
        return;
    }
    for (size_t i = 1; i < pixels; ++i) {
        std::memcpy(out + i * bytes, out, bytes);
    }
}

} // namespace pyramid
