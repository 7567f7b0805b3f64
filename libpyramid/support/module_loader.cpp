#include "libpyramid/support/module_loader.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#ifndef PYRAMID_MODULE_INSTALL_DIR
#define PYRAMID_MODULE_INSTALL_DIR "../lib/libpyramid"
#endif

namespace pyramid {

namespace {

std::vector<std::string> candidatePaths(const ModuleLocation& where) {
    std::vector<std::string> paths;
    if (const char* env = ::secure_getenv(where.variable); env && *env) {
        paths.emplace_back(env);
        return paths; // an explicit choice is not second-guessed
    }
    Dl_info self{};
    if (dladdr(reinterpret_cast<void*>(&loadModule), &self) != 0 && self.dli_fname) {
        const std::filesystem::path here = std::filesystem::path(self.dli_fname).parent_path();
        paths.push_back((here / where.fileName).string());
        // An installed program: the modules are in the library directory (cmake/install.cmake).
        paths.push_back((here / PYRAMID_MODULE_INSTALL_DIR / where.fileName).lexically_normal().string());
    }
    if (where.buildPath && *where.buildPath) {
        paths.emplace_back(where.buildPath);
    }
    return paths;
}

} // namespace

LoadedModule loadModule(const ModuleLocation& where, const char* entrySymbol, bool global,
                        const std::function<bool(void* entry)>& accepts) {
    LoadedModule result;
    for (const std::string& path : candidatePaths(where)) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
            result.why = path + " not found";
            continue;
        }
        void* handle = dlopen(path.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL));
        if (!handle) {
            const char* e = dlerror();
            result.why = e ? e : path + ": dlopen failed";
            continue;
        }
        void* entry = dlsym(handle, entrySymbol);
        if (!entry || !accepts(entry)) {
            result.why = path + " is from another build of libpyramid";
            continue;
        }
        result.entry = entry;
        result.why.clear();
        return result;
    }
    if (result.why.empty()) {
        result.why = std::string(where.fileName) + " not found";
    }
    return result;
}

} // namespace pyramid
