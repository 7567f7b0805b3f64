#include "libpyramid/input/image_io_module.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <vector>

#include "formats/error.hpp"

#ifndef PYRAMID_OIIO_MODULE_BUILD_PATH
#define PYRAMID_OIIO_MODULE_BUILD_PATH ""
#endif
#ifndef PYRAMID_OIIO_MODULE_INSTALL_DIR
#define PYRAMID_OIIO_MODULE_INSTALL_DIR "../lib/libpyramid"
#endif

namespace pyramid {

namespace {

constexpr const char* kModuleFileName = "libpyramid_oiio.so";

// Where to look, in order. The variable names code this process will run: it is read with
// secure_getenv, so that a set-user-ID or file-capability program that links the library
// never loads a module its caller chose (it then looks beside the library only).
std::vector<std::string> candidatePaths() {
    std::vector<std::string> paths;
    if (const char* env = ::secure_getenv("PYRAMID_OIIO_MODULE"); env && *env) {
        paths.emplace_back(env);
        return paths; // an explicit choice is not second-guessed
    }
    Dl_info self{};
    if (dladdr(reinterpret_cast<void*>(&imageIoModule), &self) != 0 && self.dli_fname) {
        const std::filesystem::path here = std::filesystem::path(self.dli_fname).parent_path();
        paths.push_back((here / kModuleFileName).string());
        // An installed program: the module is in the library directory (cmake/install.cmake).
        paths.push_back((here / PYRAMID_OIIO_MODULE_INSTALL_DIR / kModuleFileName).lexically_normal().string());
    }
    if (*PYRAMID_OIIO_MODULE_BUILD_PATH) {
        paths.emplace_back(PYRAMID_OIIO_MODULE_BUILD_PATH);
    }
    return paths;
}

struct Loaded {
    const ImageIoModule* module = nullptr;
    std::string why; // when not loaded
};

Loaded load() {
    Loaded result;
    for (const std::string& path : candidatePaths()) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
            result.why = path + " not found";
            continue;
        }
        // Never closed: the module's ImageCache lives as long as the process.
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* e = dlerror();
            result.why = e ? e : path + ": dlopen failed";
            continue;
        }
        using Entry = const ImageIoModule* (*)();
        const auto entry = reinterpret_cast<Entry>(dlsym(handle, "pyramid_image_io_module"));
        const ImageIoModule* module = entry ? entry() : nullptr;
        if (!module || module->abi != kImageIoModuleAbi) {
            result.why = path + " is from another build of libpyramid";
            continue;
        }
        result.module = module;
        return result;
    }
    if (result.why.empty()) {
        result.why = std::string(kModuleFileName) + " not found";
    }
    return result;
}

} // namespace

const ImageIoModule& imageIoModule(const std::string& who) {
    static std::once_flag once;
    static Loaded loaded;
    std::call_once(once, [] { loaded = load(); });
    if (!loaded.module) {
        fail(who, "needs OpenImageIO, but the image I/O module cannot be loaded (" + loaded.why +
                      "; set PYRAMID_OIIO_MODULE to its path)");
    }
    return *loaded.module;
}

} // namespace pyramid
