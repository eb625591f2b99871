! A user's program against the installed library: one real relaxation through the module gfmd.
program consumer
  use gfmd
  implicit none
  type(gfmd_sim_t) :: sim
  real(dp) :: area
  call sim%create(64, 64, 64.0_dp, 64.0_dp)
  call sim%generate_selfaffine(0.8_dp, 16.0_dp, 4.0_dp, 1.0_dp, seed=1)
  call sim%set_green(GFMD_GREEN_LAYER_FLUID, 4.0_dp)
  call sim%set_pressure(0.05_dp)
  call sim%relax()
  call sim%get_contact_area(area)
  call sim%destroy()
  print '(a, a, a, f6.4)', 'fortran consumer: gfmd ', gfmd_version(), ', A/A0 = ', area
  if (area <= 0.0_dp .or. area >= 1.0_dp) error stop 1
end program consumer
