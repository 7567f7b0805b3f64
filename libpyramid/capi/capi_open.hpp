// How the C API's producers open (pyramid.h: *_open, *_open_regions, *_open_sources), the
// elevation producer (pyramid_elevation.cpp) and the ortho producer (pyramid_ortho.cpp) alike: a
// path's files or set, region paths as path sources, sources made and armed once the producer is
// built. Each producer's opens end in one function that takes the name of the call made, for its
// messages.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "formats/byte_source.hpp"
#include "formats/pyramid_set.hpp"
#include "libpyramid/capi/capi_sized.hpp"
#include "libpyramid/capi/capi_sources.hpp"
#include "libpyramid/capi/capi_status.hpp"
#include "libpyramid/capi/pyramid.h"

namespace pyramid::capi {

// The region paths of an *_open_regions call as path sources; false when the array or one of
// its paths is null.
inline bool regionList(const char* const* paths, size_t count, std::vector<pyramid_source>& sources,
                       std::vector<const pyramid_source*>& pointers) {
    if (count > 0 && !paths) {
        return false;
    }
    for (size_t k = 0; k < count; ++k) {
        if (!paths[k]) {
            return false;
        }
        sources.push_back(pathSource(paths[k]));
    }
    for (const pyramid_source& s : sources) {
        pointers.push_back(&s);
    }
    return true;
}

// The files a path names (formats/pyramid_set.hpp): a pyramid file alone, or the main file and
// the regions of a set named by its main file (its index beside it), its index or its
// directory. files[0] is the main file; `regions` points into files[1..].
inline pyramid_status setFiles(const char* path, const char* function, std::vector<std::string>& files,
                               std::vector<const char*>& regions) {
    if (!path) {
        return failWith(PYRAMID_ERROR_ARGUMENT, std::string(function) + ": null argument");
    }
    return guarded([&] {
        if (pyramid::findRegionIndex(path).empty()) {
            files = {path}; // a file alone: its reader says what is wrong with it
            return PYRAMID_OK;
        }
        const pyramid::PyramidSet set = pyramid::openPyramidSet(path);
        files.push_back(set.main);
        files.insert(files.end(), set.regions.begin(), set.regions.end());
        for (size_t k = 1; k < files.size(); ++k) {
            regions.push_back(files[k].c_str());
        }
        return PYRAMID_OK;
    });
}

using ByteSourcePtr = std::shared_ptr<const pyramid::ByteSource>;

// The three ways a producer opens, one protocol for every kind of producer; `*producer` is null
// whenever the open fails.
//
// *_open(path): the files the path names (setFiles), opened as *_open_regions opens them.
template <class Producer, class OpenRegions>
pyramid_status openPath(const char* path, const char* function, Producer** producer, OpenRegions openRegions) {
    std::vector<std::string> files;
    std::vector<const char*> regions;
    if (const pyramid_status s = setFiles(path, function, files, regions); s != PYRAMID_OK) {
        if (producer) {
            *producer = nullptr;
        }
        return s;
    }
    return openRegions(files[0].c_str(), regions.data(), regions.size());
}

// *_open_regions(path, region paths): the paths as path sources, opened as *_open_sources opens
// them (`function` names the call in the message of a null argument).
template <class Producer, class OpenSources>
pyramid_status openRegionPaths(const char* path, const char* const* regionPaths, size_t regionCount,
                               const char* function, Producer** producer, OpenSources openSources) {
    std::vector<pyramid_source> regions;
    std::vector<const pyramid_source*> pointers;
    if (!path || !producer || !regionList(regionPaths, regionCount, regions, pointers)) {
        if (producer) {
            *producer = nullptr;
        }
        return failWith(PYRAMID_ERROR_ARGUMENT, std::string(function) + ": null argument");
    }
    const pyramid_source main = pathSource(path);
    return openSources(&main, pointers.data(), regionCount);
}

// *_open_sources(sources, options): the options read by their size and the sources made, then
// `build(options, main, regions, made)`; when it returns PYRAMID_OK the caller's I/O sources are
// armed (SourceSet) and `made` is handed over.
template <class Options, class Producer, class Build>
pyramid_status openSources(const pyramid_source* main, const pyramid_source* const* regions, size_t regionCount,
                           const Options* options, const char* function, Producer** producer, Build build) {
    if (!producer) {
        return failWith(PYRAMID_ERROR_ARGUMENT, std::string(function) + ": null argument");
    }
    *producer = nullptr;
    Options o{}; // a member the caller's struct lacks is zero
    if (!readSized(options, o, (std::string(function) + ": options").c_str())) {
        return PYRAMID_ERROR_ARGUMENT;
    }
    return guarded([&] {
        SourceSet sources;
        ByteSourcePtr mainBytes;
        std::vector<ByteSourcePtr> regionBytes;
        if (!sources.makeAll(main, regions, regionCount, function, mainBytes, regionBytes)) {
            return PYRAMID_ERROR_ARGUMENT;
        }
        std::unique_ptr<Producer> made;
        const pyramid_status s = build(o, mainBytes, regionBytes, made);
        if (s == PYRAMID_OK) {
            sources.arm();
            *producer = made.release();
        }
        return s;
    });
}

} // namespace pyramid::capi
