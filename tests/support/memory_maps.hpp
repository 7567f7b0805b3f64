// A process's memory maps as /proc/PID/smaps lists them, and whether the kernel's transparent
// huge pages are off: for the tests of what the library and programs ask of the kernel.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace pyramid::test {

struct MemoryMap {
    uintptr_t from = 0, to = 0; // [from, to)
    std::string name;           // "[heap]", a file's path, or empty
    int64_t rssKb = 0;          // "Rss:"
    int thpEligible = -1;       // "THPeligible:", -1 when not listed
};

// The maps of /proc/PID/smaps ("self" for this process); empty when it cannot be read.
std::vector<MemoryMap> memoryMaps(const std::string& pid);

// The map holding `p`, or null.
const MemoryMap* mapHolding(const std::vector<MemoryMap>& maps, const void* p);

// Whether /sys/kernel/mm/transparent_hugepage/enabled says [never] (or cannot be read).
bool transparentHugePagesOff();

} // namespace pyramid::test
