# Finds TetGen 1.5 built as a library (Debian's libtet1.5-dev: tetgen.h and libtet.so, no CMake
# package configuration). Defines TetGen_FOUND and the imported target TetGen::tet; the `tetra`
# structure uses it for its constrained Delaunay tetrahedralization.
find_path(TetGen_INCLUDE_DIR tetgen.h)
find_library(TetGen_LIBRARY NAMES tet)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(TetGen REQUIRED_VARS TetGen_LIBRARY TetGen_INCLUDE_DIR)
if(TetGen_FOUND AND NOT TARGET TetGen::tet)
  add_library(TetGen::tet UNKNOWN IMPORTED)
  set_target_properties(TetGen::tet PROPERTIES
    IMPORTED_LOCATION "${TetGen_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${TetGen_INCLUDE_DIR}")
endif()
mark_as_advanced(TetGen_INCLUDE_DIR TetGen_LIBRARY)
