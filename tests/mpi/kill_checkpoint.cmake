# cmake -DMPIEXEC=... -DFLAGS=... -DPROGRAM=test_mpi_kill -DPATH=<file> -P kill_checkpoint.cmake
# The job whose last rank kills itself while the second checkpoint is written must fail; the
# checkpoint written before it must then be intact (test_mpi_kill check).
file(REMOVE ${PATH} ${PATH}.tmp ${PATH}.good)
separate_arguments(flags UNIX_COMMAND "${FLAGS}")
execute_process(COMMAND ${MPIEXEC} ${flags} -np 2 ${PROGRAM} write ${PATH}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
message("killed job: exit ${rc}")
if(rc EQUAL 0 OR rc EQUAL 3 OR rc EQUAL 4)
  message(FATAL_ERROR "the job was not killed in its second save (exit ${rc}):\n${out}\n${err}")
endif()
execute_process(COMMAND ${PROGRAM} check ${PATH} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the checkpoint before the kill did not survive")
endif()
file(REMOVE ${PATH} ${PATH}.tmp ${PATH}.good)
