# Finds the parts of Debian's SuiteSparse 5.x that conserve uses.
# Debian ships neither a CMake config nor a .pc file for it, so each library
# is looked up by name. Defines the imported target SuiteSparse::SuiteSparse.
find_path(SuiteSparse_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
set(_ss_libs umfpack cholmod klu btf amd camd colamd ccolamd suitesparseconfig metis)
set(SuiteSparse_LIBRARIES "")
foreach(lib IN LISTS _ss_libs)
  find_library(SuiteSparse_${lib}_LIBRARY NAMES ${lib})
  if(SuiteSparse_${lib}_LIBRARY)
    list(APPEND SuiteSparse_LIBRARIES ${SuiteSparse_${lib}_LIBRARY})
  else()
    list(APPEND _ss_missing ${lib})
  endif()
endforeach()
find_package(BLAS REQUIRED)
find_package(LAPACK REQUIRED)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparse
  REQUIRED_VARS SuiteSparse_INCLUDE_DIR SuiteSparse_umfpack_LIBRARY SuiteSparse_cholmod_LIBRARY
  REASON_FAILURE_MESSAGE "missing libraries [${_ss_missing}], run scripts/install-deps.sh")
if(SuiteSparse_FOUND AND NOT TARGET SuiteSparse::SuiteSparse)
  add_library(SuiteSparse::SuiteSparse INTERFACE IMPORTED)
  set_target_properties(SuiteSparse::SuiteSparse PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${SuiteSparse_LIBRARIES};${LAPACK_LIBRARIES};${BLAS_LIBRARIES}")
endif()
