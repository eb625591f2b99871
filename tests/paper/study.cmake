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
