# FindERFA: the Essential Routines for Fundamental Astronomy (Debian liberfa-dev), the open library of
# the IAU SOFA standards that satgnc uses for time scales and Earth orientation. ERFA ships a pkg-config
# file and no CMake package, hence this module. Defines the imported target ERFA::erfa.
find_path(ERFA_INCLUDE_DIR erfa.h)
find_library(ERFA_LIBRARY NAMES erfa)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(ERFA REQUIRED_VARS ERFA_LIBRARY ERFA_INCLUDE_DIR
  REASON_FAILURE_MESSAGE "install Debian's liberfa-dev (scripts/setup-system.sh does)")
if(ERFA_FOUND AND NOT TARGET ERFA::erfa)
  add_library(ERFA::erfa UNKNOWN IMPORTED)
  set_target_properties(ERFA::erfa PROPERTIES IMPORTED_LOCATION "${ERFA_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${ERFA_INCLUDE_DIR}")
endif()
mark_as_advanced(ERFA_INCLUDE_DIR ERFA_LIBRARY)
