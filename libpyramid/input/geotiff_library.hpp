// libgeotiff, loaded with dlopen the first time a TIFF has GeoKeys. Linking it would load PROJ
// and some 30 shared libraries (curl, sqlite, TLS...) into every program and every engine that
// links libpyramid, for inputs that mostly carry no georeferencing: about 20 ms of start-up and
// 8 MB of memory in each (doc/input.md, "The image I/O module", for the same reasoning). Its
// headers are used as they are; only the functions are looked up.
#pragma once
#include <geotiff/geo_normalize.h>
#include <geotiff/geo_simpletags.h>
#include <geotiff/geo_tiffp.h> // TIFFMethod, which GTIFSetSimpleTagsMethods fills
#include <geotiff/geotiff.h>

#include <string>

namespace pyramid {

struct GeoTiffLibrary {
    decltype(&::ST_Create) stCreate = nullptr;
    decltype(&::ST_SetKey) stSetKey = nullptr;
    decltype(&::ST_Destroy) stDestroy = nullptr;
    decltype(&::GTIFSetSimpleTagsMethods) setSimpleTagsMethods = nullptr;
    decltype(&::GTIFNewWithMethodsEx) newWithMethods = nullptr;
    decltype(&::GTIFFree) free = nullptr;
    decltype(&::GTIFKeyInfo) keyInfo = nullptr;
    decltype(&::GTIFKeyGet) keyGet = nullptr;
    decltype(&::GTIFAllocDefn) allocDefn = nullptr;
    decltype(&::GTIFFreeDefn) freeDefn = nullptr;
    decltype(&::GTIFGetDefn) getDefn = nullptr;
    decltype(&::GTIFGetPCSInfo) pcsInfo = nullptr;
    decltype(&::GTIFGetGCSInfo) gcsInfo = nullptr;
    decltype(&::GTIFFreeMemory) freeMemory = nullptr;
};

// The library (loaded once, thread-safe), or nullptr with `why` set (one clause: what could not
// be loaded).
const GeoTiffLibrary* geoTiffLibrary(std::string& why);

} // namespace pyramid
