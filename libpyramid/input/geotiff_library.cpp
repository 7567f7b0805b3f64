#include "libpyramid/input/geotiff_library.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <mutex>

// The soname the build found (CMake: GEOTIFF_LIBRARY's), e.g. "libgeotiff.so.5".
#ifndef PYRAMID_GEOTIFF_SONAME
#define PYRAMID_GEOTIFF_SONAME "libgeotiff.so.5"
#endif

namespace pyramid {

namespace {

struct Loaded {
    GeoTiffLibrary library;
    bool ok = false;
    std::string why;
};

template <class F>
bool lookUp(void* handle, const char* name, F& f, std::string& why) {
    f = reinterpret_cast<F>(dlsym(handle, name));
    if (!f) {
        why = std::string(PYRAMID_GEOTIFF_SONAME) + " has no " + name;
    }
    return f != nullptr;
}

Loaded load() {
    Loaded l;
    // PROJ, which libgeotiff looks EPSG codes up with, prints its own errors on stderr ("crs not
    // found") unless PROJ_DEBUG says otherwise; the readers say what they cannot use instead. It
    // reads the variable when it is first used, which is through this library.
    setenv("PROJ_DEBUG", "0", 0);
    void* handle = dlopen(PYRAMID_GEOTIFF_SONAME, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* e = dlerror();
        l.why = e ? e : PYRAMID_GEOTIFF_SONAME ": dlopen failed";
        return l;
    }
    GeoTiffLibrary& g = l.library;
    l.ok = lookUp(handle, "ST_Create", g.stCreate, l.why) && lookUp(handle, "ST_SetKey", g.stSetKey, l.why) &&
           lookUp(handle, "ST_Destroy", g.stDestroy, l.why) &&
           lookUp(handle, "GTIFSetSimpleTagsMethods", g.setSimpleTagsMethods, l.why) &&
           lookUp(handle, "GTIFNewWithMethodsEx", g.newWithMethods, l.why) && lookUp(handle, "GTIFFree", g.free, l.why) &&
           lookUp(handle, "GTIFKeyInfo", g.keyInfo, l.why) && lookUp(handle, "GTIFKeyGet", g.keyGet, l.why) &&
           lookUp(handle, "GTIFAllocDefn", g.allocDefn, l.why) && lookUp(handle, "GTIFFreeDefn", g.freeDefn, l.why) &&
           lookUp(handle, "GTIFGetDefn", g.getDefn, l.why) && lookUp(handle, "GTIFGetPCSInfo", g.pcsInfo, l.why) &&
           lookUp(handle, "GTIFGetGCSInfo", g.gcsInfo, l.why) && lookUp(handle, "GTIFFreeMemory", g.freeMemory, l.why) &&
           lookUp(handle, "proj_context_create", g.projContextCreate, l.why) &&
           lookUp(handle, "proj_context_destroy", g.projContextDestroy, l.why) &&
           lookUp(handle, "proj_create_from_database", g.projCreateFromDatabase, l.why) &&
           lookUp(handle, "proj_get_type", g.projGetType, l.why) && lookUp(handle, "proj_get_name", g.projGetName, l.why) &&
           lookUp(handle, "proj_crs_get_coordinate_system", g.projCrsGetCoordinateSystem, l.why) &&
           lookUp(handle, "proj_cs_get_axis_info", g.projCsGetAxisInfo, l.why) &&
           lookUp(handle, "proj_uom_get_info_from_database", g.projUomGetInfoFromDatabase, l.why) &&
           lookUp(handle, "proj_destroy", g.projDestroy, l.why) && lookUp(handle, "proj_create", g.projCreate, l.why) &&
           lookUp(handle, "proj_identify", g.projIdentify, l.why) &&
           lookUp(handle, "proj_list_get_count", g.projListGetCount, l.why) &&
           lookUp(handle, "proj_list_get", g.projListGet, l.why) &&
           lookUp(handle, "proj_list_destroy", g.projListDestroy, l.why) &&
           lookUp(handle, "proj_int_list_destroy", g.projIntListDestroy, l.why) &&
           lookUp(handle, "proj_get_id_auth_name", g.projGetIdAuthName, l.why) &&
           lookUp(handle, "proj_get_id_code", g.projGetIdCode, l.why);
    return l; // the handle stays open for the process's life
}

} // namespace

const GeoTiffLibrary* geoTiffLibrary(std::string& why) {
    static std::once_flag once;
    static Loaded loaded;
    std::call_once(once, [] { loaded = load(); });
    why = loaded.why;
    return loaded.ok ? &loaded.library : nullptr;
}

} // namespace pyramid
