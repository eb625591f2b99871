# cmake -DMPIEXEC=... -DFLAGS=... -DNP=2 -DC_PROGRAM=mpi_surface -DPYTHON=python3 -DSCRIPT=mpi_surface.py
#       -DOUT=<folder> -P python_mpi.cmake
# The same distributed run from C and from Python (mpi4py, gfmd.Simulation(comm=...)): the
# surface, the patch labels, A/A0 and the patch count must be the same bytes.
separate_arguments(flags UNIX_COMMAND "${FLAGS}")
execute_process(COMMAND ${PYTHON} -c "import mpi4py" RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "mpi4py is missing (Debian: python3-mpi4py; scripts/test.sh installs it): ${err}")
endif()
foreach(side c py)
  file(REMOVE ${OUT}/mpi_surface_${side}.bin)
endforeach()
execute_process(COMMAND ${MPIEXEC} ${flags} -np ${NP} ${C_PROGRAM} ${OUT}/mpi_surface_c.bin RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the C run failed (${rc})")
endif()
execute_process(COMMAND ${MPIEXEC} ${flags} -np ${NP} ${PYTHON} ${SCRIPT} ${OUT}/mpi_surface_py.bin RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the Python run failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/mpi_surface_c.bin ${OUT}/mpi_surface_py.bin
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the Python run on ${NP} ranks differs from the C run")
endif()
message("Python over MPI on ${NP} ranks: the same bytes as C (surface, labels, A/A0, patch count)")
