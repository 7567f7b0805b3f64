#include "libpyramid/input/input_list.hpp"

#include <glob.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <utility>

#include "formats/error.hpp"
#include "libpyramid/input/input_list_text.hpp"
#include "libpyramid/input/vrt_sources.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

namespace fs = std::filesystem;
using input_list_detail::resolveAgainst;
using input_list_detail::trim;

// ---------------------------------------------------------------------------------------------
// Text

bool isVrtName(const std::string& path) { return endsWithNoCase(path, ".vrt"); }

// What a directory contributes: the files terrain tiles come as (GeoTIFF, SRTM height files, DTED, ERDAS
// Imagine, XYZ text, USGS DEMs (and GTOPO30's .dem), ESRI ASCII and .hdr-labelled grids; any case).
bool isGridFileName(const std::string& name) {
    for (const char* ext : {".tif", ".tiff", ".hgt", ".asc", ".bil", ".flt", ".dt0", ".dt1", ".dt2", ".img", ".xyz", ".dem"}) {
        if (endsWithNoCase(name, ext)) {
            return true;
        }
    }
    return false;
}

bool hasGlobCharacters(const std::string& text) { return text.find_first_of("*?[") != std::string::npos; }

// TEXT with glob(3)'s special characters escaped, so that it matches only itself.
std::string escapeGlob(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '*' || c == '?' || c == '[' || c == ']' || c == '\\') {
            out += '\\';
        }
        out += c;
    }
    return out;
}

// "ORIGIN: WHERE", or WHERE alone for a command-line argument (no origin).
std::string within(const std::string& origin, const std::string& where) {
    return origin.empty() ? where : origin + ": " + where;
}

// What PATH is (symlinks followed): not_found when nothing is there. Throws naming WHERE when
// the file system cannot tell (a directory on the way that cannot be searched).
fs::file_status statusOf(const std::string& path, const std::string& where) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (status.type() == fs::file_type::none) {
        fail(where, "cannot read: " + ec.message());
    }
    return status;
}

// ---------------------------------------------------------------------------------------------
// The expansion

class Expansion {
public:
    InputList result;

    // An argument or a list file's line: PATH as resolved; PATTERN the glob to expand when PATH
    // does not exist and holds glob characters (PATH with its resolved prefix escaped).
    void addArgument(const std::string& path, const std::string& pattern, const std::string& origin) {
        if (path.empty()) {
            fail(origin, "an empty argument names no file");
        }
        const fs::file_status status = statusOf(path, within(origin, path));
        if (fs::exists(status)) {
            addExisting(path, origin, true);
        } else if (hasGlobCharacters(path)) {
            addGlob(pattern, path, origin);
        } else {
            fail(within(origin, path), "no such file");
        }
    }

private:
    std::set<std::string> seenFiles_;
    std::set<std::string> seenVrtArguments_;
    std::set<std::string> readVrts_;
    std::vector<std::string> vrtsBeingRead_;

    // The key duplicates are found by: the path made absolute, normalised lexically.
    static std::string normalKey(const std::string& path) {
        fs::path p(path);
        if (p.is_relative()) {
            std::error_code ec;
            const fs::path cwd = fs::current_path(ec);
            if (!ec) {
                p = cwd / p;
            }
        }
        return p.lexically_normal().string();
    }

    // PATH exists (as named, or as a glob match): a directory, a VRT or a file.
    void addExisting(const std::string& path, const std::string& origin, bool named) {
        if (fs::is_directory(statusOf(path, within(origin, path)))) {
            addDirectory(path, origin);
        } else if (isVrtName(path)) {
            addVrt(path, origin, named);
        } else {
            addFile(path, origin);
        }
    }

    void addFile(const std::string& path, const std::string& origin) {
        const fs::file_status status = statusOf(path, within(origin, path));
        if (!fs::exists(status)) {
            fail(within(origin, path), "no such file");
        }
        if (!fs::is_regular_file(status)) {
            fail(within(origin, path), "not a regular file");
        }
        if (seenFiles_.insert(normalKey(path)).second) {
            result.paths.push_back(path);
        }
    }

