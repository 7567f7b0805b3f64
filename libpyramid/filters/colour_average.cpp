#include "libpyramid/filters/colour_average.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pyramid {

namespace {

// sRGB 8-bit -> linear light in 0..65535, rounded once to integers so that the (libm-dependent)
// last bits of pow() cannot change any result.
const std::array<uint32_t, 256>& decodeTable() {
    static const std::array<uint32_t, 256> table = [] {
        std::array<uint32_t, 256> t{};
        for (int v = 0; v < 256; ++v) {
            const double s = v / 255.0;
            const double linear = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
            t[static_cast<size_t>(v)] = static_cast<uint32_t>(std::lround(linear * 65535.0));
        }
        return t;
    }();
    return table;
}

// For every linear value 0..65535 (an average of four table entries never exceeds 65535), the
// 8-bit sRGB value whose linear value is nearest (ties to the lower value): one lookup per
// averaged sample. Built in one walk up both scales (the first entry at or above each value
// only moves up), the same table as a binary search per value, without 65,536 of them on the
// thread that first averages.
const std::array<uint8_t, 65536>& encodeTable() {
    static const std::array<uint8_t, 65536> table = [] {
        const auto& t = decodeTable();
        std::array<uint8_t, 65536> e{};
        size_t hi = 0; // the first entry >= v (256: none)
        for (uint32_t v = 0; v < e.size(); ++v) {
            while (hi < t.size() && t[hi] < v) {
                ++hi;
            }
            if (hi == 0) {
                e[v] = 0;
            } else if (hi == t.size()) {
                e[v] = 255;
            } else {
                e[v] = static_cast<uint8_t>(v - t[hi - 1] <= t[hi] - v ? hi - 1 : hi);
            }
        }
        return e;
    }();
    return table;
}

} // namespace

ColourAverager::ColourAverager(ColourSpace space, int channels) : space_(space), channels_(channels) {}

bool ColourAverager::linearChannel(int channel) const {
    if (space_ == ColourSpace::Linear) {
        return true;
    }
    return (channels_ == 2 || channels_ == 4) && channel == channels_ - 1;
}

uint8_t ColourAverager::average(int channel, uint8_t a, uint8_t b, uint8_t c, uint8_t d) const {
    if (linearChannel(channel)) {
        return static_cast<uint8_t>((static_cast<unsigned>(a) + b + c + d + 2u) >> 2);
    }
    const auto& t = decodeTable();
    const uint32_t sum = t[a] + t[b] + t[c] + t[d];
    return encodeTable()[(sum + 2u) >> 2];
}

namespace {

// Reduces rows [0, out.height) with the channel count known at compile time, so that the
// per-sample choice (light or stored value) and the table look-ups compile to straight-line
// code: the same arithmetic as average(), without a call and two guarded statics per sample.
template <int N>
void reduceRows(const Image8& in, Image8& out, const std::array<bool, 4>& linear) {
    const auto& dec = decodeTable();
    const auto& enc = encodeTable();
    for (int y = 0; y < out.height; ++y) {
        const uint8_t* r0 = in.at(0, 2 * y);
        const uint8_t* r1 = in.at(0, 2 * y + 1);
        uint8_t* o = out.at(0, y);
        for (int x = 0; x < out.width; ++x) {
            const size_t i0 = static_cast<size_t>(2 * x * N);
            for (int c = 0; c < N; ++c) {
                const uint8_t a = r0[i0 + c], b = r0[i0 + N + c], d = r1[i0 + c], e = r1[i0 + N + c];
                o[static_cast<size_t>(x * N + c)] =
                    linear[static_cast<size_t>(c)]
                        ? static_cast<uint8_t>((static_cast<unsigned>(a) + b + d + e + 2u) >> 2)
                        : enc[(dec[a] + dec[b] + dec[d] + dec[e] + 2u) >> 2];
            }
        }
    }
}

} // namespace

Image8 ColourAverager::reduce(const Image8& in) const {
    Image8 out(in.width / 2, in.height / 2, in.channels, Image8::Unset); // every pixel is written
    std::array<bool, 4> linear{};
    for (int c = 0; c < std::min(in.channels, 4); ++c) {
        linear[static_cast<size_t>(c)] = linearChannel(c);
    }
    switch (in.channels) {
    case 1:
        reduceRows<1>(in, out, linear);
        break;
    case 2:
        reduceRows<2>(in, out, linear);
        break;
    case 3:
        reduceRows<3>(in, out, linear);
        break;
    case 4:
        reduceRows<4>(in, out, linear);
        break;
    default: // not produced by the ortho code (1 to 4 channels); kept general
        for (int y = 0; y < out.height; ++y) {
            const uint8_t* r0 = in.at(0, 2 * y);
            const uint8_t* r1 = in.at(0, 2 * y + 1);
            uint8_t* o = out.at(0, y);
            for (int x = 0; x < out.width; ++x) {
                for (int c = 0; c < in.channels; ++c) {
                    const size_t i0 = static_cast<size_t>(2 * x * in.channels + c);
                    const size_t i1 = i0 + static_cast<size_t>(in.channels);
                    o[static_cast<size_t>(x * in.channels + c)] = average(c, r0[i0], r0[i1], r1[i0], r1[i1]);
                }
            }
        }
        break;
    }
    return out;
}

} // namespace pyramid
