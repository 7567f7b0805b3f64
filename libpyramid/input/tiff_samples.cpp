#include "libpyramid/input/tiff_samples.hpp"

#include <algorithm>
#include <cstring>

namespace pyramid {

void undoFloatPredictor(uint8_t* bytes, size_t count, uint8_t* out) {
    uint8_t sum = 0;
    for (size_t k = 0; k < 4 * count; ++k) {
        sum = static_cast<uint8_t>(sum + bytes[k]);
        bytes[k] = sum;
    }
    const uint8_t* b3 = bytes;             // most significant bytes
    const uint8_t* b2 = bytes + count;
    const uint8_t* b1 = bytes + 2 * count;
    const uint8_t* b0 = bytes + 3 * count; // least significant
    for (size_t i = 0; i < count; ++i) {
        const uint32_t word = static_cast<uint32_t>(b0[i]) | static_cast<uint32_t>(b1[i]) << 8 |
                              static_cast<uint32_t>(b2[i]) << 16 | static_cast<uint32_t>(b3[i]) << 24;
        std::memcpy(out + 4 * i, &word, 4); // float32's bits, host order
    }
}

namespace {

template <typename T>
void accumulate(uint8_t* row, size_t count, size_t channels) {
    if (channels == 1) {
        // One band (DEMs): the running sum stays in a register.
        T previous = 0;
        for (size_t i = 0; i < count; ++i) {
            T v;
            std::memcpy(&v, row + i * sizeof(T), sizeof(T));
            previous = static_cast<T>(previous + v);
            std::memcpy(row + i * sizeof(T), &previous, sizeof(T));
        }
        return;
    }
    // Sample i adds the one `channels` samples before it (the same channel of the pixel to its
    // left); the first pixel's samples stand as they are.
    for (size_t i = channels; i < count * channels; ++i) {
        T v, left;
        std::memcpy(&v, row + i * sizeof(T), sizeof(T));
        std::memcpy(&left, row + (i - channels) * sizeof(T), sizeof(T));
        v = static_cast<T>(v + left);
        std::memcpy(row + i * sizeof(T), &v, sizeof(T));
    }
}

template <typename T>
void convert(const uint8_t* raw, size_t count, float* out) {
    for (size_t k = 0; k < count; ++k) {
        T v;
        std::memcpy(&v, raw + k * sizeof(T), sizeof(T));
        out[k] = static_cast<float>(v);
    }
}

} // namespace

void undoHorizontalPredictor(uint8_t* row, size_t count, int bits, int channels) {
    const auto c = static_cast<size_t>(std::max(channels, 1));
    switch (bits) {
    case 8: return accumulate<uint8_t>(row, count, c);
    case 16: return accumulate<uint16_t>(row, count, c);
    default: return accumulate<uint32_t>(row, count, c);
    }
}

void swapSampleBytes(uint8_t* row, size_t count, int bits) {
    const size_t n = static_cast<size_t>(bits / 8);
    for (size_t i = 0; i < count && n > 1; ++i) {
        uint8_t* s = row + i * n;
        for (size_t a = 0, b = n - 1; a < b; ++a, --b) {
            const uint8_t t = s[a];
            s[a] = s[b];
            s[b] = t;
        }
    }
}

void samplesToFloat(const uint8_t* raw, size_t count, int bits, int sampleFormat, float* out) {
    const bool isSigned = sampleFormat == 2;
    if (sampleFormat == 3 && bits == 64) {
        for (size_t i = 0; i < count; ++i) {
            double d;
            std::memcpy(&d, raw + 8 * i, sizeof d);
            out[i] = static_cast<float>(d); // to the nearest float32, as OpenImageIO converts it
        }
    } else if (sampleFormat == 3) {
        std::memcpy(out, raw, count * sizeof(float));
    } else if (bits == 8) {
        isSigned ? convert<int8_t>(raw, count, out) : convert<uint8_t>(raw, count, out);
    } else if (bits == 16) {
        isSigned ? convert<int16_t>(raw, count, out) : convert<uint16_t>(raw, count, out);
    } else {
        isSigned ? convert<int32_t>(raw, count, out) : convert<uint32_t>(raw, count, out);
    }
}

void samplesToUInt16(const uint8_t* raw, size_t count, int bits, uint16_t* out) {
    if (bits == 8) {
        std::copy_n(raw, count, out);
    } else {
        std::memcpy(out, raw, count * sizeof(uint16_t));
    }
}

} // namespace pyramid
