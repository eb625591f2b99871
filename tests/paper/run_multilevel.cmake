# gfmd_paper --multilevel and --approach: the study at 64^2 (half-space and two sheets, no
# adhesion) with each body's first load relaxed from flat and from coarser grids, and with every
# relaxation started by 100 mass-weighted steps, reaches the same equilibria (check_paper
# --same-equilibrium); a bad level count or approach is refused with exit status 2.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(args --n 64 --bandwidth 8 --widths 0,0.25,0.0625 --no-adhesion --threads 1)

# the study with extra options into OUT/name; fails the test if it fails
function(run_study name)
  execute_process(COMMAND ${STUDY} ${args} ${ARGN} --out ${OUT}/${name}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "gfmd_paper ${ARGN} failed (${rc}):\n${out}${err}")
  endif()
endfunction()

# OUT/a and OUT/b hold the same equilibria (and another start did run)
function(expect_same a b what)
  execute_process(COMMAND ${CHECK} --same-equilibrium ${OUT}/${a} ${OUT}/${b} 4096
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} changed the study's equilibria")
  endif()
endfunction()

# a bad option: refused with exit status 2
function(expect_refused)
  execute_process(COMMAND ${STUDY} ${args} ${ARGN} --out ${OUT}/bad RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "gfmd_paper ${ARGN} exited with ${rc}, not 2")
  endif()
endfunction()

run_study(levels1 --multilevel 1)
run_study(levels3 --multilevel 3)
expect_same(levels1 levels3 "the multilevel start")
run_study(approach --approach 100)
expect_same(levels1 approach "the mass-weighted approach")
expect_refused(--multilevel 0)
expect_refused(--approach -1)
