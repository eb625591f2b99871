!> The Fortran bindings against the C library: the same problem through the module gfmd and
!> through direct C calls (module gfmd_c_api) must give identical surfaces and A/A0 to 1e-12; the
!> layout (nx /= ny) is x fastest; errors come back through stat/errmsg; destroy is idempotent;
!> assignment copies.
program test_fortran_bindings
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_int64_t, c_double, c_int32_t
  use gfmd
  use gfmd_c_api
  implicit none
  integer :: passed = 0, failed = 0

  call same_problem_as_c()
  call portable_surface_and_layout()
  call layout_non_square()
  call error_paths()
  call destroy_twice()
  call assignment_copies()
  call checkpoint_restart()
  call theory_and_fits()
  call wide_seed_and_creation_options()
  call patches_histogram_and_plasticity()
  call topographies()
  call free_boundaries()

  print '(i0, " passed, ", i0, " failed")', passed, failed
  if (failed > 0) error stop 1

contains

  subroutine check(cond, what)
    logical, intent(in) :: cond
    character(*), intent(in) :: what
    if (cond) then
      passed = passed + 1
    else
      failed = failed + 1
      print '(a)', 'FAILED: ' // what
    end if
  end subroutine check

  subroutine ok(st, what)
    integer(c_int32_t), intent(in) :: st
    character(*), intent(in) :: what
    call check(st == GFMD_OK, what)
  end subroutine ok

  !> Same seed, same relaxation, through the module and through raw C calls.
  !> A seed above 2^31 reaches C unchanged (the surface equals C's for the same 64-bit seed); a
  !> handle created with threads and planner reports them; restart_solver continues like a same-
  !> pressure restart of a twin (the C test_continuation proves the trajectory itself).
  subroutine wide_seed_and_creation_options()
    integer, parameter :: nx = 32, ny = 24
    integer(c_int64_t), parameter :: seed = 2_c_int64_t**40 + 3_c_int64_t
    type(gfmd_sim_t) :: a, b
    type(c_ptr) :: p
    real(dp) :: hf(nx, ny), hc(nx * ny), h32(nx, ny), za(nx, ny), zb(nx, ny), dmean, pmean
    integer :: threads, st, solver

    call a%create(nx, ny, real(nx, dp), real(ny, dp), threads=1, planner=GFMD_PLANNER_ESTIMATE)
    call a%get_threads(threads)
    call check(threads == 1, 'create with threads = 1 keeps one thread')
    call a%get_solver(solver)
    call check(solver == GFMD_SOLVER_CG, 'the automatic choice on a small non-adhesive half-space is CG')
    call check(GFMD_SOLVER_FIRE_MASS == GFMD_SOLVER_MASS_WEIGHTED_FIRE .and. GFMD_SOLVER_MASS_WEIGHTED_FIRE == 2 .and. &
               GFMD_SOLVER_MASS_FIRE == GFMD_SOLVER_APPROACH_THEN_FIRE .and. GFMD_SOLVER_APPROACH_THEN_FIRE == 5, &
               'the deprecated solver names keep their values')
    call a%generate_selfaffine(0.8_dp, 16.0_dp, 4.0_dp, 1.0_dp, seed)
    call a%get_heights(hf)
    p = c_null_ptr
    call ok(c_gfmd_sim_create_ex(int(nx, c_int64_t), int(ny, c_int64_t), real(nx, c_double), real(ny, c_double), &
                                 1_c_int32_t, int(GFMD_PLANNER_ESTIMATE, c_int32_t), p), 'C create')
    call ok(c_gfmd_generate_selfaffine(p, 0.8_dp, 16.0_dp, 4.0_dp, 1.0_dp, seed, int(GFMD_DIST_UNIFORM, c_int32_t)), &
            'C generate')
    call ok(c_gfmd_get_heights(p, hc), 'C heights')
    call c_gfmd_sim_destroy(p)
    call check(all(hf == reshape(hc, [nx, ny])), 'a 64-bit seed gives C''s surface')
    call a%generate_selfaffine(0.8_dp, 16.0_dp, 4.0_dp, 1.0_dp, 3)
    call a%get_heights(h32)
    call check(any(h32 /= hf), 'a narrowed seed (3 = 2^40 + 3 mod 2^32) would give another surface')

    call a%generate_selfaffine(0.8_dp, 16.0_dp, 4.0_dp, 1.0_dp, seed)
    call a%set_pressure(0.02_dp)
    call a%step(20)
    b = a
    call a%restart_solver()
    call b%set_pressure(0.02_dp)
    call a%step(30)
    call b%step(30)
    call a%get_surface(za)
    call b%get_surface(zb)
    call check(all(za == zb), 'restart_solver restarts as a change of the landscape does')
    call a%create(nx, ny, 1.0_dp, 1.0_dp, planner=99, stat=st)
    call check(st == GFMD_ERR_BAD_ENUM, 'an unknown planner at creation is refused')
    ! displacement control through the module: the prescribed mean holds, the pressure follows
    call b%set_mean_displacement(maxval(hf) - 0.3_dp)
    call b%relax()
    call b%get_mean_displacement(dmean)
    call b%get_mean_pressure(pmean)
    call check(abs(dmean - (maxval(hf) - 0.3_dp)) <= 1e-12_dp, 'set_mean_displacement holds the mean of z')
    call check(pmean > 0.0_dp, 'a body pressed below the highest peak carries a compressive mean pressure')
    call b%set_mean_displacement(-1e3_dp, stat=st)
    call check(st == GFMD_ERR_INVALID_ARG, 'a mean below the substrate is refused')
    call a%destroy()
    call b%destroy()
  end subroutine wide_seed_and_creation_options

  !> Patches, the pressure histogram, Persson's P(p) and plasticity through the module against the
  !> same calls of the C API on the same handle: equal to the bit; the hand-made sets' known counts.
  subroutine patches_histogram_and_plasticity()
    integer, parameter :: nx = 64, ny = 48, nb = 20
    type(gfmd_sim_t) :: sim
    type(c_ptr) :: p
    logical :: board(8, 6)
    integer :: labels(8, 6), n, lab(nx, ny), i, j, st
    integer(c_int64_t) :: labc(nx, ny), nc
    real(dp), allocatable :: area(:)
    real(dp) :: areac(1000), frac(nb), mean(nb), fracc(nb), meanc(nb), range(2), rangec(2)
    real(dp) :: pa(3), dens(3), densc(3), plastic, volume, plc, voc, hard, a

    do j = 1, 6
      do i = 1, 8
        board(i, j) = mod(i + j, 2) == 0
      end do
    end do
    call gfmd_label_patches(board, labels, n, connectivity=4)
    call check(n == 24 .and. labels(1, 1) == 1 .and. labels(2, 1) == 0 .and. labels(3, 1) == 2, &
               'a checkerboard is 24 patches with 4-connectivity, numbered x fastest')
    call gfmd_label_patches(board, labels, n, connectivity=8)
    call check(n == 1 .and. all((labels == 1) .eqv. board), 'and one with 8')
    call gfmd_label_patches(board, labels, n, connectivity=5, stat=st)
    call check(st == GFMD_ERR_INVALID_ARG, 'connectivity 5 is refused')

    call sim%create(nx, ny, real(nx, dp), real(ny, dp))
    call sim%generate_selfaffine(0.8_dp, 32.0_dp, 4.0_dp, 1.0_dp, seed=5)
    call sim%set_hardness(0.4_dp)
    call sim%set_pressure(0.05_dp)
    call sim%relax(tol=1e-9_dp)
    p = gfmd_sim_c_handle(sim)
    call sim%get_contact_patches(lab, n, connectivity=8)
    call ok(c_gfmd_get_contact_patches(p, 8_c_int32_t, labc, nc), 'C patches')
    call check(n == nc .and. all(lab == labc), 'the same labels as C')
    call sim%get_patch_property(GFMD_PATCH_AREA, area, connectivity=8)
    call ok(c_gfmd_get_patch_property(p, 8_c_int32_t, int(GFMD_PATCH_AREA, c_int32_t), 1000_c_int64_t, areac, nc), &
            'C patch areas')
    call sim%get_contact_area(a)
    call check(size(area) == n .and. all(area == areac(1:n)), 'the same patch areas as C')
    call check(sum(area) == a * nx * ny, 'the patch areas sum to A/A0 times the cell')
    range = 0.0_dp
    call sim%get_pressure_histogram(frac, mean, range)
    rangec = 0.0_dp
    call ok(c_gfmd_get_pressure_histogram(p, int(nb, c_int64_t), rangec, fracc, meanc), 'C histogram')
    call check(all(frac == fracc) .and. all(mean == meanc) .and. all(range == rangec), 'the same histogram as C')
    call check(abs(sum(frac) - a) <= 1e-14_dp, 'the histogram sums to A/A0')
    pa = [0.0_dp, 0.05_dp, 0.2_dp]
    call sim%persson_pressure_distribution(0.05_dp, pa, dens)
    call ok(c_gfmd_persson_pressure_distribution(p, 0.05_dp, 3_c_int64_t, pa, densc), 'C P(p)')
    call check(all(dens == densc) .and. dens(1) == 0.0_dp, 'the same P(p) as C, 0 at p = 0')
    call sim%get_plasticity(plastic, volume)
    call ok(c_gfmd_get_plasticity(p, plc, voc), 'C plasticity')
    call sim%get_hardness(hard)
    call check(plastic == plc .and. volume == voc .and. plastic > 0.0_dp .and. hard == 0.4_dp, &
               'the same plastic state as C, some points yielding')
    call sim%set_hardness(-1.0_dp, stat=st)
    call check(st == GFMD_ERR_INVALID_ARG, 'a negative hardness is refused')
    call sim%destroy()
  end subroutine patches_histogram_and_plasticity

  subroutine same_problem_as_c()
    integer, parameter :: nx = 48, ny = 32
    type(gfmd_sim_t) :: sim
    type(c_ptr) :: p
    real(dp) :: hf(nx, ny), hc(nx * ny), area_f, gap_f, el_f, area_c, gap_c, el_c, ad
    integer(c_int64_t) :: taken
    integer :: steps

    call sim%create(nx, ny, real(nx, dp), real(ny, dp))
    call sim%generate_selfaffine(0.8_dp, 16.0_dp, 4.0_dp, 1.0_dp, seed=11)
    call sim%set_green(GFMD_GREEN_LAYER_FLUID, 6.0_dp)
    call sim%set_pressure(0.05_dp)
    call sim%relax(tol=1e-8_dp, steps=steps)
    call sim%get_heights(hf)
    call sim%get_contact_area(area_f)
    call sim%get_mean_gap(gap_f)
    call sim%get_energies(elastic=el_f)

    p = c_null_ptr
    call ok(c_gfmd_sim_create(int(nx, c_int64_t), int(ny, c_int64_t), real(nx, c_double), real(ny, c_double), p), &
            'C create')
    call ok(c_gfmd_generate_selfaffine(p, 0.8_dp, 16.0_dp, 4.0_dp, 1.0_dp, 11_c_int64_t, &
                                       int(GFMD_DIST_UNIFORM, c_int32_t)), 'C generate')
    call ok(c_gfmd_set_green(p, int(GFMD_GREEN_LAYER_FLUID, c_int32_t), 6.0_dp), 'C green')
    call ok(c_gfmd_set_pressure(p, 0.05_dp), 'C pressure')
    call ok(c_gfmd_relax(p, 1e-8_dp, 1000000_c_int64_t, taken), 'C relax')
    call ok(c_gfmd_get_heights(p, hc), 'C heights')
    call ok(c_gfmd_get_contact_area(p, area_c), 'C area')
    call ok(c_gfmd_get_mean_gap(p, gap_c), 'C gap')
    call ok(c_gfmd_get_energies(p, el_c, ad), 'C energies')
    call c_gfmd_sim_destroy(p)

    call check(all(hf == reshape(hc, [nx, ny])), 'same seed gives the same surface, element by element')
    call check(steps == taken, 'same number of steps')
    call check(abs(area_f - area_c) <= 1e-12_dp, 'same A/A0 to 1e-12')
    call check(abs(gap_f - gap_c) <= 1e-12_dp * abs(gap_c), 'same mean gap to 1e-12')
    call check(abs(el_f - el_c) <= 1e-12_dp * abs(el_c), 'same elastic energy to 1e-12')
    call check(area_f > 0.0_dp .and. area_f < 1.0_dp, 'partial contact')
    call sim%destroy()
  end subroutine same_problem_as_c

  !> The C test suite's recorded heights for seed 1234 (test_selfaffine.c): h[0] and
  !> h[1000] = h(ix = 40, iy = 15) in C, so h(41, 16) here if x runs fastest.
  subroutine portable_surface_and_layout()
    type(gfmd_sim_t) :: sim
    real(dp) :: h(64, 64)
    call sim%create(64, 64, 64.0_dp, 64.0_dp)
    call sim%generate_selfaffine(0.8_dp, 16.0_dp, 4.0_dp, 1.0_dp, 1234, GFMD_DIST_UNIFORM)
    call sim%get_heights(h)
    call check(abs(h(1, 1) - (-7.4601656021861711_dp)) < 1e-11_dp, 'h(1,1) as recorded in C')
    call check(abs(h(41, 16) - (-7.1371718903458916_dp)) < 1e-11_dp, 'h(41,16) = C h[1000]: x fastest')
    call sim%destroy()
  end subroutine portable_surface_and_layout

  !> A substrate varying along x only (the first index) on a 40 x 24 grid: the gap is constant
  !> along y, and the C view of the same memory indexes it as ix + nx*iy.
  subroutine layout_non_square()
    integer, parameter :: nx = 40, ny = 24
    real(dp), parameter :: pi = acos(-1.0_dp)
    type(gfmd_sim_t) :: sim
    real(dp) :: h(nx, ny), gap(nx, ny), gml(nx, ny)
    integer :: i, j
    do j = 1, ny
      do i = 1, nx
        h(i, j) = 0.5_dp * cos(2.0_dp * pi * (i - 1) / nx)
      end do
    end do
    call sim%create(nx, ny, real(nx, dp), real(ny, dp))
    call sim%set_heights(h)
    call sim%set_pressure(0.01_dp)
    call sim%relax(tol=1e-10_dp)
    call sim%get_gap(gap)
    call check(maxval(abs(gap - spread(gap(:, 1), 2, ny))) < 1e-9_dp, 'gap constant along y (second index)')
    call check(maxval(gap(:, 1)) - minval(gap(:, 1)) > 0.1_dp, 'gap varies along x (first index)')
    call check(gap(1, 1) == 0.0_dp .and. gap(nx / 2 + 1, 1) > 0.0_dp, 'contact at the crest x = 0, open at the valley')
    ! the same equilibrium from a start made on coarser grids
    call sim%reset()
    call sim%relax_multilevel(2, tol=1e-10_dp, steps=i, coarse_steps=j)
    call sim%get_gap(gml)
    call check(j > 0 .and. maxval(abs(gml - gap)) < 1e-8_dp, 'relax_multilevel ends where relax ends')
    call sim%relax_multilevel(0, stat=i)
    call check(i == GFMD_ERR_INVALID_ARG, 'relax_multilevel refuses 0 levels')
    call sim%destroy()
  end subroutine layout_non_square

  subroutine error_paths()
    type(gfmd_sim_t) :: sim, never
    integer :: st, steps
    character(len=300) :: msg
    real(dp) :: a0, a1, small(10, 10), f

    call sim%create(0, 5, 1.0_dp, 1.0_dp, stat=st, errmsg=msg)
    call check(st == GFMD_ERR_INVALID_ARG, 'create with nx = 0')
    call check(.not. sim%is_created(), 'failed create leaves nothing')
    call check(index(msg, 'create') > 0, 'create message: ' // trim(msg))

    call never%set_pressure(0.1_dp, stat=st, errmsg=msg)
    call check(st == GFMD_ERR_NULL, 'call on a simulation never created')
    call check(index(msg, 'create first') > 0, 'message says to create first: ' // trim(msg))

    call sim%create(32, 32, 32.0_dp, 32.0_dp)
    call sim%generate_selfaffine(0.8_dp, 8.0_dp, 4.0_dp, 1.0_dp, 5)
    call sim%set_pressure(0.05_dp)
    call sim%relax()
    call sim%get_contact_area(a0)

    call sim%set_pressure(-1.0_dp, stat=st, errmsg=msg)
    call check(st == GFMD_ERR_INVALID_ARG, 'negative pressure')
    call check(index(msg, 'sigma0') > 0, 'message names sigma0: ' // trim(msg))
    call check(index(sim%last_error(), 'sigma0') > 0, 'last_error names sigma0')
    call sim%get_contact_area(a1)
    call check(a0 == a1, 'failed call leaves the state unchanged')

    call sim%set_green(99, 1.0_dp, stat=st)
    call check(st == GFMD_ERR_BAD_ENUM, 'unknown Green kind')
    call sim%set_green(GFMD_GREEN_LAYER_BONDED, 1.0_dp, stat=st, errmsg=msg)
    call check(st == GFMD_ERR_STATE, 'bonded layer without Poisson ratio')
    call sim%set_solver(GFMD_SOLVER_NEWTON, stat=st, errmsg=msg)
    call check(st == GFMD_ERR_STATE, 'the Newton solver refuses a half-space')
    call check(index(msg, 'fluid foundation') > 0, 'Newton message: ' // trim(msg))
    call sim%get_gap(small, stat=st, errmsg=msg)
    call check(st == GFMD_ERR_INVALID_ARG, 'wrong array shape')
    call check(index(msg, '(nx, ny) = (32, 32)') > 0, 'shape message: ' // trim(msg))

    call sim%set_pressure(0.2_dp)
    call sim%relax(tol=1e-14_dp, max_steps=2, steps=steps, stat=st, errmsg=msg)
    call check(st == GFMD_ERR_NOT_CONVERGED, 'not converged')
    call check(steps == 2, 'steps reported when not converged')
    call sim%relax(stat=st)
    call check(st == GFMD_OK, 'a later relax continues and converges')

    call sim%set_pressure(0.1_dp, stat=st, errmsg=msg)
    call check(st == GFMD_OK .and. len_trim(msg) == 0, 'success clears errmsg')

    call gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, 1.0_dp, f)
    call check(abs(f - 7.382435_dp) < 1e-6_dp, 'green factor f(1)')
    call gfmd_green_factor(GFMD_GREEN_LAYER_FLUID, -1.0_dp, f, stat=st)
    call check(st == GFMD_ERR_INVALID_ARG, 'green factor of t < 0')
    call check(len(gfmd_status_string(GFMD_ERR_DIVERGED)) > 0, 'status string')
    call check(len(gfmd_version()) > 0, 'version string')
    call sim%destroy()
  end subroutine error_paths

  subroutine destroy_twice()
    type(gfmd_sim_t) :: sim, never
    call sim%create(8, 8, 8.0_dp, 8.0_dp)
    call check(sim%is_created(), 'created')
    call sim%destroy()
    call sim%destroy()
    call never%destroy()
    call check(.not. sim%is_created(), 'destroyed twice without harm')
  end subroutine destroy_twice

  subroutine assignment_copies()
    type(gfmd_sim_t) :: a, b, c
    real(dp) :: area_a, area_b, area_a2
    call a%create(32, 32, 32.0_dp, 32.0_dp)
    call a%generate_selfaffine(0.8_dp, 8.0_dp, 4.0_dp, 1.0_dp, 8)
    call a%set_pressure(0.05_dp)
    call a%relax()
    call a%get_contact_area(area_a)
    b = a
    call check(b%is_created(), 'assignment makes a copy')
    call b%get_contact_area(area_b)
    call check(area_a == area_b, 'the copy has the same state')
    call b%set_pressure(0.3_dp)
    call b%relax()
    call b%get_contact_area(area_b)
    call a%get_contact_area(area_a2)
    call check(area_a2 == area_a .and. area_b > area_a, 'the copy is independent')
    b = c   ! assigning an empty simulation frees b's
    call check(.not. b%is_created(), 'assigning an empty simulation empties')
    call a%copy_to(c)
    call check(c%is_created(), 'copy_to')
    call a%destroy()
    call b%destroy()
    call c%destroy()
  end subroutine assignment_copies

  !> Save, load, and continue: the same as continuing the original, bit for bit; a damaged
  !> file is refused through stat and leaves the object as it was.
  !> A text matrix written here read back bit for bit (x fastest: h(nx, ny)); a generated
  !> surface's spectrum through the module against the C calls on the same handle, bit for bit;
  !> its rms slope the generator's; Persson's area the simulation's; errors through stat.
  !> Free boundaries through the module and through the C API: the same surface to the bit, the
  !> boundary reported, a layer refused and an unknown boundary too.
  subroutine free_boundaries()
    integer, parameter :: nx = 24, ny = 16
    type(gfmd_sim_t) :: a
    type(c_ptr) :: p
    real(dp) :: za(nx, ny), zc(nx * ny)
    integer :: boundary, st
    integer(c_int64_t) :: steps
    call a%create(nx, ny, real(nx, dp), real(ny, dp), threads=1, planner=GFMD_PLANNER_ESTIMATE)
    call a%set_boundary(GFMD_BOUNDARY_FREE)
    call a%get_boundary(boundary)
    call check(boundary == GFMD_BOUNDARY_FREE, 'the boundary set is the boundary reported')
    call a%generate_selfaffine(0.8_dp, 12.0_dp, 4.0_dp, 1.0_dp, 5)
    call a%set_pressure(0.05_dp)
    call a%relax()
    call a%get_surface(za)
    p = c_null_ptr
    call ok(c_gfmd_sim_create_ex(int(nx, c_int64_t), int(ny, c_int64_t), real(nx, c_double), real(ny, c_double), &
                                 1_c_int32_t, int(GFMD_PLANNER_ESTIMATE, c_int32_t), p), 'C create')
    call ok(c_gfmd_set_boundary(p, int(GFMD_BOUNDARY_FREE, c_int32_t)), 'C boundary')
    call ok(c_gfmd_generate_selfaffine(p, 0.8_dp, 12.0_dp, 4.0_dp, 1.0_dp, 5_c_int64_t, &
                                       int(GFMD_DIST_UNIFORM, c_int32_t)), 'C generate')
    call ok(c_gfmd_set_pressure(p, 0.05_dp), 'C pressure')
    call ok(c_gfmd_relax(p, 0.0_dp, 1000000_c_int64_t, steps), 'C relax')
    call ok(c_gfmd_get_surface(p, zc), 'C surface')
    call c_gfmd_sim_destroy(p)
    call check(all(za == reshape(zc, [nx, ny])), 'free boundaries: the module''s surface is the C API''s')
    call a%set_green(GFMD_GREEN_LAYER_FLUID, 2.0_dp, stat=st)
    call check(st == GFMD_ERR_STATE, 'a layer with free boundaries is refused')
    call a%set_boundary(5, stat=st)
    call check(st == GFMD_ERR_BAD_ENUM, 'an unknown boundary is refused')
    call a%destroy()
  end subroutine free_boundaries

  subroutine topographies()
    integer, parameter :: nx = 6, ny = 4, n = 64, nb = 12
    type(gfmd_topo_t) :: t, g
    type(gfmd_sim_t) :: sim
    real(dp) :: h(nx, ny), back(nx, ny), hs(n, n), q(nb), c(nb), qc(nb), cc(nb), lx, ly
    real(dp) :: rh, rs, rk, a, sa, v, mg, mgc
    real(dp), allocatable :: q1(:), c1(:)
    integer :: i, j, u, gx, gy, f, m, st, count(nb)
    integer(c_int64_t) :: countc(nb)
    logical :: units
    do j = 1, ny
      do i = 1, nx
        h(i, j) = real(i * 7 + j * 13, dp) / 8.0_dp
      end do
    end do
    open (newunit=u, file='fortran_topo.txt', status='replace', action='write')
    write (u, '(a)') '# a scan exported as text'
    do j = 1, ny
      write (u, '(*(g0, :, " "))') (h(i, j), i = 1, nx)
    end do
    close (u)
    call t%read('fortran_topo.txt')
    call t%get_grid(gx, gy, lx, ly)
    call t%get_info(f, units, m)
    call check(gx == nx .and. gy == ny .and. f == GFMD_TOPO_MATRIX .and. .not. units .and. m == 0, &
               'a text matrix: its grid, format, no units, nothing missing')
    call t%get_heights(back)
    call check(all(back == h), 'read back bit for bit, x fastest')
    call t%read('no/such/file.txt', stat=st)
    call check(st == GFMD_ERR_IO, 'a missing file: GFMD_ERR_IO')
    call t%fill_missing(method=9, stat=st)
    call check(st == GFMD_ERR_BAD_ENUM, 'an unknown fill method is refused')
    call t%destroy()

    call sim%create(n, n, real(n, dp), real(n, dp), planner=GFMD_PLANNER_ESTIMATE)
    call sim%generate_selfaffine(0.8_dp, 32.0_dp, 4.0_dp, 0.3_dp, seed=9)
    call sim%get_heights(hs)
    call g%from_heights(hs, real(n, dp), real(n, dp))
    call g%psd(q, c, count)
    call check(sum(count) == n * n - 1, 'every mode but q = 0 in the bins')
    call g%moments(rh, rs, rk)
    call check(abs(rs / 0.3_dp - 1) < 1e-12_dp, 'the rms slope is the generator''s rms gradient')
    call g%persson_contact_area(0.05_dp, a, variance=v)
    call sim%persson_contact_area(0.05_dp, sa)
    call check(abs(a / sa - 1) < 1e-12_dp, 'Persson''s area of the topography is the simulation''s')
    call g%persson_mean_gap(0.05_dp, mg)
    call check(gfmd_topo_format_supported(GFMD_TOPO_GSF) .and. .not. gfmd_topo_format_supported(99) .and. &
               (gfmd_topo_format_supported(GFMD_TOPO_X3P) .eqv. (c_gfmd_topo_format_supported(GFMD_TOPO_X3P) == 1)), &
               'which formats this build reads')
    call check(c_gfmd_topo_persson_mean_gap(gfmd_topo_c_handle(g), GFMD_WINDOW_NONE, GFMD_GREEN_HALFSPACE, 0.0_dp, &
                                            0.0_dp, 1.0_dp, 0.05_dp, 0.45_dp, mgc) == 0 .and. mg == mgc .and. mg > 0, &
               'Persson''s mean gap: the module''s is the C API''s')
    call g%profile_psd(q1, c1)
    call check(size(q1) == n / 2 + 1 .and. abs(q1(1) - 8.0_dp * atan(1.0_dp) / n) < 1e-15_dp, &
               'the profiles'' PSD: nx/2 + 1 wavenumbers 2 pi k / lx')
    ! the same bins from the C call on the same handle: equal to the bit
    qc = 0
    cc = 0
    call check(c_gfmd_topo_psd(gfmd_topo_c_handle(g), GFMD_WINDOW_NONE, int(nb, c_int64_t), qc, cc, countc) == 0, 'C psd')
    call check(all(q == qc) .and. all(c == cc) .and. all(count == countc), 'the module''s PSD is the C API''s')
    call g%destroy()
    call sim%destroy()
  end subroutine topographies

  subroutine checkpoint_restart()
    type(gfmd_sim_t) :: a, b
    real(dp) :: za(24, 16), zb(24, 16), area
    integer :: st, u, nthreads
    character(len=300) :: msg
    call a%create(24, 16, 24.0_dp, 16.0_dp)
    call a%set_threads(1)
    call a%get_threads(nthreads)
    call check(nthreads == 1, 'threads set')
    call a%generate_selfaffine(0.8_dp, 8.0_dp, 3.0_dp, 1.0_dp, 4)
    call a%set_pressure(0.05_dp)
    call a%step(20)
    call a%save('fortran_checkpoint.gfmd')
    call b%load('fortran_checkpoint.gfmd')
    call a%step(30)
    call b%step(30)
    call a%get_surface(za)
    call b%get_surface(zb)
    call check(all(za == zb), 'restart continues bit for bit')
    open (newunit=u, file='fortran_damaged.gfmd', status='replace', access='stream')
    write (u) 'GFMDCKPT', 1_c_int32_t
    close (u)
    call b%get_contact_area(area)
    call b%load('fortran_damaged.gfmd', stat=st, errmsg=msg)
    call check(st == GFMD_ERR_FORMAT, 'truncated checkpoint refused')
    call check(index(msg, 'truncated') > 0, 'load message: ' // trim(msg))
    call check(b%is_created(), 'a refused load keeps the simulation')
    call b%load('no/such/file', stat=st)
    call check(st == GFMD_ERR_IO, 'missing checkpoint')
    call gfmd_export_wisdom('fortran_wisdom.txt', stat=st)
    call check(st == GFMD_OK, 'export wisdom')
    call a%destroy()
    call b%destroy()
    open (newunit=u, file='fortran_checkpoint.gfmd')
    close (u, status='delete')
    open (newunit=u, file='fortran_damaged.gfmd')
    close (u, status='delete')
    open (newunit=u, file='fortran_wisdom.txt')
    close (u, status='delete')
  end subroutine checkpoint_restart

  !> Persson's theory and the least-squares fit through the module: the half-space variance is
  !> (E* g/2)^2 (exact for the generator's spectral gradient; 1e-12 for the sums' rounding) and a
  !> Fortran (column-major) matrix fits a known line exactly; bad shapes come back as stat.
  subroutine theory_and_fits()
    type(gfmd_sim_t) :: sim
    real(dp) :: v, area, a(5, 2), b(5), x(2), rss, x3(3)
    integer :: st, i
    character(200) :: msg
    call sim%create(64, 64, 64.0_dp, 64.0_dp)
    call sim%generate_selfaffine(0.8_dp, 16.0_dp, 4.0_dp, 1.0_dp, 3)
    call sim%persson_variance(v)
    call check(abs(v - 0.25_dp) < 1e-12_dp, 'Persson variance of a half-space = (E* g/2)^2')
    call sim%persson_contact_area(0.1_dp, area)
    call check(abs(area - erf(0.1_dp / sqrt(0.5_dp))) < 1e-14_dp, 'Persson area = erf(sigma0/sqrt(2V))')
    call sim%persson_contact_area(-1.0_dp, area, stat=st, errmsg=msg)
    call check(st == GFMD_ERR_INVALID_ARG .and. index(msg, 'sigma0') > 0, 'negative load refused with a message')
    ! the inverse, to the rounding of the bisection (the last bit of x) and of V (1e-12 above)
    call sim%persson_load(erf(0.1_dp / sqrt(0.5_dp)), x(1))
    call check(abs(x(1) - 0.1_dp) < 1e-12_dp, 'Persson load inverts the area')
    call sim%persson_load(1.0_dp, x(1), stat=st, errmsg=msg)
    call check(st == GFMD_ERR_INVALID_ARG .and. index(msg, 'rel_area') > 0, 'full contact refused with a message')
    do i = 1, 5
      a(i, 1) = 1.0_dp
      a(i, 2) = real(i, dp)
      b(i) = 2.0_dp - 0.5_dp * real(i, dp)
    end do
    call gfmd_least_squares(a, b, x, rss)
    call check(abs(x(1) - 2.0_dp) < 1e-13_dp .and. abs(x(2) + 0.5_dp) < 1e-13_dp .and. rss < 1e-26_dp, &
               'least squares recovers the line 2 - x/2')
    x3 = 7.0_dp
    call gfmd_least_squares(a, b, x3, stat=st, errmsg=msg)
    call check(st == GFMD_ERR_INVALID_ARG .and. all(x3 == 7.0_dp), 'wrong size of x refused, x unchanged')
    a(:, 2) = 3.0_dp * a(:, 1)
    call gfmd_least_squares(a, b, x, stat=st)
    call check(st == GFMD_ERR_INVALID_ARG, 'rank-deficient matrix refused')
  end subroutine theory_and_fits
end program test_fortran_bindings
