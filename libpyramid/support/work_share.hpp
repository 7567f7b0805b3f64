// How a build split across processes is shared out (doc/planet-scale.md): the units of work of
// every pyramid of the build (the subtrees below its in-memory top levels, in the order the
// encoder takes them), pyramid after pyramid, cut into `count` runs of whole groups of 4 when a
// pyramid has subtrees; part I takes run I. The part whose run holds a pyramid's first unit also
// records the pyramid's top levels. Pure arithmetic: the same answer in every process.
#pragma once
#include <algorithm>
#include <cstdint>

namespace pyramid {

// The units [begin, end) of one pyramid that a share encodes, and whether it records the
// pyramid's top levels.
struct ShareRange {
    int64_t begin = 0, end = 0;
    bool top = false;
    bool active() const { return top || begin < end; }
};

// Part `index` of `count` of a build of `pyramids` pyramids of `units` units each: its range in
// pyramid `pyramid`.
inline ShareRange shareRange(int index, int count, int pyramid, int pyramids, int64_t units) {
    const int64_t total = units * pyramids;
    const int64_t group = units % 4 == 0 ? 4 : 1;
    // floor(groups * i / count) without overflow, in whole groups.
    const auto boundary = [&](int i) {
        if (i >= count) {
            return total;
        }
        const int64_t groups = total / group;
        return ((groups / count) * i + (groups % count) * i / count) * group;
    };
    const int64_t b = boundary(index), e = boundary(index + 1);
    const int64_t first = static_cast<int64_t>(pyramid) * units;
    ShareRange r;
    r.begin = std::clamp<int64_t>(b - first, 0, units);
    r.end = std::clamp<int64_t>(e - first, 0, units);
    r.top = first >= b && first < e;
    return r;
}

} // namespace pyramid
