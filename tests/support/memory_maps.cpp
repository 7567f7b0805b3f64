#include "tests/support/memory_maps.hpp"

#include <fstream>
#include <sstream>

namespace pyramid::test {

std::vector<MemoryMap> memoryMaps(const std::string& pid) {
    std::vector<MemoryMap> maps;
    std::ifstream smaps("/proc/" + pid + "/smaps");
    std::string line;
    while (std::getline(smaps, line)) {
        // A map's first line: "FROM-TO PERMS OFFSET DEV INODE [NAME]"; its fields: "Name:  value".
        const size_t colon = line.find(':'), space = line.find(' ');
        if (space != std::string::npos && (colon == std::string::npos || colon > space)) {
            MemoryMap m;
            char dash = 0;
            std::string perms, offset, device, inode;
            std::istringstream head(line);
            if (head >> std::hex >> m.from >> dash >> m.to >> perms >> offset >> device >> inode && dash == '-') {
                std::getline(head >> std::ws, m.name);
                maps.push_back(m);
            }
        } else if (!maps.empty() && line.rfind("Rss:", 0) == 0) {
            maps.back().rssKb = std::stoll(line.substr(4));
        } else if (!maps.empty() && line.rfind("THPeligible:", 0) == 0) {
            maps.back().thpEligible = std::stoi(line.substr(12));
        }
    }
    return maps;
}

const MemoryMap* mapHolding(const std::vector<MemoryMap>& maps, const void* p) {
    const auto at = reinterpret_cast<uintptr_t>(p);
    for (const MemoryMap& m : maps) {
        if (m.from <= at && at < m.to) {
            return &m;
        }
    }
    return nullptr;
}

bool transparentHugePagesOff() {
    std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(f, modes);
    return modes.empty() || modes.find("[never]") != std::string::npos;
}

} // namespace pyramid::test
