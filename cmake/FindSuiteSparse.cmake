# Debian 12's SuiteSparse 5.12 ships no CMake package for CHOLMOD and AMD: find them by hand.
# Defines SuiteSparse::cholmod and SuiteSparse::amd.
find_path(SuiteSparse_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(SuiteSparse_CHOLMOD_LIBRARY cholmod)
find_library(SuiteSparse_AMD_LIBRARY amd)
find_library(SuiteSparse_CONFIG_LIBRARY suitesparseconfig)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparse REQUIRED_VARS
  SuiteSparse_INCLUDE_DIR SuiteSparse_CHOLMOD_LIBRARY SuiteSparse_AMD_LIBRARY SuiteSparse_CONFIG_LIBRARY)
if(SuiteSparse_FOUND AND NOT TARGET SuiteSparse::cholmod)
  add_library(SuiteSparse::config UNKNOWN IMPORTED)
  set_target_properties(SuiteSparse::config PROPERTIES IMPORTED_LOCATION ${SuiteSparse_CONFIG_LIBRARY}
    INTERFACE_INCLUDE_DIRECTORIES ${SuiteSparse_INCLUDE_DIR})
  add_library(SuiteSparse::amd UNKNOWN IMPORTED)
  set_target_properties(SuiteSparse::amd PROPERTIES IMPORTED_LOCATION ${SuiteSparse_AMD_LIBRARY}
    INTERFACE_LINK_LIBRARIES SuiteSparse::config)
  add_library(SuiteSparse::cholmod UNKNOWN IMPORTED)
  set_target_properties(SuiteSparse::cholmod PROPERTIES IMPORTED_LOCATION ${SuiteSparse_CHOLMOD_LIBRARY}
    INTERFACE_LINK_LIBRARIES SuiteSparse::config)
endif()
mark_as_advanced(SuiteSparse_INCLUDE_DIR SuiteSparse_CHOLMOD_LIBRARY SuiteSparse_AMD_LIBRARY SuiteSparse_CONFIG_LIBRARY)
