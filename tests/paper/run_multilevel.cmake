# gfmd_paper --multilevel and --approach: the study at 64^2 (half-space and two sheets, no
# adhesion) with each body's first load relaxed from flat and from coarser grids, and with every
# relaxation started by 100 mass-weighted steps, reaches the same equilibria (check_paper
# --same-equilibrium); a bad level count or approach is refused with exit status 2.
# gfmd_paper --jobs: the bodies swept two and three at a time (with and without adhesion) write the
# same tables, bit for bit but the seconds, as one at a time (same FFT plans: --planner estimate),
# and print the bodies' blocks in the same order; --jobs 0 and --jobs 33 are refused.
include(${CMAKE_CURRENT_LIST_DIR}/study.cmake)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(args --n 64 --bandwidth 8 --widths 0,0.25,0.0625 --no-adhesion --threads 1)

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

# --jobs: tables and the order of the printed blocks against one body at a time
set(args --n 64 --bandwidth 8 --widths 0,0.25,0.0625 --adh-widths 0.25,0.0625 --threads 1 --planner estimate)
foreach(jobs 1 2 3)
  execute_process(COMMAND ${STUDY} ${args} --jobs ${jobs} --out ${OUT}/jobs${jobs}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE log${jobs} ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "gfmd_paper --jobs ${jobs} failed (${rc}):\n${log${jobs}}${err}")
  endif()
  string(REGEX MATCHALL "\n[^\n]*W = w/lambda_s = [^\n]*" order${jobs} "${log${jobs}}")
endforeach()
list(LENGTH order1 bodies)
if(NOT bodies EQUAL 5)
  message(FATAL_ERROR "--jobs 1 printed ${bodies} bodies, not 5:\n${log1}")
endif()
foreach(jobs 2 3)
  if(NOT order${jobs} STREQUAL order1)
    message(FATAL_ERROR "--jobs ${jobs}: bodies ${order${jobs}}, one at a time ${order1}")
  endif()
  expect_same_tables(${OUT}/jobs1 ${OUT}/jobs${jobs} "--jobs ${jobs}")
  message("--jobs ${jobs}: the same ${bodies} bodies in the same order, the same tables")
endforeach()
expect_refused(--jobs 0)
expect_refused(--jobs 33)
