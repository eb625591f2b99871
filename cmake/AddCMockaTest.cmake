# gfmd_add_cmocka_test(<name> SOURCES <files...> [LIBS <libs...>] [TIMEOUT <seconds>])
# One CMocka executable per unit, registered with ctest under its own name.
function(gfmd_add_cmocka_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE gfmd::gfmd PkgConfig::CMOCKA m ${ARG_LIBS})
  target_compile_options(${name} PRIVATE $<$<C_COMPILER_ID:GNU,Clang>:-Wall -Wextra>)
  add_test(NAME ${name} COMMAND ${name})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  # One thread per test: ctest -j runs tests side by side on the same cores, and OpenMP threads
  # that wait for each other on an oversubscribed core slow down tenfold. test_threads checks
  # the threaded paths on purpose.
  set_tests_properties(${name} PROPERTIES TIMEOUT ${ARG_TIMEOUT} LABELS "unit" ENVIRONMENT "OMP_NUM_THREADS=1")
endfunction()
