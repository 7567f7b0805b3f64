# `pyramid serve`'s web viewer (doc/cli/pyramid-serve.md, "The viewer"): the files of web/ and
# three.js from Debian's libjs-three (scripts/install-deps.sh), copied into <build>/viewer when
# the programs are built; cmake/install.cmake installs them to <datadir>/libpyramid/viewer.
set(PYRAMID_VIEWER_DIR ${PROJECT_BINARY_DIR}/viewer)
file(MAKE_DIRECTORY ${PYRAMID_VIEWER_DIR})
file(GLOB PYRAMID_VIEWER_SOURCES LIST_DIRECTORIES false CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/web/*)
list(FILTER PYRAMID_VIEWER_SOURCES EXCLUDE REGEX "/(README\\.md|CMakeLists\\.txt)$")
set(PYRAMID_THREE_DIR /usr/share/javascript/three)
set(PYRAMID_THREE_FILES ${PYRAMID_THREE_DIR}/three.min.js ${PYRAMID_THREE_DIR}/examples/js/controls/OrbitControls.js
    ${PYRAMID_THREE_DIR}/examples/js/controls/FlyControls.js)
foreach(file ${PYRAMID_THREE_FILES})
  if(EXISTS ${file})
    list(APPEND PYRAMID_VIEWER_SOURCES ${file})
  else()
    message(WARNING "${file} not found: the web viewer will lack it (scripts/install-deps.sh installs libjs-three)")
  endif()
endforeach()
set(PYRAMID_VIEWER_FILES)
foreach(file ${PYRAMID_VIEWER_SOURCES})
  get_filename_component(name ${file} NAME)
  add_custom_command(OUTPUT ${PYRAMID_VIEWER_DIR}/${name}
                     COMMAND ${CMAKE_COMMAND} -E copy_if_different ${file} ${PYRAMID_VIEWER_DIR}/${name}
                     DEPENDS ${file} VERBATIM)
  list(APPEND PYRAMID_VIEWER_FILES ${PYRAMID_VIEWER_DIR}/${name})
endforeach()
add_custom_target(pyramid_viewer ALL DEPENDS ${PYRAMID_VIEWER_FILES})
add_dependencies(pyramid pyramid_viewer)
