#include "libpyramid/input/image_io_module.hpp"

#include <mutex>

#include "formats/error.hpp"
#include "libpyramid/support/module_loader.hpp"

#ifndef PYRAMID_OIIO_MODULE_BUILD_PATH
#define PYRAMID_OIIO_MODULE_BUILD_PATH ""
#endif

namespace pyramid {

namespace {

struct Loaded {
    const ImageIoModule* module = nullptr;
    std::string why; // when not loaded
};

Loaded load() {
    using Entry = const ImageIoModule* (*)();
    const LoadedModule loaded = loadModule(
        {"libpyramid_oiio.so", "PYRAMID_OIIO_MODULE", PYRAMID_OIIO_MODULE_BUILD_PATH}, "pyramid_image_io_module",
        false, [](void* entry) {
            const ImageIoModule* module = reinterpret_cast<Entry>(entry)();
            return module && module->abi == kImageIoModuleAbi;
        });
    Loaded result;
    result.why = loaded.why;
    if (loaded.entry) {
        result.module = reinterpret_cast<Entry>(loaded.entry)();
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
