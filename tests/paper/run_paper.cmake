# Runs the paper study in its small mode and checks the tables' physics (check_paper.c).
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${STUDY} --quick --threads 1 --out ${OUT} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gfmd_paper --quick failed (${rc})")
endif()
execute_process(COMMAND ${CHECK} ${OUT} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the study's tables fail the physics checks")
endif()
