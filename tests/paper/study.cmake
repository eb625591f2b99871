# What the study's test scripts share.  They are run with -DSTUDY=gfmd_paper -DOUT=folder and set
# `args`, the options of every run.

# run_study(NAME OPTIONS...): the study with its args and these options into OUT/NAME; fails the
# test if it fails; its stdout in log_<NAME>, its stderr in err_<NAME>
function(run_study name)
  execute_process(COMMAND ${STUDY} ${args} ${ARGN} --out ${OUT}/${name}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "gfmd_paper ${ARGN} --out ${name} failed (${rc}):\n${out}${err}")
  endif()
  set(log_${name} "${out}" PARENT_SCOPE)
  set(err_${name} "${err}" PARENT_SCOPE)
endfunction()

# expect_same_tables(A B WHAT): the CSV tables of the study folders A and B are the same, bit for bit
# but fig3_area.csv's last column (each load's wall time); fails the test with WHAT otherwise.
function(expect_same_tables a b what)
  file(GLOB tables_a RELATIVE ${a} ${a}/*.csv)
  file(GLOB tables_b RELATIVE ${b} ${b}/*.csv)
  if(NOT tables_a OR NOT tables_a STREQUAL tables_b)
    message(FATAL_ERROR "${what} wrote the tables ${tables_b}, not ${tables_a}")
  endif()
  foreach(table IN LISTS tables_a)
    file(READ ${a}/${table} ta)
    file(READ ${b}/${table} tb)
    if(table STREQUAL "fig3_area.csv")
      string(REGEX REPLACE ",[^,\n]*\n" "\n" ta "${ta}")
      string(REGEX REPLACE ",[^,\n]*\n" "\n" tb "${tb}")
    endif()
    if(NOT ta STREQUAL tb)
      message(FATAL_ERROR "${what} wrote another ${table}:\n${tb}\nagainst:\n${ta}")
    endif()
  endforeach()
endfunction()

# expect_bodies_sum(LOG BODIES WHAT): the run printed BODIES "this body:" lines, and its total
# line's "bodies X s" is the sum of their seconds.  Both are printed to 0.01 s, each rounded by at
# most 0.005 s: with B bodies the printed sum and the sum of the printed figures differ by at most
# (B + 1) x 0.005 s; compared in hundredths (CMake's integer arithmetic), at most (B + 1) / 2 + 1
# of them apart.
function(expect_bodies_sum log bodies what)
  string(REGEX MATCHALL "this body: [0-9]+ steps, [0-9]+\\.[0-9][0-9] s" lines "${log}")
  list(LENGTH lines n)
  if(NOT n EQUAL bodies OR NOT "${log}" MATCHES "\ntotal [0-9.]+ s, [0-9]+ steps \\(bodies ([0-9]+)\\.([0-9][0-9]) s, first loads ")
    message(FATAL_ERROR "${what}: ${n} bodies' blocks, not ${bodies}, or no bodies' seconds in the total line:\n${log}")
  endif()
  math(EXPR printed "${CMAKE_MATCH_1} * 100 + 1${CMAKE_MATCH_2} - 100")
  set(sum 0)
  foreach(line IN LISTS lines)
    string(REGEX MATCH "([0-9]+)\\.([0-9][0-9]) s$" _ "${line}")
    math(EXPR sum "${sum} + ${CMAKE_MATCH_1} * 100 + 1${CMAKE_MATCH_2} - 100")
  endforeach()
  math(EXPR diff "${printed} - ${sum}")
  math(EXPR slack "(${n} + 1) / 2 + 1")
  if(diff GREATER slack OR diff LESS -${slack})
    message(FATAL_ERROR "${what}: the total line's bodies' seconds (${printed} hundredths) are not the sum of the ${n} 'this body:' lines (${sum})")
  endif()
endfunction()
