#include "formats/pyramid_kind.hpp"

#include <utility>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"

namespace pyramid {

namespace {
// The part of an error message after "PATH: ".
std::string reason(const Error& e, const std::string& path) {
    const std::string what = e.what();
    return what.rfind(path + ": ", 0) == 0 ? what.substr(path.size() + 2) : what;
}
} // namespace

OpenedPyramid openPyramid(const std::string& path) { return openPyramid(openFileSource(path)); }

OpenedPyramid openPyramid(std::shared_ptr<const ByteSource> source) {
    const std::string path = source->name();
    std::string asResidual, asOrtho;
    OpenedPyramid opened;
    try {
        opened.residual = ResidualFileReader::open(source);
        opened.kind = PyramidKind::Residual;
        return opened;
    } catch (const Error& e) {
        asResidual = reason(e, path);
    }
    try {
        opened.ortho = OrthoFileReader::open(source);
        opened.kind = PyramidKind::Ortho;
        return opened;
    } catch (const Error& e) {
        asOrtho = reason(e, path);
    }
    if (asResidual == asOrtho) {
        fail(path, asResidual);
    }
    fail(path, "not a residual pyramid file (" + asResidual + ") nor an ortho pyramid file (" + asOrtho + ")");
}

PyramidKind detectPyramidKind(const std::string& path) { return openPyramid(path).kind; }

const char* kindName(PyramidKind kind) { return kind == PyramidKind::Residual ? "residual" : "ortho"; }

} // namespace pyramid
