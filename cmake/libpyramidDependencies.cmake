# The libraries of libpyramid::preprocess that come without a CMake package, as imported targets
# for the exported targets to name instead of the building machine's paths:
#   libpyramid_deps::squish          libsquish (DXT)
#   libpyramid_deps::stb             stb (DXT)
#   libpyramid_deps::GeographicLib   GeographicLib (geodesy)
#   libpyramid_deps::geotiff_headers libgeotiff's headers: the library itself is loaded with
#                                    dlopen (libpyramid/input/geotiff_library.hpp)
# Included by the build (CMakeLists.txt) and by the installed package (libpyramidConfig.cmake,
# beside which it is installed). Finds them in the cache variables SQUISH_LIBRARY,
# SQUISH_INCLUDE_DIR, STB_LIBRARY, STB_INCLUDE_DIR, GEOGRAPHICLIB_LIBRARY,
# GEOGRAPHICLIB_INCLUDE_DIR and GEOTIFF_INCLUDE_DIR, and sets PYRAMID_DEPS_MISSING to the
# variables it could not fill (empty when all were found; the targets are then defined).
find_library(SQUISH_LIBRARY squish)
find_path(SQUISH_INCLUDE_DIR squish.h)
find_library(STB_LIBRARY stb)
find_path(STB_INCLUDE_DIR stb/stb_dxt.h)
find_library(GEOGRAPHICLIB_LIBRARY GeographicLib)
find_path(GEOGRAPHICLIB_INCLUDE_DIR GeographicLib/Config.h)
find_path(GEOTIFF_INCLUDE_DIR geotiff/geotiffio.h)

set(PYRAMID_DEPS_MISSING)
foreach(_pyramid_var SQUISH_LIBRARY SQUISH_INCLUDE_DIR STB_LIBRARY STB_INCLUDE_DIR GEOGRAPHICLIB_LIBRARY
                     GEOGRAPHICLIB_INCLUDE_DIR GEOTIFF_INCLUDE_DIR)
  if(NOT ${_pyramid_var})
    list(APPEND PYRAMID_DEPS_MISSING ${_pyramid_var})
  endif()
endforeach()
unset(_pyramid_var)

if(NOT PYRAMID_DEPS_MISSING)
  foreach(_pyramid_dep squish stb GeographicLib)
    string(TOUPPER ${_pyramid_dep} _pyramid_var)
    if(NOT TARGET libpyramid_deps::${_pyramid_dep})
      add_library(libpyramid_deps::${_pyramid_dep} UNKNOWN IMPORTED)
      set_target_properties(libpyramid_deps::${_pyramid_dep} PROPERTIES IMPORTED_LOCATION "${${_pyramid_var}_LIBRARY}"
                            INTERFACE_INCLUDE_DIRECTORIES "${${_pyramid_var}_INCLUDE_DIR}")
    endif()
  endforeach()
  if(NOT TARGET libpyramid_deps::geotiff_headers)
    add_library(libpyramid_deps::geotiff_headers INTERFACE IMPORTED)
    set_target_properties(libpyramid_deps::geotiff_headers PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${GEOTIFF_INCLUDE_DIR}")
  endif()
  unset(_pyramid_dep)
  unset(_pyramid_var)
endif()
