# libgfmd_mpi (GFMD_BUILD_MPI): the serial library's core and C API (the objects of gfmd_core, and
# checkpoint.cpp and fft_grid.cpp compiled again with GFMD_MPI), plus the distributed grid and
# gfmd_mpi.h.  It exports every gfmd_* symbol of libgfmd and its own (abi/gfmd_mpi.symbols): a
# program links one of the two.  libgfmd itself never sees MPI.
find_package(MPI REQUIRED COMPONENTS C CXX)
# Debian ships no pkg-config file for FFTW's MPI library: find it beside libfftw3.
find_library(FFTW3_MPI_LIBRARY NAMES fftw3_mpi HINTS ${FFTW3_LIBRARY_DIRS} REQUIRED)
find_path(FFTW3_MPI_INCLUDE_DIR fftw3-mpi.h HINTS ${FFTW3_INCLUDE_DIRS} REQUIRED)

add_library(gfmd_mpi ${GFMD_VARIANT_SOURCES} $<TARGET_OBJECTS:gfmd_core> ${GFMD_KERNEL_OBJECTS}
  src/mpi/fft_grid_mpi.cpp src/mpi/c_api_mpi.cpp src/mpi/checkpoint_mpi.cpp)
add_library(gfmd::mpi ALIAS gfmd_mpi)
target_compile_definitions(gfmd_mpi PRIVATE GFMD_MPI)
set_target_properties(gfmd_mpi PROPERTIES
  EXPORT_NAME mpi
  VERSION ${PROJECT_VERSION}
  SOVERSION ${PROJECT_VERSION_MAJOR}
  CXX_VISIBILITY_PRESET hidden
  VISIBILITY_INLINES_HIDDEN ON
  INSTALL_RPATH "$ORIGIN")
if(NOT BUILD_SHARED_LIBS)
  target_compile_definitions(gfmd_mpi PUBLIC GFMD_STATIC_DEFINE)
endif()
target_include_directories(gfmd_mpi PUBLIC
  $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
  $<BUILD_INTERFACE:${GFMD_GENERATED_INCLUDE}>
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
target_include_directories(gfmd_mpi PRIVATE ${FFTW3_MPI_INCLUDE_DIR})
# gfmd_mpi.h includes mpi.h: consumers get MPI's include path and library through the target.
target_link_libraries(gfmd_mpi PUBLIC MPI::MPI_C)
target_link_libraries(gfmd_mpi PRIVATE ${FFTW3_MPI_LIBRARY} ${FFTW3_OMP_LIBRARY} PkgConfig::FFTW3 PkgConfig::LAPACKE
  OpenMP::OpenMP_CXX MPI::MPI_CXX m)
target_link_libraries(gfmd_mpi PRIVATE ${GFMD_X3P_LIBS})
target_compile_options(gfmd_mpi PRIVATE ${GFMD_CXX_WARNINGS})
if(BUILD_SHARED_LIBS)
  target_link_options(gfmd_mpi PRIVATE -Wl,--version-script=${CMAKE_CURRENT_SOURCE_DIR}/src/gfmd.map)
  set_property(TARGET gfmd_mpi APPEND PROPERTY LINK_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/gfmd.map)
  if(NOT GFMD_FUZZ)
    target_link_options(gfmd_mpi PRIVATE -Wl,--no-undefined)
  endif()
endif()

install(TARGETS gfmd_mpi EXPORT gfmdMPITargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES include/gfmd_mpi.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT gfmdMPITargets NAMESPACE gfmd:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/gfmd)
configure_file(cmake/gfmd-mpi.pc.in ${CMAKE_CURRENT_BINARY_DIR}/gfmd-mpi.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/gfmd-mpi.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# Fortran: libgfmd_mpi_f (gfmd::fortran_mpi) with the modules gfmd_c_api, gfmd (compiled again,
# against libgfmd_mpi: a program must not load libgfmd and libgfmd_mpi together) and gfmd_mpi.
if(GFMD_BUILD_FORTRAN)
  find_package(MPI REQUIRED COMPONENTS Fortran)
  if(NOT MPI_Fortran_HAVE_F08_MODULE)
    message(FATAL_ERROR "GFMD_BUILD_MPI with Fortran needs MPI's mpi_f08 module")
  endif()
  set(GFMD_FORTRAN_MPI_MODDIR
    ${CMAKE_INSTALL_INCLUDEDIR}/gfmd/fortran-mpi/${CMAKE_Fortran_COMPILER_ID}-${CMAKE_Fortran_COMPILER_VERSION})
  add_library(gfmd_mpi_f bindings/fortran/gfmd_c_api.f90 bindings/fortran/gfmd_report.f90 bindings/fortran/gfmd.f90
    bindings/fortran/gfmd_mpi.f90)
  add_library(gfmd::fortran_mpi ALIAS gfmd_mpi_f)
  set_target_properties(gfmd_mpi_f PROPERTIES
    VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR}
    EXPORT_NAME fortran_mpi
    INSTALL_RPATH "$ORIGIN"
    Fortran_MODULE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/mod-mpi)
  target_compile_options(gfmd_mpi_f PRIVATE $<$<Fortran_COMPILER_ID:GNU>:-Wall -Wextra -std=f2018 -fimplicit-none>)
  target_include_directories(gfmd_mpi_f
    PRIVATE ${PROJECT_BINARY_DIR}/fortran
    PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_BINARY_DIR}/mod-mpi> $<INSTALL_INTERFACE:${GFMD_FORTRAN_MPI_MODDIR}>)
  target_link_libraries(gfmd_mpi_f PUBLIC gfmd_mpi MPI::MPI_Fortran)
  install(TARGETS gfmd_mpi_f EXPORT gfmdFortranMPITargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/mod-mpi/ DESTINATION ${GFMD_FORTRAN_MPI_MODDIR})
  install(FILES bindings/fortran/gfmd_c_api.f90 bindings/fortran/gfmd_report.f90 bindings/fortran/gfmd.f90
    bindings/fortran/gfmd_mpi.f90
    ${PROJECT_BINARY_DIR}/fortran/gfmd_constants.inc DESTINATION ${GFMD_FORTRAN_MPI_MODDIR})
  install(EXPORT gfmdFortranMPITargets NAMESPACE gfmd:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/gfmd)
  configure_file(cmake/gfmd-fortran-mpi.pc.in ${CMAKE_CURRENT_BINARY_DIR}/gfmd-fortran-mpi.pc @ONLY)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/gfmd-fortran-mpi.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()

