# gfmd_paper --multilevel and --approach: the study at 64^2 (half-space and two sheets, no
# adhesion) with each body's first load relaxed from flat and from coarser grids, and with every
# relaxation started by 100 mass-weighted steps, reaches the same equilibria (check_paper
# --same-equilibrium); a bad level count or approach is refused with exit status 2.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(args --n 64 --bandwidth 8 --widths 0,0.25,0.0625 --no-adhesion --threads 1)
foreach(levels 1 3)
  execute_process(COMMAND ${STUDY} ${args} --multilevel ${levels} --out ${OUT}/levels${levels}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "gfmd_paper --multilevel ${levels} failed (${rc}):\n${out}${err}")
  endif()
endforeach()
execute_process(COMMAND ${CHECK} --same-equilibrium ${OUT}/levels1 ${OUT}/levels3 4096
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the multilevel start changed the study's equilibria")
endif()
execute_process(COMMAND ${STUDY} ${args} --approach 100 --out ${OUT}/approach
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gfmd_paper --approach 100 failed (${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${CHECK} --same-equilibrium ${OUT}/levels1 ${OUT}/approach 4096
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the mass-weighted approach changed the study's equilibria")
endif()
execute_process(COMMAND ${STUDY} ${args} --approach -1 --out ${OUT}/bad RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "gfmd_paper --approach -1 exited with ${rc}, not 2")
endif()
execute_process(COMMAND ${STUDY} ${args} --multilevel 0 --out ${OUT}/bad RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "gfmd_paper --multilevel 0 exited with ${rc}, not 2")
endif()
