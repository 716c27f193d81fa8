# Finds OpenSubdiv's CPU library. Debian's libosd-dev ships headers and libosdCPU.so but no CMake
# package configuration, so this looks for them directly. Defines OpenSubdiv_FOUND,
# OpenSubdiv_VERSION and the imported target OpenSubdiv::osdCPU. Thicket needs 3.5 or newer
# (the Bfr limit evaluation appeared in 3.5).
find_path(OpenSubdiv_INCLUDE_DIR opensubdiv/version.h)
find_library(OpenSubdiv_osdCPU_LIBRARY NAMES osdCPU)
if(OpenSubdiv_INCLUDE_DIR AND EXISTS "${OpenSubdiv_INCLUDE_DIR}/opensubdiv/version.h")
  file(STRINGS "${OpenSubdiv_INCLUDE_DIR}/opensubdiv/version.h" _osd_version
       REGEX "^#define OPENSUBDIV_VERSION_(MAJOR|MINOR|PATCH) [0-9]+")
  string(REGEX REPLACE ".*MAJOR ([0-9]+).*MINOR ([0-9]+).*PATCH ([0-9]+).*" "\\1.\\2.\\3"
         OpenSubdiv_VERSION "${_osd_version}")
endif()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenSubdiv
  REQUIRED_VARS OpenSubdiv_osdCPU_LIBRARY OpenSubdiv_INCLUDE_DIR
  VERSION_VAR OpenSubdiv_VERSION)
if(OpenSubdiv_FOUND AND NOT TARGET OpenSubdiv::osdCPU)
  add_library(OpenSubdiv::osdCPU UNKNOWN IMPORTED)
  set_target_properties(OpenSubdiv::osdCPU PROPERTIES
    IMPORTED_LOCATION "${OpenSubdiv_osdCPU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OpenSubdiv_INCLUDE_DIR}")
endif()
mark_as_advanced(OpenSubdiv_INCLUDE_DIR OpenSubdiv_osdCPU_LIBRARY)
