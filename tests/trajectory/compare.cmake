# cmake -DPROGRAM=<record_trajectories> -DOUT=<file> -DREFERENCE=<reference.txt> -P compare.cmake
# Runs the recorder and fails, showing both tables, unless its output equals the reference.
execute_process(COMMAND ${PROGRAM} ${OUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "record_trajectories failed (${rc})")
endif()
file(READ ${OUT} actual)
file(READ ${REFERENCE} expected)
if(NOT actual STREQUAL expected)
  message(FATAL_ERROR "trajectories differ from ${REFERENCE}\nactual:\n${actual}\nexpected:\n${expected}")
endif()
