!> The seed paper's thin-layer load sweep on several MPI ranks (module gfmd_mpi over libgfmd_mpi):
!>   mpirun -np 2 ./thin_layer_sweep_mpi_f [n]      (grid n x n, default 256)
!> The program of examples/fortran/thin_layer_sweep.f90 with a distributed simulation: every call
!> is made by all ranks with the same arguments; rank 0 prints.
program thin_layer_sweep_mpi
  use mpi_f08
  use gfmd
  use gfmd_mpi
  implicit none
  real(dp), parameter :: widths(3) = [4.0_dp, 1.0_dp, 0.5_dp]   ! W = w / lambda_s
  integer, parameter :: nloads = 8
  character(len=32) :: arg
  type(gfmd_sim_t) :: sim
  real(dp) :: l, lambda_s, sigma0, area, gap, u_el, u_ad
  integer :: n, iw, k, steps, rank, ranks, local_ny, y0

  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  call MPI_Comm_size(MPI_COMM_WORLD, ranks)
  n = 256
  if (command_argument_count() >= 1) then
    call get_command_argument(1, arg)
    read (arg, *) n
  end if
  l = real(n, dp)
  lambda_s = 4.0_dp
  ! ESTIMATE: the same bits on any number of ranks
  call gfmd_sim_create_mpi(sim, n, n, l, l, MPI_COMM_WORLD, planner=GFMD_PLANNER_ESTIMATE)
  call gfmd_mpi_get_local_grid(sim, local_ny, y0)   ! this rank's rows y0 .. y0 + local_ny - 1
  if (rank == 0) print '(a, a, a, i0, a, i0, a, i0, a)', 'gfmd ', gfmd_version(), ' thin-layer sweep on ', n, &
                       ' x ', n, ', ', ranks, ' ranks'
  do iw = 1, size(widths)
    call sim%generate_selfaffine(0.8_dp, l / 8.0_dp, lambda_s, 1.0_dp, seed=2016)   ! resets the body
    call sim%set_green(GFMD_GREEN_LAYER_FLUID, widths(iw) * lambda_s)
    if (rank == 0) then
      print '(/, a, f0.2)', 'layer on a fluid foundation, W = ', widths(iw)
      print '(a4, a12, a10, a10, a14, a7)', 'W', 'sigma0/E*g', 'A/A0', 'mean gap', 'U_el', 'steps'
    end if
    do k = 0, nloads - 1
      sigma0 = 1e-3_dp * 100.0_dp**(real(k, dp) / (nloads - 1))
      call sim%set_pressure(sigma0)
      call sim%relax(steps=steps)
      call sim%get_contact_area(area)
      call sim%get_mean_gap(gap)
      call sim%get_energies(u_el, u_ad)
      if (rank == 0) print '(f4.2, es12.4, f10.5, f10.5, es14.5, i7)', widths(iw), sigma0, area, gap, u_el, steps
    end do
  end do
  call sim%destroy()   ! collective: on every rank, before MPI_Finalize
  call MPI_Finalize()
end program thin_layer_sweep_mpi
