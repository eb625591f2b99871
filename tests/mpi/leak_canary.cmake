# Runs test_mpi_leak_canary on 2 ranks under LeakSanitizer with lsan_openmpi.supp (the
# environment of the MPI tests) and passes only if every leak it made on purpose is reported,
# each from the canary's own lines, and the run failed for them (LeakSanitizer's exit status).
execute_process(COMMAND ${MPIEXEC} ${FLAGS} -np 2 ${PROGRAM}
  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
if(status EQUAL 0)
  message(FATAL_ERROR "the canary's leaks went unreported (exit status 0):\n${all}")
endif()
foreach(expected "in MPI_Comm_dup" "in MPI_Type_contiguous" "test_mpi_leak_canary.c:22")
  if(NOT all MATCHES "${expected}")
    message(FATAL_ERROR "LeakSanitizer did not report the leak through '${expected}':\n${all}")
  endif()
endforeach()
# every leak reported is the canary's: a report without its file would be Open MPI's own,
# which the suppressions missed
string(REGEX MATCHALL "(Direct|Indirect) leak of [^\n]*\n(    #[^\n]*\n)+" reports "${all}")
list(LENGTH reports count)
if(count EQUAL 0)
  message(FATAL_ERROR "no leak report found:\n${all}")
endif()
foreach(report IN LISTS reports)
  if(NOT report MATCHES "test_mpi_leak_canary.c")
    message(FATAL_ERROR "a leak not made by the canary (a suppression missing):\n${report}")
  endif()
endforeach()
message(STATUS "${count} leaks made through MPI calls and malloc reported, none of Open MPI's own")
