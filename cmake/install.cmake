# Installation (README.md, "Installing and linking"): the libraries, the public headers, the
# programs, the image I/O module, the docs, a CMake package (find_package(libpyramid
# COMPONENTS runtime gl preprocess)) and a pkg-config file per library.
include(CMakePackageConfigHelpers)
set(PYRAMID_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/libpyramid)
set(PYRAMID_PKGCONFIG_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

set(PYRAMID_INSTALL_LIBRARIES pyramid_runtime pyramid_runtime_static pyramid_preprocess)
if(TARGET pyramid_gl)
  list(APPEND PYRAMID_INSTALL_LIBRARIES pyramid_gl)
endif()
install(TARGETS ${PYRAMID_INSTALL_LIBRARIES} EXPORT libpyramidTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS ${PYRAMID_PROGRAMS} # cli/CMakeLists.txt
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(PYRAMID_MAN_PAGES)
  install(FILES ${PYRAMID_MAN_PAGES} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1) # cli/CMakeLists.txt
endif()
# The C API's encode functions as a shared library, for FFIs (python/): no CMake target of the
# package (C and C++ programs link libpyramid::preprocess).
install(TARGETS pyramid_encode LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
# `pyramid serve`'s web viewer (cmake/viewer.cmake), found by the programs at
# <bindir>/../share/libpyramid/viewer (libpyramid/serve/viewer_files.hpp).
install(DIRECTORY ${PYRAMID_VIEWER_DIR}/ DESTINATION ${CMAKE_INSTALL_DATADIR}/libpyramid/viewer)
# The modules, found by the programs at <bindir>/PYRAMID_MODULE_INSTALL_DIR (libpyramid/CMakeLists.txt).
install(TARGETS pyramid_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/libpyramid)
if(PYRAMID_MPI_ENABLED)
  install(TARGETS pyramid_mpi LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/libpyramid)
endif()

# Headers: <prefix>/include/libpyramid/{formats,runtime,capi,...}. Consumers include
# "libpyramid/capi/pyramid.h" (through <prefix>/include); the headers' own "formats/..." resolve
# through <prefix>/include/libpyramid, which the packages add too.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/formats DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/libpyramid
        FILES_MATCHING PATTERN "*.hpp")
set(PYRAMID_HEADER_FOLDERS support filters input sphere encode runtime verify preview distribute api capi)
if(TARGET pyramid_gl)
  list(APPEND PYRAMID_HEADER_FOLDERS gl)
endif()
foreach(folder ${PYRAMID_HEADER_FOLDERS})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/libpyramid/${folder} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/libpyramid
          FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h" PATTERN "oiio" EXCLUDE)
endforeach()

# doc/ beside README.md as in the sources, so that the links between them hold where installed.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/doc/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/doc)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})

# The CMake package.
set(PYRAMID_HAS_GL FALSE)
if(TARGET pyramid_gl)
  set(PYRAMID_HAS_GL TRUE)
endif()
install(EXPORT libpyramidTargets NAMESPACE libpyramid:: DESTINATION ${PYRAMID_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/libpyramidConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/libpyramidConfig.cmake INSTALL_DESTINATION ${PYRAMID_CMAKE_DIR})
# 0.x: a minor version may break compatibility, as the soname says (libpyramid/CMakeLists.txt).
write_basic_package_version_file(${PROJECT_BINARY_DIR}/libpyramidConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/libpyramidConfig.cmake ${PROJECT_BINARY_DIR}/libpyramidConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/libpyramidDependencies.cmake DESTINATION ${PYRAMID_CMAKE_DIR})

# pkg-config: relocatable (the prefix is found from the .pc file's own place), so that
# `cmake --install --prefix` anywhere gives working files.
file(RELATIVE_PATH PYRAMID_PC_PREFIX /${PYRAMID_PKGCONFIG_DIR} /)
string(REGEX REPLACE "/$" "" PYRAMID_PC_PREFIX "${PYRAMID_PC_PREFIX}")
set(PYRAMID_PC_PACKAGES libpyramid-runtime libpyramid-preprocess)
if(TARGET pyramid_gl)
  list(APPEND PYRAMID_PC_PACKAGES libpyramid-gl)
endif()
foreach(pc ${PYRAMID_PC_PACKAGES})
  configure_file(${CMAKE_CURRENT_LIST_DIR}/${pc}.pc.in ${PROJECT_BINARY_DIR}/${pc}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/${pc}.pc DESTINATION ${PYRAMID_PKGCONFIG_DIR})
endforeach()
