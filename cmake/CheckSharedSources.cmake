# gfmd_check_shared_sources(source...): stops the configure when a source that is compiled once for
# both libraries (libgfmd and libgfmd_mpi: the object library gfmd_core) reads GFMD_MPI -- its one
# object could then be right for only one of them.
# Also a script, for the test that proves the refusal (tests/CMakeLists.txt, shared_sources_check):
#   cmake -DSOURCES="a.cpp|b.cpp" -P CheckSharedSources.cmake   ("|" or ";" between the sources)
function(gfmd_check_shared_sources)
  foreach(source ${ARGN})
    file(STRINGS ${source} mpi_lines REGEX "GFMD_MPI")
    if(mpi_lines)
      message(FATAL_ERROR "${source} reads GFMD_MPI: add it to GFMD_VARIANT_SOURCES")
    endif()
  endforeach()
endfunction()

if(CMAKE_SCRIPT_MODE_FILE)
  if(NOT DEFINED SOURCES)
    message(FATAL_ERROR "usage: cmake -DSOURCES=<list of sources> -P CheckSharedSources.cmake")
  endif()
  string(REPLACE "|" ";" SOURCES "${SOURCES}")
  gfmd_check_shared_sources(${SOURCES})
  message(STATUS "no shared source reads GFMD_MPI")
endif()
