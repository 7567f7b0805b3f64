// A set of outputs that appear together (the six files of a cube-face pyramid): they are
// written into a hidden staging directory inside the destination directory, each atomically as
// usual, and commit() moves them into place, creating subdirectories as needed. Destroyed
// before commit(), the staging directory and everything in it are removed, so a run that fails
// at its fifth face leaves none of the first four behind, and so are the destination directory
// and its parents when this object created them and they are empty.
#pragma once
#include <string>
#include <vector>

namespace pyramid {

class StagingDirectory {
public:
    // Creates `destination` if needed and a fresh staging directory inside it. Throws Error
    // ("DIR: cannot create ...") when it cannot.
    explicit StagingDirectory(const std::string& destination);
    ~StagingDirectory();
    StagingDirectory(const StagingDirectory&) = delete;
    StagingDirectory& operator=(const StagingDirectory&) = delete;

    // Where to write the output whose final path is destination/relative.
    std::string path(const std::string& relative) const;
    // Renames every regular file of the staging tree onto the same relative path in the
    // destination (replacing what is there), then removes the staging directory.
    void commit();

private:
    std::string destination_;
    std::string staging_;
    std::vector<std::string> created_; // directories this object created, deepest first
    bool committed_ = false;
};

} // namespace pyramid
