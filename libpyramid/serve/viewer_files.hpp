// Where `pyramid serve` finds the web viewer's files (doc/cli/pyramid-serve.md, "The viewer"):
// the one place that decides it.
#pragma once
#include <filesystem>
#include <string>

namespace pyramid::serve {

// `given` (--viewer-dir) when not empty; else the installed <prefix>/share/libpyramid/viewer,
// found from the running program's own directory (<prefix>/bin); else, for a program run from
// its build tree, <build>/viewer, where the build copies the viewer.
std::filesystem::path viewerDirectory(const std::string& given);

// The viewer's file `name` (a plain name: letters, digits, '.', '-', '_', not starting with '.')
// in `directory`, when it is such a name and a regular file there; empty otherwise.
std::filesystem::path viewerFile(const std::filesystem::path& directory, const std::string& name);

} // namespace pyramid::serve
