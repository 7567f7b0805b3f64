// The programs' heap (cli/cli_program.cpp, keepBuffersInTheHeap), seen in a running program's
// /proc/PID/smaps: grown once at the start by 180 MB of address space, which asks for
// transparent huge pages (unless THP is off) and holds no memory until used. Under a sanitizer,
// whose allocator replaces glibc's, the programs leave the heap alone.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "tests/support/memory_maps.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/served_program.hpp"

namespace pyramid {
namespace {

TEST(ProgramHeap, GrownOnceIntoHugePagesAndUntouched) {
    // `pyramid serve` stays up to be looked at.
    test::ServedProgram served({test::dataPath("proland/DEM.dat"), "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    const std::vector<test::MemoryMap> maps = test::memoryMaps(std::to_string(served.pid()));
    ASSERT_FALSE(maps.empty());
    int64_t heapBytes = 0, heapRssKb = 0;
    int eligible = 0;
    for (const test::MemoryMap& m : maps) {
        if (m.name.find("libasan") != std::string::npos || m.name.find("libtsan") != std::string::npos) {
            GTEST_SKIP() << "a sanitizer's allocator: " << m.name;
        }
        if (m.name == "[heap]") {
            heapBytes += static_cast<int64_t>(m.to - m.from);
            heapRssKb += m.rssKb;
            eligible = std::max(eligible, m.thpEligible);
        }
    }
    EXPECT_GE(heapBytes, int64_t{180} << 20);
    EXPECT_LT(heapRssKb, 64 * 1024) << "the heap's memory, in KB";
    if (!test::transparentHugePagesOff()) {
        EXPECT_EQ(eligible, 1);
    }
}

} // namespace
} // namespace pyramid
