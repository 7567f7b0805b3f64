// The library's modules: parts built as shared objects of their own and loaded with dlopen only
// when a run needs them, so that every other run skips their libraries' loading and start-up
// (libpyramid_oiio.so: OpenImageIO, input/image_io_module.hpp; libpyramid_mpi.so: Open MPI,
// distribute/team.hpp).
#pragma once
#include <functional>
#include <string>

namespace pyramid {

struct ModuleLocation {
    const char* fileName;  // "libpyramid_oiio.so"
    const char* variable;  // the environment variable that names it ("PYRAMID_OIIO_MODULE")
    const char* buildPath; // where this build put it ("" when unknown)
};

struct LoadedModule {
    void* entry = nullptr; // the entry point's address; null when not loaded
    std::string why;       // when not loaded: one line, the last place tried and its failure
};

// Loads a module and finds its entry point (`entrySymbol`), looking in order: $variable if set
// (and then only there), beside the library or program that holds this code, in the installed
// library directory seen from there (<prefix>/lib/libpyramid/ for a program in <prefix>/bin/),
// where the build put it. The variable is read with secure_getenv: a set-user-ID or
// file-capability program never loads a module its caller chose. `global` makes the module's
// symbols, and its libraries', visible to objects loaded later (RTLD_GLOBAL). `accepts` checks
// the entry point (a module from another build is refused: the next place is tried). A loaded
// module is never unloaded.
LoadedModule loadModule(const ModuleLocation& where, const char* entrySymbol, bool global,
                        const std::function<bool(void* entry)>& accepts);

} // namespace pyramid
