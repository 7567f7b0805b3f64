// Where the runs of deflate_runs.hpp start: the first place at or after a position where four
// bytes in a row equal those one pixel before, or the one byte before. Two finders with the same
// answer everywhere: one tests five places at a time in 64-bit words (any machine), the other
// sixty at a time in AVX2 vectors (x86-64 machines that have it, chosen when the program
// starts). The answer is a position, so the streams are the same bytes on every machine.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pyramid {

struct RunStart {
    size_t at;       // the start, or `last` where there is none before it
    size_t distance; // `pixel` where the bytes one pixel before match (preferred), else 1
};

// The first run start in [from, last) of p (pixel 1 to 4, from >= pixel). p holds at least
// last + 64 bytes.
RunStart nextRunStart(const uint8_t* p, size_t from, size_t last, size_t pixel);

// Each finder alone, for tests; nextRunStartWide is the word finder where AVX2 is missing.
RunStart nextRunStartWords(const uint8_t* p, size_t from, size_t last, size_t pixel);
RunStart nextRunStartWide(const uint8_t* p, size_t from, size_t last, size_t pixel);

} // namespace pyramid
