// libgeotiff, loaded with dlopen the first time a TIFF has GeoKeys. Linking it would load PROJ
// and some 30 shared libraries (curl, sqlite, TLS...) into every program and every engine that
// links libpyramid, for inputs that mostly carry no georeferencing: about 20 ms of start-up and
// 8 MB of memory in each (doc/input.md, "The image I/O module", for the same reasoning). Its
// headers are used as they are; only the functions are looked up.
//
// PROJ, which libgeotiff looks EPSG codes up with (and which loads with it), is asked directly for
// what libgeotiff has no call for: the unit of a vertical CRS (height_unit.hpp), the EPSG code of
// a CRS written as WKT (sidecar_georeference.hpp). Its functions are
// looked up in the same handle, so they too load only with libgeotiff.
#pragma once
#include <geotiff/geo_normalize.h>
#include <geotiff/geo_simpletags.h>
#include <geotiff/geo_tiffp.h> // TIFFMethod, which GTIFSetSimpleTagsMethods fills
#include <geotiff/geotiff.h>
#include <proj.h>

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
    // PROJ's, through libgeotiff's handle.
    decltype(&::proj_context_create) projContextCreate = nullptr;
    decltype(&::proj_context_destroy) projContextDestroy = nullptr;
    decltype(&::proj_create_from_database) projCreateFromDatabase = nullptr;
    decltype(&::proj_get_type) projGetType = nullptr;
    decltype(&::proj_get_name) projGetName = nullptr;
    decltype(&::proj_crs_get_coordinate_system) projCrsGetCoordinateSystem = nullptr;
    decltype(&::proj_cs_get_axis_info) projCsGetAxisInfo = nullptr;
    decltype(&::proj_uom_get_info_from_database) projUomGetInfoFromDatabase = nullptr;
    decltype(&::proj_destroy) projDestroy = nullptr;
    // A WKT CRS's EPSG code (sidecar_georeference.hpp).
    decltype(&::proj_create) projCreate = nullptr;
    decltype(&::proj_identify) projIdentify = nullptr;
    decltype(&::proj_list_get_count) projListGetCount = nullptr;
    decltype(&::proj_list_get) projListGet = nullptr;
    decltype(&::proj_list_destroy) projListDestroy = nullptr;
    decltype(&::proj_int_list_destroy) projIntListDestroy = nullptr;
    decltype(&::proj_get_id_auth_name) projGetIdAuthName = nullptr;
    decltype(&::proj_get_id_code) projGetIdCode = nullptr;
};

// The library (loaded once, thread-safe), or nullptr with `why` set (one clause: what could not
// be loaded).
const GeoTiffLibrary* geoTiffLibrary(std::string& why);

} // namespace pyramid
