# Debian's libtet1.5-dev: tetgen.h + libtet.so, no CMake config. TetGen is AGPL: only the
# mesh-generation target links it (see meshgen/CMakeLists.txt).
include(FindPackageHandleStandardArgs)

find_path(TETGEN_INCLUDE_DIR tetgen.h)
find_library(TETGEN_LIBRARY tet)

find_package_handle_standard_args(TetGen REQUIRED_VARS TETGEN_LIBRARY TETGEN_INCLUDE_DIR)

if(TetGen_FOUND AND NOT TARGET TetGen::tet)
  add_library(TetGen::tet UNKNOWN IMPORTED)
  set_target_properties(TetGen::tet PROPERTIES
    IMPORTED_LOCATION "${TETGEN_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${TETGEN_INCLUDE_DIR}"
    INTERFACE_COMPILE_DEFINITIONS TETLIBRARY)
endif()
mark_as_advanced(TETGEN_INCLUDE_DIR TETGEN_LIBRARY)