if(GFMD_BUILD_TESTS)
  # The environment of every test run through mpiexec (tests/mpi, the MPI example and benchmark):
  # Open MPI wants --oversubscribe for more ranks than cores and two variables to run as root (CI
  # containers).
  execute_process(COMMAND ${MPIEXEC_EXECUTABLE} --version OUTPUT_VARIABLE mpiexec_version ERROR_QUIET)
  set(GFMD_MPIEXEC_FLAGS "")
  if(mpiexec_version MATCHES "Open MPI|OpenRTE")
    set(GFMD_MPIEXEC_FLAGS --oversubscribe)
  endif()
  set(GFMD_MPI_TEST_ENV "OMP_NUM_THREADS=1;OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_mpi_yield_when_idle=1;OMPI_MCA_rmaps_base_oversubscribe=1")
  if(GFMD_SANITIZE)
    # AddressSanitizer, UBSan and LeakSanitizer check the MPI tests like the others.  Open MPI keeps
    # what MPI_Init and its threads allocate until exit and unloads its components in MPI_Finalize,
    # before LeakSanitizer's report: keep_components.c (preloaded) keeps them mapped so that their
    # frames have names, and lsan_openmpi.supp suppresses those allocations by the Open MPI
    # functions that make them, never by libmpi as a whole (test_mpi_leak_canary proves that a leak
    # made through MPI calls is still reported).  The full unwinder: Debian's Open MPI has no frame
    # pointers, the fast one stops at its first frame.
    add_library(keep_components SHARED tests/mpi/keep_components.c)
    target_compile_options(keep_components PRIVATE -fno-sanitize=all)
    target_link_options(keep_components PRIVATE -fno-sanitize=all)
    string(APPEND GFMD_MPI_TEST_ENV ";LD_PRELOAD=$<TARGET_FILE:keep_components>"
      ";ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:verify_asan_link_order=0"
      ";LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/mpi/lsan_openmpi.supp:fast_unwind_on_malloc=0")
  endif()
endif()

if(GFMD_BUILD_EXAMPLES)
  add_subdirectory(examples/mpi)
endif()

# gfmd_bench_mpi: the distributed handle against the threaded serial one (docs/mpi.md).
if(GFMD_BUILD_BENCHMARK)
  add_executable(gfmd_bench_mpi bench/gfmd_bench_mpi.c)
  target_include_directories(gfmd_bench_mpi PRIVATE ${FFTW3_MPI_INCLUDE_DIR})
  target_link_libraries(gfmd_bench_mpi PRIVATE gfmd::mpi ${FFTW3_MPI_LIBRARY} PkgConfig::FFTW3 m)
  if(GFMD_BUILD_TESTS)
    add_test(NAME benchmark_mpi_small
      COMMAND ${MPIEXEC_EXECUTABLE} ${GFMD_MPIEXEC_FLAGS} ${MPIEXEC_NUMPROC_FLAG} 2 $<TARGET_FILE:gfmd_bench_mpi> --sizes 64,96 --steps 3)
    set_tests_properties(benchmark_mpi_small PROPERTIES PROCESSORS 2 RUN_SERIAL TRUE LABELS "mpi"
      PASS_REGULAR_EXPRESSION "    96     2 \\| +[0-9.]+ +[0-9.]+"
      ENVIRONMENT "${GFMD_MPI_TEST_ENV}"
      FAIL_REGULAR_EXPRESSION "Sanitizer")  # beside a PASS expression the exit status does not count
  endif()
endif()
