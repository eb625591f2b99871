!> Without `stat`, an error stops the program with the library's message (checked by ctest's
!> PASS_REGULAR_EXPRESSION on the output).
program error_stop
  use gfmd
  implicit none
  type(gfmd_sim_t) :: sim
  call sim%create(16, 16, 16.0_dp, 16.0_dp)
  call sim%set_pressure(-1.0_dp)
  print '(a)', 'not reached'
end program error_stop
