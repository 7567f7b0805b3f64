// The exception types of libpyramid. A message is a single line that names the file (or the
// option) and the problem, ready to print as is: "DEM.dat: offset table points past the end of
// the file (tile 12)".
#pragma once
#include <stdexcept>
#include <string>
#include <utility>

namespace pyramid {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A tile the pyramid does not hold: outside its levels or tiles, or an empty byte range.
class MissingTileError : public Error {
public:
    using Error::Error;
};

// An option value the library cannot use. The library names the option in its own words (the
// options field, "tileSize") and speaks of the value ("7 is not an even number from 2 to
// 8192"); a program maps the option to its own spelling (the programs: "--tile-size").
class OptionError : public Error {
public:
    OptionError(std::string option, std::string problem)
        : Error(option + ": " + problem), option_(std::move(option)), problem_(std::move(problem)) {}
    const std::string& option() const { return option_; }
    const std::string& problem() const { return problem_; }

private:
    std::string option_;
    std::string problem_;
};

// A run stopped because its caller asked (a cancellation callback answered true): like every
// failure, it leaves nothing behind.
class Cancelled : public Error {
public:
    using Error::Error;
};

// "(level,tx,ty)": how every message names a tile.
// (Appended piece by piece: GCC 12 at -O3 gives a false -Wrestrict on "(" + std::string.)
inline std::string tileCoordinates(int level, int tx, int ty) {
    std::string s = "(";
    s += std::to_string(level);
    s += ',';
    s += std::to_string(tx);
    s += ',';
    s += std::to_string(ty);
    s += ')';
    return s;
}

// "WHERE: WHAT", the shape of every error message.
[[noreturn]] inline void fail(const std::string& where, const std::string& what) {
    throw Error(where.empty() ? what : where + ": " + what);
}

// "OPTION: WHAT" for an option value (OptionError).
[[noreturn]] inline void failOption(const std::string& option, const std::string& what) {
    throw OptionError(option, what);
}

} // namespace pyramid
