// Which kind of pyramid file a path (or any byte source) holds. Both kinds start with a 28-byte header and carry no
// magic number, so the kind is the one whose header and whole offset table validate against
// the file (the two layouts practically never both validate; residual wins if they do).
#pragma once
#include <memory>
#include <string>

#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"

namespace pyramid {

enum class PyramidKind { Residual, Ortho };

// A pyramid file opened as the kind it holds, by the reader that validated it: its offset table
// is read once, by that reader, and kept.
struct OpenedPyramid {
    PyramidKind kind = PyramidKind::Residual;
    std::unique_ptr<ResidualFileReader> residual; // set when kind is Residual
    std::unique_ptr<OrthoFileReader> ortho;       // set when kind is Ortho
};
// Throws Error("PATH: not a residual or ortho pyramid file (...)") naming both reasons.
OpenedPyramid openPyramid(const std::string& path);
// The same from any source (kept by the reader that opened it).
OpenedPyramid openPyramid(std::shared_ptr<const ByteSource> source);

// openPyramid(path).kind.
PyramidKind detectPyramidKind(const std::string& path);

const char* kindName(PyramidKind kind); // "residual" or "ortho"

} // namespace pyramid
