# Runs the study's pull-off stage (apps/paper/pulloff.c) small (64^2, two sheets) and checks its
# table against force balance: under displacement control the mean pressure is carried by the
# wall (compressive) and the adhesion (tensile, at most gamma0/rho per area: the elastic stress has
# no mean), so a tensile pull-off stress lies in (0, gamma0/rho]; and every sheet must come off.
# The same run is --adhesion-only (checked below): the adhesive sweeps and the pull-offs alone.
# The sheets W = 1 and 0.25, under displacement control the default's mass-weighted FIRE (the
# W = 0.25 sheet's pull-off took 124 585 FIRE steps, 21 s, when the default was FIRE there).
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${STUDY} --n 64 --bandwidth 8 --threads 1 --adhesion-only --adh-widths 1,0.25 --pulloff
                        --out ${OUT}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "gfmd_paper --adhesion-only --pulloff failed (${rc})")
endif()
file(STRINGS ${OUT}/fig8_pulloff.csv lines)
list(GET lines 0 header)
if(NOT header STREQUAL "W,pull_off_over_Estar,pull_off_over_gamma0_rho,max_area,detached,lift,steps,seconds")
  message(FATAL_ERROR "fig8_pulloff.csv: header '${header}'")
endif()
list(LENGTH lines n)
if(NOT n EQUAL 3)
  message(FATAL_ERROR "fig8_pulloff.csv: ${n} lines, expected a header and 2 rows")
endif()
foreach(i 1 2)
  list(GET lines ${i} row)
  string(REPLACE "," ";" f "${row}")
  list(GET f 2 ratio)
  list(GET f 4 detached)
  if(NOT detached EQUAL 1)
    message(FATAL_ERROR "row ${i}: the sheet did not come off: ${row}")
  endif()
  # -1 <= ratio < 0 (CMake compares numbers as floating point with LESS/GREATER)
  if(NOT ratio LESS 0 OR ratio LESS -1)
    message(FATAL_ERROR "row ${i}: pull-off ${ratio} gamma0/rho outside [-1, 0): ${row}")
  endif()
endforeach()
message("pull-off table: 2 sheets came off, tensile stresses within the adhesive bound")

# --adhesion-only ran the adhesive sweeps (Fig. 7, and Fig. 8's pull-offs) without the sweeps of
# Figs. 3-6 (the paper's size in two runs); with --no-adhesion it has nothing to run and is refused
# with exit status 2.
if(EXISTS ${OUT}/fig3_area.csv OR NOT EXISTS ${OUT}/fig7_theta.csv)
  message(FATAL_ERROR "--adhesion-only: expected fig7 tables and no fig3 table")
endif()
# fits.csv and the report hold the theta fits and nothing of the sweeps that did not run (kappa,
# c(W)); with one sheet of W <= 0.25 theta is not fitted (nan), as the program says
file(READ ${OUT}/fits.csv fits)
if(NOT fits MATCHES "theta_exponent," OR fits MATCHES "kappa_halfspace|c_exponent")
  message(FATAL_ERROR "--adhesion-only: fits.csv should hold the theta fits only:\n${fits}")
endif()
if(out MATCHES "kappa|alpha")
  message(FATAL_ERROR "--adhesion-only: the report prints a fit that did not run:\n${out}")
endif()
file(STRINGS ${OUT}/fig7_adhesion_sweep.csv lines)
list(LENGTH lines n)
if(NOT n EQUAL 21)
  message(FATAL_ERROR "--adhesion-only: fig7_adhesion_sweep.csv has ${n} lines, expected a header and 2 x 10 loads")
endif()
execute_process(COMMAND ${STUDY} --adhesion-only --no-adhesion RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "gfmd_paper --adhesion-only --no-adhesion exited with ${rc}, not 2")
endif()
message("--adhesion-only: the adhesive sweeps alone; refused with --no-adhesion")
