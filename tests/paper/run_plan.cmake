# gfmd_paper --plan: what the options resolve to, without relaxing anything.  A 2048^2 study costs
# hours, so --full's defaults (docs/paper/full.md) are checked here through the plan: the paper's
# grid and spectrum, every body, the multilevel first loads from N = 2048 on (4 levels) and flat
# starts below, what --jobs/--threads resolve to; nothing is written.  That the plan is what a run
# does: a small run prints the plan's own first lines before its sweeps.  Bad options are still
# refused (exit status 2) with --plan.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

# the plan of these options into variable `plan`; fails the test unless it exits 0 and writes nothing
function(plan)
  execute_process(COMMAND ${STUDY} ${ARGN} --plan --out ${OUT}/never
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "gfmd_paper ${ARGN} --plan failed (${rc}):\n${out}${err}")
  endif()
  if(EXISTS ${OUT}/never)
    message(FATAL_ERROR "gfmd_paper ${ARGN} --plan created its output folder")
  endif()
  set(plan "${out}" PARENT_SCOPE)
endfunction()

# the plan holds each of the given lines (as printed, whole lines)
function(expect_lines what)
  foreach(line IN LISTS ARGN)
    string(FIND "\n${plan}" "\n${line}\n" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "${what}: no line '${line}' in the plan:\n${plan}")
    endif()
  endforeach()
endfunction()

# --full: the paper's setting, 13 bodies without adhesion and 9 adhesive sheets, 3 coarser grids
plan(--full)
expect_lines("--full"
  "grid 2048x2048, L = 2048 a, lambda_s = 4 a, lambda_r = 256 a (= 64 lambda_s, L = 8 lambda_r), H = 0.8, g = 1, E* = 1, seed 2016"
  "each body's first load from 3 coarser grids (--multilevel 4)"
  "bodies without adhesion, W (0 = half-space): 0 100 10 4 2 1 0.5 0.25 0.177 0.125 0.088 0.0625 0.044"
  "adhesive bodies, W: 0 4 1 0.5 0.25 0.177 0.125 0.088 0.0625"
  "every other load: no approach steps (--approach 0)"
  "solver: auto")
# the rule is on the grid, not on --full: 4096^2 multilevel, 1024^2 flat; an explicit level wins
plan(--n 4096 --bandwidth 64)
expect_lines("--n 4096" "each body's first load from 3 coarser grids (--multilevel 4)")
plan(--n 1024 --bandwidth 64)
expect_lines("--n 1024" "each body's first load from a flat surface (--multilevel 1)")
plan(--full --multilevel 1)
expect_lines("--full --multilevel 1" "each body's first load from a flat surface (--multilevel 1)")
plan(--n 1024 --bandwidth 64 --multilevel 3)
expect_lines("--n 1024 --multilevel 3" "each body's first load from 2 coarser grids (--multilevel 3)")
# --threads T alone: one body at a time on T threads; --jobs J: one thread each unless --threads
plan(--full --threads 2)
expect_lines("--full --threads 2" "bodies swept 1 at a time, 2 thread(s) each")
plan(--full --jobs 2)
expect_lines("--full --jobs 2" "bodies swept 2 at a time, 1 thread(s) each")
plan(--full --jobs 3 --threads 2 --approach 100 --no-adhesion)
expect_lines("--full --jobs 3 --threads 2 --approach 100 --no-adhesion"
  "bodies swept 3 at a time, 2 thread(s) each"
  "every other load: up to 100 mass-weighted steps first (--approach 100)"
  "adhesive bodies, W: none")

# --resume: said in the plan (tests/paper/run_resume.cmake runs it)
plan(--full --resume)
expect_lines("--full --resume" "bodies saved in ${OUT}/never by an earlier run of this study are read, not relaxed (--resume)")

# the plan is what a run does: a small run's first lines are its plan's
set(small --n 64 --bandwidth 8 --widths 0,0.25 --no-adhesion --jobs 2 --threads 1 --multilevel 2)
plan(${small})
execute_process(COMMAND ${STUDY} ${small} --out ${OUT}/small RESULT_VARIABLE rc OUTPUT_VARIABLE run ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gfmd_paper ${small} failed (${rc}):\n${run}${err}")
endif()
string(REGEX MATCH "^[^\n]*\n[^\n]*\n[^\n]*\n[^\n]*\n" head "${plan}")
string(FIND "${run}" "${head}" at)
if(NOT at EQUAL 0)
  message(FATAL_ERROR "the run does not begin with its plan's lines:\n${head}\nthe run:\n${run}")
endif()

# refused with --plan as without it
foreach(bad "--multilevel;0" "--multilevel;9" "--jobs;0" "--approach;-1" "--n;16")
  execute_process(COMMAND ${STUDY} --full ${bad} --plan --out ${OUT}/never RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "gfmd_paper --full ${bad} --plan exited with ${rc}, not 2")
  endif()
endforeach()
message("--plan: --full's grid, bodies and multilevel first loads; the size rule; jobs and threads; a run begins with its plan; bad options refused")
