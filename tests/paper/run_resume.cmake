# gfmd_paper --resume: every body's sweep is saved as soon as it is done, and a later run of the same
# study reads the saved bodies instead of relaxing them.  What an interrupted run leaves is some
# bodies' checkpoints: here a whole run's folder with two of its five checkpoints removed.  The
# resumed run (one and two bodies at a time) must relax exactly the two missing bodies, print the
# read bodies' blocks as the whole run printed them (their own seconds too: read, not re-run), and
# write the whole run's tables bit for bit but the wall-time column (same FFT plans: --planner
# estimate).  Refused with exit status 2 and nothing written: a checkpoint of another study
# (another seed, another first-load start), a damaged one.  Without --resume the checkpoints are
# ignored and every body relaxed.
include(${CMAKE_CURRENT_LIST_DIR}/study.cmake)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(args --n 64 --bandwidth 8 --widths 0,1,0.25 --adh-widths 1,0.25 --planner estimate --threads 1)
set(bodies body_W0 body_W1 body_W0.25 body_W1_adhesive body_W0.25_adhesive)

# a body's printed block (from its title line to its "this body:" line) in a run's stdout
function(body_block log title var)
  string(FIND "${log}" "${title}\n" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "no block '${title}' in:\n${log}")
  endif()
  string(SUBSTRING "${log}" ${at} -1 rest)
  string(FIND "${rest}" "this body:" end)
  string(SUBSTRING "${rest}" ${end} -1 tail)
  string(FIND "${tail}" "\n" eol)
  math(EXPR len "${end} + ${eol}")
  string(SUBSTRING "${rest}" 0 ${len} b)
  set(${var} "${b}" PARENT_SCOPE)
endfunction()

run_study(whole --jobs 2)
list(LENGTH bodies n_bodies)
expect_bodies_sum("${log_whole}" ${n_bodies} "--jobs 2")
foreach(b IN LISTS bodies)
  if(NOT EXISTS ${OUT}/whole/${b}.sweep)
    message(FATAL_ERROR "the whole run saved no ${b}.sweep")
  endif()
endforeach()
file(GLOB parts ${OUT}/whole/*.part)
if(parts)
  message(FATAL_ERROR "half-written checkpoints left: ${parts}")
endif()

foreach(jobs 1 2)
  set(name part${jobs})
  file(MAKE_DIRECTORY ${OUT}/${name})
  foreach(b body_W0 body_W0.25 body_W1_adhesive) # the run "stopped" before W = 1 and the adhesive W = 0.25
    file(COPY ${OUT}/whole/${b}.sweep DESTINATION ${OUT}/${name})
  endforeach()
  run_study(${name} --jobs ${jobs} --resume)
  string(REGEX MATCHALL "read from [^\n]*" read "${err_${name}}")
  string(REGEX MATCHALL "bodies done [^\n]*" relaxed "${err_${name}}")
  list(LENGTH read n_read)
  if(NOT n_read EQUAL 3 OR NOT "${log_${name}}" MATCHES "\nresumed: 3 of 5 bodies read from ")
    message(FATAL_ERROR "--resume --jobs ${jobs} read ${n_read} bodies, not 3:\n${log_${name}}${err_${name}}")
  endif()
  if(jobs GREATER 1)
    list(LENGTH relaxed n_relaxed)
    if(NOT n_relaxed EQUAL 2 OR NOT "${relaxed}" MATCHES "W = 1," OR NOT "${relaxed}" MATCHES "W = 0.25, adhesive")
      message(FATAL_ERROR "--resume --jobs 2 relaxed ${relaxed}, not W = 1 and the adhesive W = 0.25")
    endif()
  endif()
  foreach(title "half-space, W = w/lambda_s = 0" "layer on a fluid foundation, W = w/lambda_s = 0.25"
                "layer on a fluid foundation with adhesion, W = w/lambda_s = 1")
    body_block("${log_whole}" "${title}" a)
    body_block("${log_${name}}" "${title}" b)
    if(NOT a STREQUAL b)
      message(FATAL_ERROR "--resume --jobs ${jobs} printed the read body '${title}' as\n${b}\nthe whole run:\n${a}")
    endif()
  endforeach()
  expect_same_tables(${OUT}/whole ${OUT}/${name} "--resume --jobs ${jobs}")
  expect_bodies_sum("${log_${name}}" ${n_bodies} "--resume --jobs ${jobs}") # the read bodies' seconds counted too
  message("--resume --jobs ${jobs}: 3 bodies read, 2 relaxed, the whole run's blocks and tables")
endforeach()

# every body read back, two at a time: no worker starts, and Persson's curves (written by the first
# worker without a body, bodies.c) must still be written, as the whole run wrote them
file(MAKE_DIRECTORY ${OUT}/all)
foreach(b IN LISTS bodies)
  file(COPY ${OUT}/whole/${b}.sweep DESTINATION ${OUT}/all)
endforeach()
run_study(all --jobs 2 --resume)
if(NOT "${log_all}" MATCHES "\nresumed: 5 of 5 bodies read from ")
  message(FATAL_ERROR "--resume with every checkpoint did not read all five:\n${log_all}${err_all}")
endif()
expect_same_tables(${OUT}/whole ${OUT}/all "--resume --jobs 2, every body read")
message("--resume --jobs 2, every body read: the whole run's tables, Persson's curves among them")

# refused, nothing written: another study's checkpoints, a damaged checkpoint
function(expect_refused what dir pattern)
  file(GLOB before ${OUT}/${dir}/*)
  file(GLOB_RECURSE stamps ${OUT}/${dir}/*.sweep)
  execute_process(COMMAND ${STUDY} ${args} ${ARGN} --resume --out ${OUT}/${dir}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(GLOB after ${OUT}/${dir}/*)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "${pattern}" OR NOT before STREQUAL after)
    message(FATAL_ERROR "${what}: exit ${rc} (not 2), files ${after} (were ${before}):\n${err}")
  endif()
  message("${what}: refused (${err})")
endfunction()
file(MAKE_DIRECTORY ${OUT}/other)
file(COPY ${OUT}/whole/body_W0.sweep DESTINATION ${OUT}/other)
file(READ ${OUT}/whole/body_W0.sweep saved)
expect_refused("a checkpoint of another seed" other "body_W0.sweep belongs to another study" --seed 7)
expect_refused("a checkpoint of another first-load start" other "belongs to another study" --multilevel 2)
file(READ ${OUT}/other/body_W0.sweep still)
if(NOT still STREQUAL saved)
  message(FATAL_ERROR "a refused --resume changed the checkpoint")
endif()
file(MAKE_DIRECTORY ${OUT}/damaged)
string(REGEX REPLACE "\nend\n$" "\n" cut "${saved}")
string(REGEX REPLACE "\n[^\n]*\n$" "\n" cut "${cut}") # its last load's line gone
file(WRITE ${OUT}/damaged/body_W0.sweep "${cut}")
expect_refused("a damaged checkpoint" damaged "body_W0.sweep is damaged")
file(WRITE ${OUT}/damaged/body_W0.sweep "W = 0\n")
expect_refused("not a checkpoint" damaged "is not a checkpoint of gfmd_paper")

# without --resume: every body relaxed, the checkpoints of the earlier run replaced
run_study(part2 --jobs 2)
if(err_part2 MATCHES "read from" OR NOT err_part2 MATCHES "5 of 5 bodies done")
  message(FATAL_ERROR "a run without --resume read checkpoints:\n${err_part2}")
endif()
message("--resume: reads only its own study's checkpoints, refuses others and damaged ones, and runs without it relax every body")
