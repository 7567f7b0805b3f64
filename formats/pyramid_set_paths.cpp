// Which files a path names (pyramid_set.hpp): an index, the index beside a pyramid file or the
// file alone, a directory's one index; and the pyramids under a directory.
#include "formats/pyramid_set.hpp"

#include <algorithm>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "formats/error.hpp"

namespace pyramid {

namespace fs = std::filesystem;

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A path of the index, relative to the index's directory.
std::string besideIndex(const std::string& index, const std::string& file) {
    const fs::path dir = fs::path(index).parent_path();
    return dir.empty() ? file : (dir / file).string();
}

} // namespace

std::string findRegionIndex(const std::string& path) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) {
        return endsWith(path, ".json") ? path : std::string(); // for the readers' own messages
    }
    if (fs::is_directory(status)) {
        std::vector<std::string> found;
        for (const fs::directory_entry& e : fs::directory_iterator(path, ec)) {
            const std::string name = e.path().filename().string();
            if (endsWith(name, kRegionIndexSuffix) && e.is_regular_file()) {
                found.push_back(name);
            }
        }
        if (ec) {
            fail(path, "cannot list the directory: " + ec.message());
        }
        std::sort(found.begin(), found.end());
        if (found.empty()) {
            fail(path, std::string("no region set index (*") + kRegionIndexSuffix + ") in this directory");
        }
        if (found.size() > 1) {
            std::string names;
            for (const std::string& f : found) {
                names += (names.empty() ? "" : ", ") + f;
            }
            fail(path, "several region set indexes in this directory (" + names + "): name one");
        }
        return (fs::path(path) / found.front()).string();
    }
    if (endsWith(path, ".json")) {
        return path;
    }
    const std::string beside = regionIndexPath(path);
    return fs::exists(beside, ec) ? beside : std::string();
}

PyramidSet resolvePyramidSet(const std::string& path) {
    PyramidSet set;
    set.index = findRegionIndex(path);
    if (set.index.empty()) {
        set.main = path;
        set.kind = detectPyramidKind(path);
        return set;
    }
    const RegionIndex index = readRegionIndex(set.index);
    set.kind = index.kind;
    // A main file named by the user keeps the user's spelling in messages.
    const bool named = set.index != path && fs::path(path).filename() == fs::path(index.main).filename() &&
                       !fs::is_directory(path);
    set.main = named ? path : besideIndex(set.index, index.main);
    for (const RegionEntry& e : index.regions) {
        set.regions.push_back(besideIndex(set.index, e.file));
        set.roots.push_back(e.root);
    }
    return set;
}

PyramidsUnder pyramidsUnder(const std::string& directory) {
    PyramidsUnder found;
    std::vector<std::string> dats;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(directory, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
        if (!it->is_regular_file(ec)) {
            continue;
        }
        const std::string path = it->path().string();
        if (endsWith(path, kRegionIndexSuffix)) {
            found.sets.push_back(path);
        } else if (endsWith(path, ".dat")) {
            dats.push_back(path);
        }
    }
    if (ec) {
        fail(directory, "cannot list the directory: " + ec.message());
    }
    std::sort(found.sets.begin(), found.sets.end());
    std::sort(dats.begin(), dats.end());
    std::vector<std::string> listed; // the files the indexes name
    for (const std::string& index : found.sets) {
        try {
            const PyramidSet set = resolvePyramidSet(index);
            listed.push_back(fs::weakly_canonical(set.main).string());
            for (const std::string& r : set.regions) {
                listed.push_back(fs::weakly_canonical(r).string());
            }
        } catch (const Error&) {
            // a bad index: its problems are the set's
        }
    }
    std::sort(listed.begin(), listed.end());
    for (const std::string& dat : dats) {
        if (!std::binary_search(listed.begin(), listed.end(), fs::weakly_canonical(dat).string())) {
            found.files.push_back(dat);
        }
    }
    return found;
}

} // namespace pyramid
