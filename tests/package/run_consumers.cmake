# cmake -DBUILD_DIR=<gfmd build> -DSOURCE_DIR=<gfmd source> -DWORK=<scratch> -P run_consumers.cmake
# Installs the built library into a scratch prefix, then builds and runs the consumer projects the
# way a user would: CMake find_package, and the documented one-line pkg-config command, for C and
# Fortran (and libgfmd_mpi's, with mpicc and mpifort, when built); and gfmd as a static subproject.  Every program runs without LD_LIBRARY_PATH: the
# installed libraries must find each other by themselves.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${err}")
  endif()
endfunction()

set(prefix ${WORK}/prefix)
file(REMOVE_RECURSE ${WORK})
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# CMake: find_package(gfmd)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/c -B ${WORK}/c-cmake -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK}/c-cmake)
unset(ENV{LD_LIBRARY_PATH})
run(${WORK}/c-cmake/consumer)

# pkg-config: cc consumer.c $(pkg-config --cflags --libs gfmd)
set(ENV{PKG_CONFIG_PATH} "${prefix}/lib/pkgconfig")
execute_process(COMMAND pkg-config --cflags --libs gfmd OUTPUT_VARIABLE flags OUTPUT_STRIP_TRAILING_WHITESPACE
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config does not know gfmd")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
run(cc ${SOURCE_DIR}/tests/package/c/consumer.c ${flags} -o ${WORK}/consumer-pc)
run(${WORK}/consumer-pc)

if(FORTRAN)
  # CMake: find_package(gfmd COMPONENTS Fortran)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/fortran -B ${WORK}/f-cmake -DCMAKE_PREFIX_PATH=${prefix})
  run(${CMAKE_COMMAND} --build ${WORK}/f-cmake)
  run(${WORK}/f-cmake/consumer)
  # the documented one-liner: gfortran consumer.f90 $(pkg-config --cflags --libs gfmd-fortran)
  execute_process(COMMAND pkg-config --cflags --libs gfmd-fortran OUTPUT_VARIABLE fflags
                  OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pkg-config does not know gfmd-fortran")
  endif()
  separate_arguments(fflags UNIX_COMMAND "${fflags}")
  run(gfortran ${SOURCE_DIR}/tests/package/fortran/consumer.f90 ${fflags} -o ${WORK}/consumer-f-pc)
  run(${WORK}/consumer-f-pc)
endif()

if(MPI)
  # libgfmd_mpi: find_package(gfmd COMPONENTS MPI [Fortran]), and the pkg-config one-liners with
  # mpicc and mpifort; each consumer runs on 2 ranks.
  set(mpirun ${MPIEXEC} --oversubscribe -np 2)
  set(ENV{OMPI_ALLOW_RUN_AS_ROOT} 1)
  set(ENV{OMPI_ALLOW_RUN_AS_ROOT_CONFIRM} 1)
  set(ENV{OMP_NUM_THREADS} 1)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/mpi -B ${WORK}/mpi-cmake -DCMAKE_PREFIX_PATH=${prefix}
      -DWITH_FORTRAN=${FORTRAN})
  run(${CMAKE_COMMAND} --build ${WORK}/mpi-cmake)
  run(${mpirun} ${WORK}/mpi-cmake/consumer)
  execute_process(COMMAND pkg-config --cflags --libs gfmd-mpi OUTPUT_VARIABLE mflags OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pkg-config does not know gfmd-mpi")
  endif()
  separate_arguments(mflags UNIX_COMMAND "${mflags}")
  run(mpicc ${SOURCE_DIR}/tests/package/mpi/consumer.c ${mflags} -o ${WORK}/consumer-mpi-pc)
  run(${mpirun} ${WORK}/consumer-mpi-pc)
  if(FORTRAN)
    run(${mpirun} ${WORK}/mpi-cmake/consumer_f)
    execute_process(COMMAND pkg-config --cflags --libs gfmd-fortran-mpi OUTPUT_VARIABLE mfflags
                    OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "pkg-config does not know gfmd-fortran-mpi")
    endif()
    separate_arguments(mfflags UNIX_COMMAND "${mfflags}")
    run(mpifort ${SOURCE_DIR}/tests/package/mpi/consumer.f90 ${mfflags} -o ${WORK}/consumer-mpi-f-pc)
    run(${mpirun} ${WORK}/consumer-mpi-f-pc)
  endif()
endif()

# Python: the installed package (<prefix>/share/gfmd/python) finds the installed library by itself
if(PYTHON)
  set(ENV{PYTHONPATH} "${prefix}/share/gfmd/python")
  unset(ENV{GFMD_LIBRARY})
  set(ENV{PYTHONDONTWRITEBYTECODE} 1)
  run(${PYTHON} ${SOURCE_DIR}/tests/package/python/consumer.py)
endif()

# add_subdirectory: a static gfmd inside the consumer's own build
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/subproject -B ${WORK}/subproject -DGFMD_SOURCE=${SOURCE_DIR}
    -DCMAKE_BUILD_TYPE=Debug)
run(${CMAKE_COMMAND} --build ${WORK}/subproject -j 2)
run(${WORK}/subproject/consumer)
