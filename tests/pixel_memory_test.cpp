// Pixel memory (libpyramid/filters/pixel_memory.hpp): buffers of 2 MB and more start on a 2 MB
// boundary and their memory may be backed by transparent huge pages (the kernel says so in
// /proc/self/smaps, unless THP is off); smaller ones are plain; containers of it keep what they
// are given and leave the rest unset.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "libpyramid/filters/image8.hpp"
#include "libpyramid/filters/pixel_memory.hpp"
#include "tests/support/memory_maps.hpp"

namespace pyramid {
namespace {

TEST(PixelMemory, LargeBuffersStartOnHugePagesAndMayUseThem) {
    const size_t bytes = 5 * kHugePageBytes + 12345;
    auto* p = static_cast<uint8_t*>(allocatePixelMemory(bytes));
    EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % kHugePageBytes, 0u);
    for (size_t k = 0; k < bytes; k += 4096) {
        p[k] = static_cast<uint8_t>(k >> 12);
    }
    p[bytes - 1] = 7;
    for (size_t k = 0; k < bytes; k += 4096) {
        ASSERT_EQ(p[k], static_cast<uint8_t>(k >> 12)) << k;
    }
    EXPECT_EQ(p[bytes - 1], 7);
    if (!test::transparentHugePagesOff()) {
        const std::vector<test::MemoryMap> maps = test::memoryMaps("self");
        const test::MemoryMap* map = test::mapHolding(maps, p);
        ASSERT_NE(map, nullptr);
        EXPECT_EQ(map->thpEligible, 1) << map->name;
    }
    releasePixelMemory(p, bytes);
}

TEST(PixelMemory, ContainersHoldWhatTheyAreGiven) {
    PixelBytes small(1000, 3);
    EXPECT_EQ(small.size(), 1000u);
    EXPECT_EQ(small[999], 3);
    Image8 big(1100, 1000, 3); // 3.3 MB, cleared
    EXPECT_EQ(reinterpret_cast<uintptr_t>(big.pixels.data()) % kHugePageBytes, 0u);
    EXPECT_EQ(big.pixels.size(), 3300000u);
    EXPECT_EQ(*big.at(1099, 999), 0);
    *big.at(1099, 999) = 200;
    big.pixels.resize(big.pixels.size() + 1); // grows into a new block, keeping the pixels
    EXPECT_EQ(reinterpret_cast<uintptr_t>(big.pixels.data()) % kHugePageBytes, 0u);
    EXPECT_EQ(*big.at(1099, 999), 200);
    const PixelMemory decoded = makePixelMemory(kHugePageBytes);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(decoded.get()) % kHugePageBytes, 0u);
}

} // namespace
} // namespace pyramid
