// The one exception type of libpyramid. Its message is a single line that names the
// file (or the option) and the problem, ready to print as is: "DEM.dat: offset table
// points past the end of the file (tile 12)".
#pragma once
#include <stdexcept>
#include <string>

namespace pyramid {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// "WHERE: WHAT", the shape of every error message.
[[noreturn]] inline void fail(const std::string& where, const std::string& what) {
    throw Error(where.empty() ? what : where + ": " + what);
}

} // namespace pyramid
