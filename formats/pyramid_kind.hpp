// Which kind of pyramid file a path holds. Both kinds start with a 28-byte header and carry no
// magic number, so the kind is the one whose header and whole offset table validate against
// the file (the two layouts practically never both validate; residual wins if they do).
#pragma once
#include <string>

namespace pyramid {

enum class PyramidKind { Residual, Ortho };

// Throws Error("PATH: not a residual or ortho pyramid file (...)") naming both reasons.
PyramidKind detectPyramidKind(const std::string& path);

const char* kindName(PyramidKind kind); // "residual" or "ortho"

} // namespace pyramid
