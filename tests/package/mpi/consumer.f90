! A user's Fortran MPI program: the same thin layer through the modules gfmd and gfmd_mpi.
program consumer
  use mpi_f08
  use gfmd
  use gfmd_mpi
  implicit none
  type(gfmd_sim_t) :: sim
  integer :: rank, st
  real(dp) :: area
  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  call gfmd_sim_create_mpi(sim, 64, 64, 64.0_dp, 64.0_dp, MPI_COMM_WORLD, planner=GFMD_PLANNER_ESTIMATE)
  call sim%set_green(GFMD_GREEN_LAYER_FLUID, 4.0_dp)
  call sim%generate_selfaffine(0.8_dp, 32.0_dp, 4.0_dp, 0.1_dp, 1)
  call sim%set_pressure(0.02_dp)
  call sim%relax(stat=st)
  call sim%get_contact_area(area)
  if (rank == 0) print '(a, f7.4)', 'Fortran consumer: A/A0 = ', area
  call sim%destroy()
  call MPI_Finalize()
  if (st /= GFMD_OK .or. area <= 0 .or. area >= 1) error stop 1
end program consumer