    // The directory's rasters of terrain tiles (isGridFileName; no hidden ones, no subdirectories), by name.
    void addDirectory(const std::string& path, const std::string& origin) {
        const std::string where = within(origin, path);
        std::vector<std::string> names;
        std::error_code ec;
        fs::directory_iterator it(path, ec);
        if (ec) {
            fail(where, "cannot list the directory: " + ec.message());
        }
        for (; it != fs::directory_iterator(); it.increment(ec)) {
            const std::string name = it->path().filename().string();
            if (name.empty() || name[0] == '.' || !isGridFileName(name)) {
                continue;
            }
            std::error_code typeError;
            if (it->is_directory(typeError)) {
                continue;
            }
            names.push_back(name);
        }
        if (ec) {
            fail(where, "cannot list the directory: " + ec.message());
        }
        if (names.empty()) {
            fail(where, "the directory holds no .tif, .tiff, .hgt, .dt0-2, .img, .xyz, .dem, .asc, .bil or .flt file");
        }
        std::sort(names.begin(), names.end());
        for (const std::string& name : names) {
            addFile((fs::path(path) / name).string(), origin);
        }
    }

    void addGlob(const std::string& pattern, const std::string& shown, const std::string& origin) {
        glob_t matches{};
        const int rc = ::glob(pattern.c_str(), GLOB_NOSORT, nullptr, &matches);
        std::vector<std::string> found;
        if (rc == 0) {
            for (size_t k = 0; k < matches.gl_pathc; ++k) {
                found.emplace_back(matches.gl_pathv[k]);
            }
        }
        globfree(&matches);
        if (rc == GLOB_NOMATCH) {
            fail(within(origin, shown), "no file matches the pattern");
        }
        if (rc != 0) {
            fail(within(origin, shown), rc == GLOB_NOSPACE ? "out of memory expanding the pattern"
                                                           : "cannot read the directories of the pattern");
        }
        std::sort(found.begin(), found.end());
        for (const std::string& match : found) {
            addExisting(match, origin, true);
        }
    }

    // The files of a VRT's plain sources, in order of first appearance. NAMED: the VRT was named
    // by an argument, a list file's line or their glob (not found as another VRT's source).
    void addVrt(const std::string& path, const std::string& origin, bool named) {
        const std::string where = within(origin, path);
        const std::string key = normalKey(path);
        if (named && seenVrtArguments_.insert(key).second) {
            result.vrtSources.push_back(path);
        }
        if (std::find(vrtsBeingRead_.begin(), vrtsBeingRead_.end(), key) != vrtsBeingRead_.end()) {
            fail(where, "the VRT is, through its sources, a source of itself");
        }
        if (readVrts_.count(key)) {
            return; // its files are in the list already
        }
        const fs::file_status status = statusOf(path, where);
        if (!fs::exists(status)) {
            fail(where, "no such file");
        }
        if (!fs::is_regular_file(status)) {
            fail(where, "not a regular file");
        }
        const std::vector<std::string> files = vrtSourceFiles(path, where);
        vrtsBeingRead_.push_back(key);
        for (const std::string& file : files) {
            if (isVrtName(file)) {
                addVrt(file, where, false);
            } else {
                addFile(file, where);
            }
        }
        vrtsBeingRead_.pop_back();
        readVrts_.insert(key);
    }
};

} // namespace

InputList expandInputs(const std::vector<std::string>& arguments, const std::string& listFile) {
    Expansion expansion;
    for (const std::string& argument : arguments) {
        expansion.addArgument(argument, argument, "");
    }
    if (!listFile.empty()) {
        const fs::file_status status = statusOf(listFile, listFile);
        if (!fs::exists(status)) {
            fail(listFile, "no such file");
        }
        if (!fs::is_regular_file(status)) {
            fail(listFile, "not a regular file (a list file names one input a line)");
        }
        std::ifstream in(listFile, std::ios::binary);
        if (!in) {
            fail(listFile, "cannot read");
        }
        const std::string directory = fs::path(listFile).parent_path().string();
        const std::string patternDirectory = escapeGlob(directory);
        std::string line;
        for (int number = 1; std::getline(in, line); ++number) {
            const std::string entry = trim(line);
            if (entry.empty() || entry[0] == '#') {
                continue;
            }
            const bool absolute = fs::path(entry).is_absolute();
            expansion.addArgument(absolute ? entry : resolveAgainst(directory, entry),
                                  absolute ? entry : resolveAgainst(patternDirectory, entry),
                                  listFile + ":" + std::to_string(number));
        }
        if (in.bad()) {
            fail(listFile, "cannot read");
        }
    }
    if (expansion.result.paths.empty()) {
        if (listFile.empty()) {
            throw Error("no input file given");
        }
        fail(listFile, "lists no file, and no other input is given");
    }
    return std::move(expansion.result);
}

} // namespace pyramid
