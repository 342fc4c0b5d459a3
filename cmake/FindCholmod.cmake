# Finds CHOLMOD from SuiteSparse (Debian's libsuitesparse-dev ships no CMake config in 5.x).
# Defines the imported targets Cholmod::Cholmod and Cholmod::Umfpack (UMFPACK, the sparse LU of
# non-symmetric systems, from the same package).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(UMFPACK_LIBRARY umfpack)
find_library(SUITESPARSE_CONFIG_LIBRARY suitesparseconfig)
find_library(AMD_LIBRARY amd)
find_library(COLAMD_LIBRARY colamd)
find_library(CAMD_LIBRARY camd)
find_library(CCOLAMD_LIBRARY ccolamd)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Cholmod
  REQUIRED_VARS CHOLMOD_LIBRARY UMFPACK_LIBRARY CHOLMOD_INCLUDE_DIR SUITESPARSE_CONFIG_LIBRARY AMD_LIBRARY COLAMD_LIBRARY)

if(Cholmod_FOUND AND NOT TARGET Cholmod::Cholmod)
  add_library(Cholmod::Cholmod UNKNOWN IMPORTED)
  set_target_properties(Cholmod::Cholmod PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}")
  set(_deps ${SUITESPARSE_CONFIG_LIBRARY} ${AMD_LIBRARY} ${COLAMD_LIBRARY})
  if(CAMD_LIBRARY)
    list(APPEND _deps ${CAMD_LIBRARY})
  endif()
  if(CCOLAMD_LIBRARY)
    list(APPEND _deps ${CCOLAMD_LIBRARY})
  endif()
  set_property(TARGET Cholmod::Cholmod PROPERTY INTERFACE_LINK_LIBRARIES "${_deps}")
  add_library(Cholmod::Umfpack UNKNOWN IMPORTED)
  set_target_properties(Cholmod::Umfpack PROPERTIES
    IMPORTED_LOCATION "${UMFPACK_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "Cholmod::Cholmod")
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY UMFPACK_LIBRARY SUITESPARSE_CONFIG_LIBRARY AMD_LIBRARY COLAMD_LIBRARY CAMD_LIBRARY CCOLAMD_LIBRARY)
