// The checks a program makes on its outputs' paths before any work starts, so that a path
// that cannot be written fails in a moment rather than after the encode, and the sweep of the
// stale temporaries of earlier runs beside them (formats/temporaries.hpp).
#pragma once
#include <string>
#include <vector>

namespace pyramid {

// The directories made for an output file (`mkdir -p` of its parents). Destroyed before
// keep(), it removes those it made that are empty again: a run that fails leaves no trace.
class OutputParents {
public:
    OutputParents() = default;
    ~OutputParents();
    OutputParents(const OutputParents&) = delete;
    OutputParents& operator=(const OutputParents&) = delete;
    void keep() { kept_ = true; }

private:
    friend void makeOutputDirectory(const std::string&, OutputParents&, const std::string&);
    std::vector<std::string> created_; // deepest first
    bool kept_ = false;
};

// For an output file: throws Error naming `path` when it is a directory, when a parent is a
// file, or when its directory cannot be written (no permission, a read-only file system).
// Creates the missing parents (recorded in `parents`), then sweeps stale temporaries beside
// the file.
void prepareOutputFile(const std::string& path, OutputParents& parents);

// Makes `directory` and its missing parents (`mkdir -p`), recorded in `parents`. Throws Error
// naming `who` when one cannot be made, or when `directory` exists and is not a directory.
void makeOutputDirectory(const std::string& directory, OutputParents& parents, const std::string& who);

// For an output directory (made later by a StagingDirectory): throws Error naming `directory`
// when it exists and is not a directory or cannot be written, or when the nearest existing
// directory it would be made in is a file or cannot be written. Creates nothing. Sweeps stale
// temporaries in it when it exists.
void prepareOutputDirectory(const std::string& directory);

} // namespace pyramid
