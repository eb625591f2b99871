! The Fortran module gfmd_mpi under mpiexec: a simulation created from a type(MPI_Comm) and one
! from the integer handle of the same communicator run the same steps to the same bits; local
! slabs h(nx, local_ny) go in and come out unchanged, rows y0 .. y0 + local_ny - 1 of the grid a
! serial simulation of the same seed holds (within a few ulps of the height range: another FFT);
! whole-grid getters are refused with a status on more than one rank; a checkpoint written by
! the distributed simulation loads through the integer-communicator variant.
program test_mpi_fortran
  use mpi_f08
  use gfmd
  use gfmd_mpi
  implicit none
  integer, parameter :: nx = 40, ny = 30
  type(gfmd_sim_t) :: a, b, serial, c
  integer :: rank, size, local_ny, y0, st, failures, total, i, j
  real(dp), allocatable :: h(:, :), back(:, :), whole(:, :), za(:, :), zb(:, :)
  real(dp) :: area_a, area_b, ea, eb, ad, hmin, worst
  character(len=256) :: msg

  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  call MPI_Comm_size(MPI_COMM_WORLD, size)
  failures = 0

  call gfmd_sim_create_mpi(a, nx, ny, real(nx, dp), real(ny, dp), MPI_COMM_WORLD, planner=GFMD_PLANNER_ESTIMATE)
  call gfmd_sim_create_mpi(b, nx, ny, real(nx, dp), real(ny, dp), MPI_COMM_WORLD%MPI_VAL, planner=GFMD_PLANNER_ESTIMATE)
  call gfmd_mpi_get_local_grid(a, local_ny, y0)
  call gfmd_mpi_get_ranks(a, i)
  call expect(i == size, 'get_ranks')

  ! The substrate of a seed, generated on the ranks, against a serial simulation's.
  call a%generate_selfaffine(0.8_dp, 20.0_dp, 4.0_dp, 0.1_dp, 5)
  allocate (h(nx, local_ny), back(nx + 3, local_ny), whole(nx, ny), za(nx, local_ny), zb(nx, local_ny))
  call gfmd_mpi_get_local_heights(a, h)
  call serial%create(nx, ny, real(nx, dp), real(ny, dp), threads=1, planner=GFMD_PLANNER_ESTIMATE)
  call serial%generate_selfaffine(0.8_dp, 20.0_dp, 4.0_dp, 0.1_dp, 5)
  call serial%get_heights(whole)
  hmin = minval(whole)
  worst = 0
  do j = 1, local_ny
    do i = 1, nx
      worst = max(worst, abs(h(i, j) - whole(i, y0 + j)))
    end do
  end do
  call expect(worst <= 1e-14_dp * abs(hmin), 'local heights are the serial surface''s rows')
  call serial%destroy()

  ! b gets a's substrate through its local slab with a leading dimension > nx.
  back = -1
  back(1:nx, :) = h
  call gfmd_mpi_set_local_heights(b, back)
  back = 0
  call gfmd_mpi_get_local_heights(b, back)
  call expect(all(back(1:nx, :) == h), 'local heights round trip (ld = nx + 3)')

  call a%set_green(GFMD_GREEN_LAYER_FLUID, 4.0_dp)
  call b%set_green(GFMD_GREEN_LAYER_FLUID, 4.0_dp)
  call a%set_pressure(0.02_dp)
  call b%set_pressure(0.02_dp)
  call a%step(40)
  call b%step(40)
  call a%get_contact_area(area_a)
  call b%get_contact_area(area_b)
  call a%get_energies(ea, ad)
  call b%get_energies(eb, ad)
  call gfmd_mpi_get_local_surface(a, za)
  call gfmd_mpi_get_local_surface(b, zb)
  call expect(area_a == area_b .and. ea == eb .and. all(za == zb), 'type(MPI_Comm) and integer handles: same bits')
  call expect(area_a > 0 .and. area_a < 1, 'a partial contact')

  ! The local rows of the patch labels: those of a serial simulation of the same surface's contact
  ! (its labels of the gathered surface's contact set), and the same count on every rank.
  block
    integer, allocatable :: lab(:, :), wlab(:, :), all_lab(:, :)
    logical, allocatable :: contact(:, :)
    real(dp), allocatable :: gap(:, :), all_gap(:, :)
    integer :: n, m, counts(64), displs(64), r
    allocate (lab(nx, local_ny), gap(nx, local_ny), all_lab(nx, ny), all_gap(nx, ny), contact(nx, ny), wlab(nx, ny))
    call gfmd_mpi_get_local_contact_patches(a, lab, n, connectivity=8)
    call gfmd_mpi_get_local_gap(a, gap)
    call MPI_Allgather(nx * local_ny, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, MPI_COMM_WORLD)
    displs(1) = 0
    do r = 2, size
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
    call MPI_Allgatherv(gap, nx * local_ny, MPI_DOUBLE_PRECISION, all_gap, counts, displs, MPI_DOUBLE_PRECISION, &
                        MPI_COMM_WORLD)
    call MPI_Allgatherv(lab, nx * local_ny, MPI_INTEGER, all_lab, counts, displs, MPI_INTEGER, MPI_COMM_WORLD)
    contact = all_gap <= 0
    call gfmd_label_patches(contact, wlab, m, connectivity=8)
    call expect(n == m .and. n > 0 .and. all(all_lab == wlab), 'local patch labels are those of the whole contact')
  end block

  call a%get_surface(whole, stat=st, errmsg=msg)
  if (size > 1) then
    call expect(st == GFMD_ERR_STATE, 'whole-grid getter refused on several ranks')
  else
    call expect(st == GFMD_OK, 'whole-grid getter on one rank')
  end if

  call a%save('mpi_fortran.gfmd')
  call gfmd_sim_load_mpi(c, 'mpi_fortran.gfmd', MPI_COMM_WORLD%MPI_VAL)
  call a%step(10)
  call c%step(10)
  call a%get_energies(ea, ad)
  call c%get_energies(eb, ad)
  call expect(ea == eb, 'a checkpoint loaded through the integer communicator continues with the same bits')
  call gfmd_sim_load_mpi(c, 'no/such/file.gfmd', MPI_COMM_WORLD, stat=st)
  call expect(st == GFMD_ERR_IO, 'missing checkpoint: GFMD_ERR_IO')

  call a%destroy()
  call b%destroy()
  call c%destroy()
  ! (a main program's allocatables are not deallocated at its end: the leak check would see them)
  deallocate (h, back, whole, za, zb)
  call MPI_Allreduce(failures, total, 1, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD)
  if (rank == 0) then
    if (total == 0) then
      print '(a, i0, a)', 'test_mpi_fortran on ', size, ' ranks: passed'
    else
      print '(a, i0, a)', 'test_mpi_fortran: FAILED (', total, ' failures)'
    end if
  end if
  call MPI_Finalize()
  if (total /= 0) error stop 1

contains

  subroutine expect(ok, what)
    logical, intent(in) :: ok
    character(*), intent(in) :: what
    if (.not. ok) then
      failures = failures + 1
      print '(a, i0, 2a)', 'rank ', rank, ': FAILED: ', what
    end if
  end subroutine expect

end program test_mpi_fortran
