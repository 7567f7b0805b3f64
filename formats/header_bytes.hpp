// Little-endian packing of the 28-byte headers (both file kinds: seven 32-bit fields).
#pragma once
#include <array>
#include <cstdint>
#include <cstring>

namespace pyramid::detail {

inline uint32_t loadU32(const uint8_t* p) {
    return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
           (static_cast<uint32_t>(p[3]) << 24);
}

inline void storeU32(uint8_t* p, uint32_t v) {
    p[0] = static_cast<uint8_t>(v);
    p[1] = static_cast<uint8_t>(v >> 8);
    p[2] = static_cast<uint8_t>(v >> 16);
    p[3] = static_cast<uint8_t>(v >> 24);
}

inline int32_t loadI32(const uint8_t* p) { return static_cast<int32_t>(loadU32(p)); }

inline float loadF32(const uint8_t* p) {
    const uint32_t bits = loadU32(p);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

inline void storeF32(uint8_t* p, float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    storeU32(p, bits);
}

// Number of tiles in a full quadtree of levels 0..depth: (4^(depth+1) - 1) / 3.
inline int64_t quadtreeTiles(int depth) { return ((int64_t{1} << (2 * (depth + 1))) - 1) / 3; }

} // namespace pyramid::detail
