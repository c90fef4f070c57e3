# Finds libccd (Debian: libccd-dev), the GJK/EPA/MPR peer linked only into benchmarks.
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(PC_CCD QUIET ccd)
endif()
find_path(CCD_INCLUDE_DIR ccd/ccd.h HINTS ${PC_CCD_INCLUDE_DIRS})
find_library(CCD_LIBRARY ccd HINTS ${PC_CCD_LIBRARY_DIRS})
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CCD REQUIRED_VARS CCD_LIBRARY CCD_INCLUDE_DIR)
if(CCD_FOUND AND NOT TARGET CCD::ccd)
  add_library(CCD::ccd UNKNOWN IMPORTED)
  set_target_properties(CCD::ccd PROPERTIES IMPORTED_LOCATION "${CCD_LIBRARY}"
                                            INTERFACE_INCLUDE_DIRECTORIES "${CCD_INCLUDE_DIR}"
                                            INTERFACE_COMPILE_DEFINITIONS "${PC_CCD_CFLAGS_OTHER}")
endif()
mark_as_advanced(CCD_INCLUDE_DIR CCD_LIBRARY)
