# Runs test_mpi_leak_canary on 2 ranks under LeakSanitizer with lsan_openmpi.supp (the
# environment of the MPI tests) and passes only if every leak it made on purpose is reported,
# each from the canary's own lines, and the run failed for them (LeakSanitizer's exit status).
# Each rank writes its reports to a file of its own (log_path, suffixed with the pid): the two
# ranks' stderr interleave, and a line of one cut into the other's report broke it apart.
set(logs "${CMAKE_CURRENT_BINARY_DIR}/leak_canary_logs")
file(REMOVE_RECURSE "${logs}")
file(MAKE_DIRECTORY "${logs}")
set(ENV{ASAN_OPTIONS} "$ENV{ASAN_OPTIONS}:log_path=${logs}/rank")
execute_process(COMMAND ${MPIEXEC} ${FLAGS} -np 2 ${PROGRAM}
  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
file(GLOB reports_files "${logs}/rank.*")
list(LENGTH reports_files ranks)
if(NOT ranks EQUAL 2)
  message(FATAL_ERROR "expected a report file from each of 2 ranks, found ${ranks}:\n${all}")
endif()
set(reports "")
foreach(f IN LISTS reports_files)
  file(READ "${f}" text)
  string(APPEND all "\n${text}")
  # every report in this rank's file
  string(REGEX MATCHALL "(Direct|Indirect) leak of [^\n]*\n(    #[^\n]*\n)+" one "${text}")
  list(APPEND reports ${one})
endforeach()
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
