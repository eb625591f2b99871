!> gfmd for Fortran: Green's function molecular dynamics for the contact between a rigid rough
!> substrate and an elastic half-space or thin layer (Putignano, Dapp & Mueser, Biomimetics 1, 7 (2016)).
!>
!>   use gfmd
!>   type(gfmd_sim_t) :: sim
!>   call sim%create(nx, ny, lx, ly)
!>
!> Fields are real(dp) arrays f(nx, ny): exactly the C layout (x fastest), passed without copies.
!> Every procedure takes optional `stat` and `errmsg`: with `stat` present, errors are returned
!> (stat /= GFMD_OK, errmsg set); without it, an error stops the program with the library's message.
!> Free a simulation with `call sim%destroy()` (idempotent); the finalizer is only a safety net.
!> Assignment `b = a` makes an independent deep copy, never a second owner of one handle.
module gfmd
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_char, c_double, c_int32_t, c_int64_t
  use gfmd_c_api
  use gfmd_report, only: c_string, finish, gfmd_status_string, handle_message, buffer_text
  implicit none
  private

  integer, parameter, public :: dp = c_double
  include 'gfmd_constants.inc'

  public :: gfmd_sim_t, gfmd_version, gfmd_status_string, gfmd_green_factor, gfmd_least_squares
  public :: gfmd_import_wisdom, gfmd_export_wisdom
  public :: gfmd_sim_adopt, gfmd_sim_c_handle, gfmd_label_patches
  public :: gfmd_topo_t, gfmd_topo_c_handle, gfmd_topo_format_supported

  !> A measured topography (gfmd_topo_*): heights h(nx, ny), NaN at missing points, read from an
  !> instrument's file or given.  Free it with `call topo%destroy()`.
  type :: gfmd_topo_t
    private
    type(c_ptr) :: ptr = c_null_ptr
  contains
    procedure :: read => topo_read
    procedure :: from_heights => topo_from_heights
    procedure :: destroy => topo_destroy
    procedure :: get_grid => topo_get_grid
    procedure :: get_info => topo_get_info
    procedure :: set_physical_size => topo_set_physical_size
    procedure :: get_heights => topo_get_heights
    procedure :: fill_missing => topo_fill_missing
    procedure :: detrend => topo_detrend
    procedure :: resample => topo_resample
    procedure :: psd => topo_psd
    procedure :: profile_psd => topo_profile_psd
    procedure :: moments => topo_moments
    procedure :: persson_contact_area => topo_persson_contact_area
    procedure :: persson_mean_gap => topo_persson_mean_gap
    final :: topo_final
  end type gfmd_topo_t

  !> A simulation: owns one C handle.
  type :: gfmd_sim_t
    private
    type(c_ptr) :: ptr = c_null_ptr
  contains
    procedure :: create => sim_create
    procedure :: destroy => sim_destroy
    procedure :: is_created => sim_is_created
    procedure :: copy_to => sim_copy_to
    procedure :: save => sim_save
    procedure :: load => sim_load
    procedure :: set_threads => sim_set_threads
    procedure :: get_threads => sim_get_threads
    procedure :: get_solver => sim_get_solver
    procedure :: set_fft_planner => sim_set_fft_planner
    procedure :: get_grid => sim_get_grid
    procedure :: set_modulus => sim_set_modulus
    procedure :: set_green => sim_set_green
    procedure :: set_boundary => sim_set_boundary
    procedure :: get_boundary => sim_get_boundary
    procedure :: set_poisson => sim_set_poisson
    procedure :: set_heights => sim_set_heights
    procedure :: get_heights => sim_get_heights
    procedure, private :: sim_generate_selfaffine, sim_generate_selfaffine_i32
    generic :: generate_selfaffine => sim_generate_selfaffine, sim_generate_selfaffine_i32
    procedure :: set_pressure => sim_set_pressure
    procedure :: set_mean_displacement => sim_set_mean_displacement
    procedure :: get_mean_displacement => sim_get_mean_displacement
    procedure :: get_mean_pressure => sim_get_mean_pressure
    procedure :: set_adhesion => sim_set_adhesion
    procedure :: set_timestep => sim_set_timestep
    procedure :: set_damping => sim_set_damping
    procedure :: set_solver => sim_set_solver
    procedure :: get_dynamics => sim_get_dynamics
    procedure :: step => sim_step
    procedure :: relax => sim_relax
    procedure :: relax_multilevel => sim_relax_multilevel
    procedure :: get_residual => sim_get_residual
    procedure :: reset => sim_reset
    procedure :: restart_solver => sim_restart_solver
    procedure :: get_contact_area => sim_get_contact_area
    procedure :: get_mean_gap => sim_get_mean_gap
    procedure :: get_energies => sim_get_energies
    procedure :: get_gap => sim_get_gap
    procedure :: get_surface => sim_get_surface
    procedure :: get_pressure => sim_get_pressure
    procedure :: persson_variance => sim_persson_variance
    procedure :: persson_contact_area => sim_persson_contact_area
    procedure :: persson_load => sim_persson_load
    procedure :: set_hardness => sim_set_hardness
    procedure :: get_hardness => sim_get_hardness
    procedure :: get_plasticity => sim_get_plasticity
    procedure :: get_contact_patches => sim_get_contact_patches
    procedure :: get_patch_property => sim_get_patch_property
    procedure :: get_pressure_histogram => sim_get_pressure_histogram
    procedure :: persson_pressure_distribution => sim_persson_pressure_distribution
    procedure :: last_error => sim_last_error
    procedure, private :: sim_assign
    generic :: assignment(=) => sim_assign
    final :: sim_final
  end type gfmd_sim_t

contains

  ! ------------------------------------------------------------------ helpers

  !> Check that a field argument is (nx, ny); report through finish if not.
  logical function shape_ok(self, a, where, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(in) :: a(:, :)
    character(*), intent(in) :: where
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    shape_ok = dims_ok(self, size(a, 1, kind=c_int64_t), size(a, 2, kind=c_int64_t), where, stat, errmsg)
  end function shape_ok

  !> The same for an array of any type of extents (n1, n2).
  logical function dims_ok(self, n1, n2, where, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    integer(c_int64_t), intent(in) :: n1, n2
    character(*), intent(in) :: where
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int64_t) :: nx, ny
    real(c_double) :: lx, ly
    integer(c_int32_t) :: st
    character(160) :: detail
    dims_ok = .false.
    st = c_gfmd_get_grid(self%ptr, nx, ny, lx, ly)
    if (st /= GFMD_OK) then
      call finish(self%ptr, st, where, stat, errmsg)
      return
    end if
    if (n1 /= nx .or. n2 /= ny) then
      write (detail, '(a,i0,a,i0,a,i0,a,i0,a)') 'the array is (', n1, ', ', n2, &
        '), the grid is (nx, ny) = (', nx, ', ', ny, ')'
      call finish(self%ptr, int(GFMD_ERR_INVALID_ARG, c_int32_t), where, stat, errmsg, trim(detail))
      return
    end if
    dims_ok = .true.
  end function dims_ok

  ! ------------------------------------------------------------------ module procedures

  !> Runtime version of the library, e.g. "0.1.0".
  function gfmd_version() result(v)
    character(:), allocatable :: v
    v = c_string(c_gfmd_version())
  end function gfmd_version

  !> f(t) of G(q) = 2 f(q w)/(q E*) for a kind of body; nu (default 0) for the bonded layer.
  subroutine gfmd_green_factor(kind, t, f, nu, stat, errmsg)
    integer, intent(in) :: kind
    real(dp), intent(in) :: t
    real(dp), intent(out) :: f
    real(dp), intent(in), optional :: nu
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double) :: n, ff
    integer(c_int32_t) :: st
    n = 0.0_dp
    if (present(nu)) n = nu
    ff = 0.0_dp
    st = c_gfmd_green_factor(int(kind, c_int32_t), t, n, ff)
    f = ff
    call finish(c_null_ptr, st, 'green_factor', stat, errmsg, '')
  end subroutine gfmd_green_factor

  !> Linear least squares (LAPACKE_dgels): x minimizing ||a x - b|| for an m x n matrix a of full
  !! column rank, m >= n >= 1 (a Fortran array is already the column-major layout the C API
  !! takes).  size(b) must be m and size(x) n; rss receives the residual sum of squares.
  subroutine gfmd_least_squares(a, b, x, rss, stat, errmsg)
    real(dp), intent(in), contiguous :: a(:, :)
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(inout) :: x(:)
    real(dp), intent(out), optional :: rss
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double) :: r, xx(max(1, size(x)))
    integer(c_int32_t) :: st
    r = 0.0_dp
    if (size(b) /= size(a, 1) .or. size(x) /= size(a, 2)) then
      call finish(c_null_ptr, GFMD_ERR_INVALID_ARG, 'least_squares', stat, errmsg, &
                  'size(b) must equal size(a, 1) and size(x) size(a, 2)')
      return
    end if
    xx = 0.0_dp
    st = c_gfmd_least_squares(int(size(a, 1), c_int64_t), int(size(a, 2), c_int64_t), a, b, xx, r)
    if (st == GFMD_OK) then
      x = xx(1:size(x))
      if (present(rss)) rss = r
    end if
    call finish(c_null_ptr, st, 'least_squares', stat, errmsg, '')
  end subroutine gfmd_least_squares

  !> A Fortran string as a NUL-terminated C string.
  function c_path(path) result(c)
    character(*), intent(in) :: path
    character(kind=c_char, len=:), allocatable :: c
    c = trim(path) // char(0)
  end function c_path

  !> Load FFTW wisdom from a file (process-wide).
  subroutine gfmd_import_wisdom(path, stat, errmsg)
    character(*), intent(in) :: path
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(c_null_ptr, c_gfmd_import_wisdom(c_path(path)), 'import_wisdom', stat, errmsg, trim(path))
  end subroutine gfmd_import_wisdom

  !> Save the process's FFTW wisdom to a file.
  subroutine gfmd_export_wisdom(path, stat, errmsg)
    character(*), intent(in) :: path
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(c_null_ptr, c_gfmd_export_wisdom(c_path(path)), 'export_wisdom', stat, errmsg, trim(path))
  end subroutine gfmd_export_wisdom

  ! ------------------------------------------------------------------ lifetime

  !> Create an nx x ny simulation on an lx x ly cell.
  !> Create (destroying what self held on success).  threads (0 = the default) and planner
  !> (GFMD_PLANNER_*, default GFMD_PLANNER_MEASURE) are fixed before the first FFT plan, as
  !> gfmd_sim_create_ex() does.
  subroutine sim_create(self, nx, ny, lx, ly, threads, planner, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(in) :: nx, ny
    real(dp), intent(in) :: lx, ly
    integer, intent(in), optional :: threads, planner
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    type(c_ptr) :: p
    integer(c_int32_t) :: st, t, pl
    t = 0
    pl = GFMD_PLANNER_MEASURE
    if (present(threads)) t = int(threads, c_int32_t)
    if (present(planner)) pl = int(planner, c_int32_t)
    st = c_gfmd_sim_create_ex(int(nx, c_int64_t), int(ny, c_int64_t), lx, ly, t, pl, p)
    if (st == GFMD_OK) then
      call c_gfmd_sim_destroy(self%ptr)
      self%ptr = p
    end if
    call finish(c_null_ptr, st, 'create', stat, errmsg, '')
  end subroutine sim_create

  !> Free the simulation; safe to call again or on one never created.
  subroutine sim_destroy(self)
    class(gfmd_sim_t), intent(inout) :: self
    call c_gfmd_sim_destroy(self%ptr)
  end subroutine sim_destroy

  logical function sim_is_created(self)
    class(gfmd_sim_t), intent(in) :: self
    sim_is_created = c_associated(self%ptr)
  end function sim_is_created

  !> Deep copy into `other` (its previous simulation is freed); stat-returning form of `other = self`.
  subroutine sim_copy_to(self, other, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    class(gfmd_sim_t), intent(inout) :: other
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    type(c_ptr) :: p
    integer(c_int32_t) :: st
    if (c_associated(self%ptr, other%ptr)) then
      call finish(self%ptr, int(GFMD_OK, c_int32_t), 'copy_to', stat, errmsg)
      return
    end if
    p = c_null_ptr
    st = GFMD_OK
    if (c_associated(self%ptr)) st = c_gfmd_sim_clone(self%ptr, p)
    if (st == GFMD_OK) then
      call c_gfmd_sim_destroy(other%ptr)
      other%ptr = p
    end if
    call finish(self%ptr, st, 'copy_to', stat, errmsg)
  end subroutine sim_copy_to

  !> other = self: a deep copy (stops the program with a message if the copy cannot be made).
  subroutine sim_assign(lhs, rhs)
    class(gfmd_sim_t), intent(inout) :: lhs
    class(gfmd_sim_t), intent(in) :: rhs
    call rhs%copy_to(lhs)
  end subroutine sim_assign

  subroutine sim_final(self)
    type(gfmd_sim_t), intent(inout) :: self
    call c_gfmd_sim_destroy(self%ptr)
  end subroutine sim_final

  !> Checkpoint: the complete state to a file (see docs/guarantees.md).
  subroutine sim_save(self, path, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    character(*), intent(in) :: path
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_sim_save(self%ptr, c_path(path)), 'save', stat, errmsg)
  end subroutine sim_save

  !> Restart: replace this object's simulation by the one saved in a checkpoint file (kept as
  !> it was if the file is refused).
  subroutine sim_load(self, path, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    character(*), intent(in) :: path
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    type(c_ptr) :: p
    integer(c_int32_t) :: st
    character(kind=c_char) :: buf(512)
    buf = char(0)
    st = c_gfmd_sim_load(c_path(path), p, buf, int(size(buf), c_int64_t))
    if (st == GFMD_OK) then
      call c_gfmd_sim_destroy(self%ptr)
      self%ptr = p
    end if
    call finish(c_null_ptr, st, 'load', stat, errmsg, buffer_text(buf))
  end subroutine sim_load

  !> Threads of this simulation (0 = all cores).
  subroutine sim_set_threads(self, nthreads, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(in) :: nthreads
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_threads(self%ptr, int(nthreads, c_int32_t)), 'set_threads', stat, errmsg)
  end subroutine sim_set_threads

  subroutine sim_get_threads(self, nthreads, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    integer, intent(out) :: nthreads
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: n
    integer(c_int32_t) :: st
    n = 0
    st = c_gfmd_get_threads(self%ptr, n)
    nthreads = int(n)
    call finish(self%ptr, st, 'get_threads', stat, errmsg)
  end subroutine sim_get_threads

  !> The solver that steps now: the one set, or the one GFMD_SOLVER_AUTO chose.
  subroutine sim_get_solver(self, solver, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    integer, intent(out) :: solver
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: k
    integer(c_int32_t) :: st
    k = 0
    st = c_gfmd_get_solver(self%ptr, k)
    solver = int(k)
    call finish(self%ptr, st, 'get_solver', stat, errmsg)
  end subroutine sim_get_solver

  !> GFMD_PLANNER_ESTIMATE, GFMD_PLANNER_MEASURE (default) or GFMD_PLANNER_PATIENT.
  subroutine sim_set_fft_planner(self, planner, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(in) :: planner
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_fft_planner(self%ptr, int(planner, c_int32_t)), 'set_fft_planner', stat, errmsg)
  end subroutine sim_set_fft_planner

  !> Grid size and cell lengths.
  subroutine sim_get_grid(self, nx, ny, lx, ly, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    integer, intent(out), optional :: nx, ny
    real(dp), intent(out), optional :: lx, ly
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int64_t) :: mx, my
    real(c_double) :: ax, ay
    integer(c_int32_t) :: st
    st = c_gfmd_get_grid(self%ptr, mx, my, ax, ay)
    if (st == GFMD_OK) then
      if (present(nx)) nx = int(mx)
      if (present(ny)) ny = int(my)
      if (present(lx)) lx = ax
      if (present(ly)) ly = ay
    end if
    call finish(self%ptr, st, 'get_grid', stat, errmsg)
  end subroutine sim_get_grid

  ! ------------------------------------------------------------------ the body and the substrate

  subroutine sim_set_modulus(self, e_star, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: e_star
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_modulus(self%ptr, e_star), 'set_modulus', stat, errmsg)
  end subroutine sim_set_modulus

  !> kind: GFMD_GREEN_HALFSPACE, GFMD_GREEN_LAYER_FLUID or GFMD_GREEN_LAYER_BONDED; width of a layer.
  !> GFMD_BOUNDARY_PERIODIC (default) or GFMD_BOUNDARY_FREE (gfmd_set_boundary in gfmd.h).
  subroutine sim_set_boundary(self, boundary, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(in) :: boundary
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_boundary(self%ptr, int(boundary, c_int32_t)), 'set_boundary', stat, errmsg)
  end subroutine sim_set_boundary

  subroutine sim_get_boundary(self, boundary, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    integer, intent(out) :: boundary
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: k
    integer(c_int32_t) :: st
    k = 0
    st = c_gfmd_get_boundary(self%ptr, k)
    boundary = int(k)
    call finish(self%ptr, st, 'get_boundary', stat, errmsg)
  end subroutine sim_get_boundary

  subroutine sim_set_green(self, kind, width, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(in) :: kind
    real(dp), intent(in), optional :: width
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double) :: w
    w = 0.0_dp
    if (present(width)) w = width
    call finish(self%ptr, c_gfmd_set_green(self%ptr, int(kind, c_int32_t), w), 'set_green', stat, errmsg)
  end subroutine sim_set_green

  subroutine sim_set_poisson(self, nu, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: nu
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_poisson(self%ptr, nu), 'set_poisson', stat, errmsg)
  end subroutine sim_set_poisson

  !> Substrate heights h(nx, ny); resets the body to flat at the highest point.
  subroutine sim_set_heights(self, h, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: h(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    if (.not. shape_ok(self, h, 'set_heights', stat, errmsg)) return
    call finish(self%ptr, c_gfmd_set_heights(self%ptr, h), 'set_heights', stat, errmsg)
  end subroutine sim_set_heights

  subroutine sim_get_heights(self, h, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(inout), contiguous :: h(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    if (.not. shape_ok(self, h, 'get_heights', stat, errmsg)) return
    call finish(self%ptr, c_gfmd_get_heights(self%ptr, h), 'get_heights', stat, errmsg)
  end subroutine sim_get_heights

  !> Self-affine substrate (see gfmd.h); distribution defaults to GFMD_DIST_UNIFORM.  A seed
  !> gives the same surface as the same seed in C.
  subroutine sim_generate_selfaffine(self, hurst, lambda_r, lambda_s, rms_gradient, seed, distribution, &
                                     stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: hurst, lambda_r, lambda_s, rms_gradient
    integer(c_int64_t), intent(in) :: seed  ! the C uint64_t's bits: seeds >= 2^63 are negative here
    integer, intent(in), optional :: distribution
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: d
    d = GFMD_DIST_UNIFORM
    if (present(distribution)) d = int(distribution, c_int32_t)
    call finish(self%ptr, c_gfmd_generate_selfaffine(self%ptr, hurst, lambda_r, lambda_s, rms_gradient, &
                                                     seed, d), &
                'generate_selfaffine', stat, errmsg)
  end subroutine sim_generate_selfaffine

  !> The same with a 32-bit seed (a default integer literal): widened, never narrowed.
  subroutine sim_generate_selfaffine_i32(self, hurst, lambda_r, lambda_s, rms_gradient, seed, distribution, &
                                         stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: hurst, lambda_r, lambda_s, rms_gradient
    integer(c_int32_t), intent(in) :: seed
    integer, intent(in), optional :: distribution
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call sim_generate_selfaffine(self, hurst, lambda_r, lambda_s, rms_gradient, int(seed, c_int64_t), &
                                 distribution, stat, errmsg)
  end subroutine sim_generate_selfaffine_i32

  ! ------------------------------------------------------------------ loads and dynamics

  subroutine sim_set_pressure(self, sigma0, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: sigma0
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_pressure(self%ptr, sigma0), 'set_pressure', stat, errmsg)
  end subroutine sim_set_pressure

  !> Displacement control: mean(z) = d (gfmd_set_mean_displacement()); set_pressure returns to
  !> pressure control.
  subroutine sim_set_mean_displacement(self, d, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: d
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_mean_displacement(self%ptr, d), 'set_mean_displacement', stat, errmsg)
  end subroutine sim_set_mean_displacement

  !> mean(z), under either control.
  subroutine sim_get_mean_displacement(self, d, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out) :: d
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_get_mean_displacement(self%ptr, d), 'get_mean_displacement', stat, errmsg)
  end subroutine sim_get_mean_displacement

  !> The mean pressure the body carries (sigma0, or the balancing one under displacement control).
  subroutine sim_get_mean_pressure(self, p, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out) :: p
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_get_mean_pressure(self%ptr, p), 'get_mean_pressure', stat, errmsg)
  end subroutine sim_get_mean_pressure

  subroutine sim_set_adhesion(self, gamma0, rho, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: gamma0, rho
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_adhesion(self%ptr, gamma0, rho), 'set_adhesion', stat, errmsg)
  end subroutine sim_set_adhesion

  subroutine sim_set_timestep(self, dt, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: dt
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_timestep(self%ptr, dt), 'set_timestep', stat, errmsg)
  end subroutine sim_set_timestep

  subroutine sim_set_damping(self, eta, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: eta
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_damping(self%ptr, eta), 'set_damping', stat, errmsg)
  end subroutine sim_set_damping

  !> GFMD_SOLVER_AUTO (default: CG, FIRE or the mass-weighted approach then FIRE, chosen from the
  !> body), GFMD_SOLVER_FIRE, GFMD_SOLVER_CG (adhesive only under pressure control), GFMD_SOLVER_MASS_WEIGHTED_FIRE (mass-weighted
  !> FIRE), GFMD_SOLVER_APPROACH_THEN_FIRE (at most 100 mass-weighted steps, then FIRE), GFMD_SOLVER_NEWTON
  !> (the active-set Newton method: thin sheets on a fluid foundation, with adhesion in a trust
  !> region, square power-of-2 grids) or GFMD_SOLVER_VERLET.
  subroutine sim_set_solver(self, solver, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(in) :: solver
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_solver(self%ptr, int(solver, c_int32_t)), 'set_solver', stat, errmsg)
  end subroutine sim_set_solver

  subroutine sim_get_dynamics(self, dt, eta, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out), optional :: dt, eta
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double) :: a, b
    integer(c_int32_t) :: st
    st = c_gfmd_get_dynamics(self%ptr, a, b)
    if (st == GFMD_OK) then
      if (present(dt)) dt = a
      if (present(eta)) eta = b
    end if
    call finish(self%ptr, st, 'get_dynamics', stat, errmsg)
  end subroutine sim_get_dynamics

  subroutine sim_step(self, nsteps, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(in) :: nsteps
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_step(self%ptr, int(nsteps, c_int64_t)), 'step', stat, errmsg)
  end subroutine sim_step

  !> Relax to the relative residual tol (default GFMD_DEFAULT_TOL) in at most max_steps
  !> (default 1000000) steps; steps receives the steps made (also when not converged).
  subroutine sim_relax(self, tol, max_steps, steps, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in), optional :: tol
    integer, intent(in), optional :: max_steps
    integer, intent(out), optional :: steps
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double) :: t
    integer(c_int64_t) :: m, taken
    integer(c_int32_t) :: st
    t = 0.0_dp
    if (present(tol)) t = tol
    m = 1000000_c_int64_t
    if (present(max_steps)) m = int(max_steps, c_int64_t)
    taken = 0
    st = c_gfmd_relax(self%ptr, t, m, taken)
    if (present(steps)) steps = int(taken)
    call finish(self%ptr, st, 'relax', stat, errmsg)
  end subroutine sim_relax

  !> gfmd_relax_multilevel: relax from a start made on grids coarsened levels - 1 times by 2.
  subroutine sim_relax_multilevel(self, levels, tol, max_steps, steps, coarse_steps, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(in) :: levels
    real(dp), intent(in), optional :: tol
    integer, intent(in), optional :: max_steps
    integer, intent(out), optional :: steps, coarse_steps
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double) :: t
    integer(c_int64_t) :: m, taken, below
    integer(c_int32_t) :: st
    t = 0.0_dp
    if (present(tol)) t = tol
    m = 1000000_c_int64_t
    if (present(max_steps)) m = int(max_steps, c_int64_t)
    taken = 0
    below = 0
    st = c_gfmd_relax_multilevel(self%ptr, t, m, int(levels, c_int32_t), taken, below)
    if (present(steps)) steps = int(taken)
    if (present(coarse_steps)) coarse_steps = int(below)
    call finish(self%ptr, st, 'relax_multilevel', stat, errmsg)
  end subroutine sim_relax_multilevel

  subroutine sim_get_residual(self, residual, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out) :: residual
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_get_residual(self%ptr, residual), 'get_residual', stat, errmsg)
  end subroutine sim_get_residual

  subroutine sim_reset(self, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_reset(self%ptr), 'reset', stat, errmsg)
  end subroutine sim_reset

  !> Restart the solver's adaptive state (gfmd_restart_solver()); relax and step otherwise continue
  !> the trajectory of the last call.
  subroutine sim_restart_solver(self, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_restart_solver(self%ptr), 'restart_solver', stat, errmsg)
  end subroutine sim_restart_solver

  ! ------------------------------------------------------------------ observables

  subroutine sim_get_contact_area(self, rel_area, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out) :: rel_area
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_get_contact_area(self%ptr, rel_area), 'get_contact_area', stat, errmsg)
  end subroutine sim_get_contact_area

  !> Persson's full-contact pressure variance V with this handle's substrate and body.
  subroutine sim_persson_variance(self, variance, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out) :: variance
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_persson_variance(self%ptr, variance), 'persson_variance', stat, errmsg)
  end subroutine sim_persson_variance

  !> Persson's A/A0 = erf(sigma0/sqrt(2 V)) at the load sigma0 (not the handle's own).
  subroutine sim_persson_contact_area(self, sigma0, rel_area, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(in) :: sigma0
    real(dp), intent(out) :: rel_area
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_persson_contact_area(self%ptr, sigma0, rel_area), 'persson_contact_area', &
                stat, errmsg)
  end subroutine sim_persson_contact_area

  !> The load sigma0 at which Persson's A/A0 is rel_area (the inverse of persson_contact_area).
  subroutine sim_persson_load(self, rel_area, sigma0, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(in) :: rel_area
    real(dp), intent(out) :: sigma0
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_persson_load(self%ptr, rel_area, sigma0), 'persson_load', stat, errmsg)
  end subroutine sim_persson_load

  subroutine sim_get_mean_gap(self, mean_gap, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out) :: mean_gap
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_get_mean_gap(self%ptr, mean_gap), 'get_mean_gap', stat, errmsg)
  end subroutine sim_get_mean_gap

  subroutine sim_get_energies(self, elastic, adhesive, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out), optional :: elastic, adhesive
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double) :: e, a
    integer(c_int32_t) :: st
    st = c_gfmd_get_energies(self%ptr, e, a)
    if (st == GFMD_OK) then
      if (present(elastic)) elastic = e
      if (present(adhesive)) adhesive = a
    end if
    call finish(self%ptr, st, 'get_energies', stat, errmsg)
  end subroutine sim_get_energies

  subroutine sim_get_gap(self, gap, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(inout), contiguous :: gap(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    if (.not. shape_ok(self, gap, 'get_gap', stat, errmsg)) return
    call finish(self%ptr, c_gfmd_get_gap(self%ptr, gap), 'get_gap', stat, errmsg)
  end subroutine sim_get_gap

  subroutine sim_get_surface(self, z, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(inout), contiguous :: z(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    if (.not. shape_ok(self, z, 'get_surface', stat, errmsg)) return
    call finish(self%ptr, c_gfmd_get_surface(self%ptr, z), 'get_surface', stat, errmsg)
  end subroutine sim_get_surface

  subroutine sim_get_pressure(self, p, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(inout), contiguous :: p(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    if (.not. shape_ok(self, p, 'get_pressure', stat, errmsg)) return
    call finish(self%ptr, c_gfmd_get_pressure(self%ptr, p), 'get_pressure', stat, errmsg)
  end subroutine sim_get_pressure

  ! ------------------------------------------------------------------ plasticity

  !> Perfect plasticity at hardness H (gfmd_set_hardness); ieee +infinity switches it off.
  subroutine sim_set_hardness(self, hardness, stat, errmsg)
    class(gfmd_sim_t), intent(inout) :: self
    real(dp), intent(in) :: hardness
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_set_hardness(self%ptr, hardness), 'set_hardness', stat, errmsg)
  end subroutine sim_set_hardness

  subroutine sim_get_hardness(self, hardness, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out) :: hardness
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call finish(self%ptr, c_gfmd_get_hardness(self%ptr, hardness), 'get_hardness', stat, errmsg)
  end subroutine sim_get_hardness

  !> The fraction of the points yielding now and the volume the substrate lost (gfmd_get_plasticity).
  subroutine sim_get_plasticity(self, plastic_area, plastic_volume, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out), optional :: plastic_area, plastic_volume
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double) :: a, v
    integer(c_int32_t) :: st
    st = c_gfmd_get_plasticity(self%ptr, a, v)
    if (st == GFMD_OK) then
      if (present(plastic_area)) plastic_area = a
      if (present(plastic_volume)) plastic_volume = v
    end if
    call finish(self%ptr, st, 'get_plasticity', stat, errmsg)
  end subroutine sim_get_plasticity

  ! ------------------------------------------------------------------ how the contact is made

  !> Connected-component labels of mask(nx, ny) (gfmd_label_patches): labels 0 outside, 1..npatches
  !> in the order of each patch's first point (x fastest); connectivity 4 (default) or 8; periodic
  !> (default .true.) wraps the grid.
  subroutine gfmd_label_patches(mask, labels, npatches, connectivity, periodic, stat, errmsg)
    logical, intent(in) :: mask(:, :)
    integer, intent(out) :: labels(:, :)
    integer, intent(out) :: npatches
    integer, intent(in), optional :: connectivity
    logical, intent(in), optional :: periodic
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t), allocatable :: m(:, :)
    integer(c_int64_t), allocatable :: lab(:, :)
    integer(c_int64_t) :: n
    integer(c_int32_t) :: st, conn, per
    conn = 4
    if (present(connectivity)) conn = int(connectivity, c_int32_t)
    per = 1
    if (present(periodic)) then
      if (.not. periodic) per = 0
    end if
    npatches = 0
    if (any(shape(labels) /= shape(mask))) then
      call finish(c_null_ptr, int(GFMD_ERR_INVALID_ARG, c_int32_t), 'label_patches', stat, errmsg, &
                  'labels must have the shape of mask')
      return
    end if
    allocate (m(size(mask, 1), size(mask, 2)), lab(size(mask, 1), size(mask, 2)))
    m = merge(1_c_int32_t, 0_c_int32_t, mask)
    st = c_gfmd_label_patches(size(mask, 1, kind=c_int64_t), size(mask, 2, kind=c_int64_t), m, conn, per, lab, n)
    if (st == GFMD_OK) then
      labels = int(lab)
      npatches = int(n)
    end if
    call finish(c_null_ptr, st, 'label_patches', stat, errmsg)
  end subroutine gfmd_label_patches

  !> The contact patches (gfmd_get_contact_patches): labels(nx, ny) and their number.
  subroutine sim_get_contact_patches(self, labels, npatches, connectivity, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    integer, intent(out) :: labels(:, :)
    integer, intent(out) :: npatches
    integer, intent(in), optional :: connectivity
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int64_t), allocatable :: lab(:, :)
    integer(c_int64_t) :: n
    integer(c_int32_t) :: st, conn
    conn = 4
    if (present(connectivity)) conn = int(connectivity, c_int32_t)
    npatches = 0
    if (.not. dims_ok(self, size(labels, 1, kind=c_int64_t), size(labels, 2, kind=c_int64_t), &
                      'get_contact_patches', stat, errmsg)) return
    allocate (lab(size(labels, 1), size(labels, 2)))
    st = c_gfmd_get_contact_patches(self%ptr, conn, lab, n)
    if (st == GFMD_OK) then
      labels = int(lab)
      npatches = int(n)
    end if
    call finish(self%ptr, st, 'get_contact_patches', stat, errmsg)
  end subroutine sim_get_contact_patches

  !> One property (GFMD_PATCH_*) of every contact patch, in label order, into values (allocated
  !> to the number of patches).
  subroutine sim_get_patch_property(self, property, values, connectivity, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    integer, intent(in) :: property
    real(dp), allocatable, intent(out) :: values(:)
    integer, intent(in), optional :: connectivity
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int64_t) :: n
    integer(c_int32_t) :: st, conn
    real(c_double) :: none(1)
    n = 0
    conn = 4
    if (present(connectivity)) conn = int(connectivity, c_int32_t)
    st = c_gfmd_get_patch_property(self%ptr, conn, int(property, c_int32_t), 0_c_int64_t, none, n)
    if (st == GFMD_OK .or. st == GFMD_ERR_TRUNCATED) then
      allocate (values(n))
      st = c_gfmd_get_patch_property(self%ptr, conn, int(property, c_int32_t), n, values, n)
    end if
    if (.not. allocated(values)) allocate (values(0))
    call finish(self%ptr, st, 'get_patch_property', stat, errmsg)
  end subroutine sim_get_patch_property

  !> The contact pressures binned into size(fraction) bins (gfmd_get_pressure_histogram); range
  !> (in: [lo, hi], or absent / [0, 0] for the contact's own; out: the range used).
  subroutine sim_get_pressure_histogram(self, fraction, mean, range, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(out) :: fraction(:), mean(:)
    real(dp), intent(inout), optional :: range(2)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double) :: r(2)
    real(c_double), allocatable :: f(:), m(:)
    integer(c_int32_t) :: st
    r = 0.0_dp
    if (present(range)) r = range
    if (size(mean) /= size(fraction)) then
      call finish(self%ptr, int(GFMD_ERR_INVALID_ARG, c_int32_t), 'get_pressure_histogram', stat, errmsg, &
                  'fraction and mean must have the same size')
      return
    end if
    allocate (f(max(size(fraction), 1)), m(max(size(fraction), 1)))
    st = c_gfmd_get_pressure_histogram(self%ptr, size(fraction, kind=c_int64_t), r, f, m)
    if (st == GFMD_OK) then
      fraction = f(1:size(fraction))
      mean = m(1:size(fraction))
      if (present(range)) range = r
    end if
    call finish(self%ptr, st, 'get_pressure_histogram', stat, errmsg)
  end subroutine sim_get_pressure_histogram

  !> Persson's P(p) at the load sigma0, at the pressures p (gfmd_persson_pressure_distribution).
  subroutine sim_persson_pressure_distribution(self, sigma0, p, density, stat, errmsg)
    class(gfmd_sim_t), intent(in) :: self
    real(dp), intent(in) :: sigma0
    real(dp), intent(in) :: p(:)
    real(dp), intent(out) :: density(:)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    real(c_double), allocatable :: d(:), q(:)
    integer(c_int32_t) :: st
    if (size(density) /= size(p)) then
      call finish(self%ptr, int(GFMD_ERR_INVALID_ARG, c_int32_t), 'persson_pressure_distribution', stat, errmsg, &
                  'p and density must have the same size')
      return
    end if
    allocate (q(max(size(p), 1)), d(max(size(p), 1)))
    q = 0.0_dp
    q(1:size(p)) = p
    st = c_gfmd_persson_pressure_distribution(self%ptr, sigma0, size(p, kind=c_int64_t), q, d)
    if (st == GFMD_OK) density = d(1:size(p))
    call finish(self%ptr, st, 'persson_pressure_distribution', stat, errmsg)
  end subroutine sim_persson_pressure_distribution

  !> The library's message of the last failure on this simulation.
  function sim_last_error(self) result(msg)
    class(gfmd_sim_t), intent(in) :: self
    character(:), allocatable :: msg
    msg = handle_message(self%ptr)
  end function sim_last_error

  !> Make `sim` the owner of a C handle made elsewhere (the module gfmd_mpi's distributed
  !> handles); its previous simulation is freed.  Not type-bound: the type's layout stays.
  subroutine gfmd_sim_adopt(sim, handle)
    type(gfmd_sim_t), intent(inout) :: sim
    type(c_ptr), intent(in) :: handle
    if (c_associated(sim%ptr, handle)) return
    call c_gfmd_sim_destroy(sim%ptr)
    sim%ptr = handle
  end subroutine gfmd_sim_adopt

  !> The C handle of `sim` (c_null_ptr before create), for calls of the C API from Fortran.
  function gfmd_sim_c_handle(sim) result(handle)
    type(gfmd_sim_t), intent(in) :: sim
    type(c_ptr) :: handle
    handle = sim%ptr
  end function gfmd_sim_c_handle

  ! ------------------------------------------------------------------ measured topographies

  !> The topography's message of its last failure.
  function topo_message(p) result(msg)
    type(c_ptr), intent(in) :: p
    character(:), allocatable :: msg
    character(kind=c_char) :: buf(512)
    buf = char(0)
    msg = ''
    if (.not. c_associated(p)) then
      msg = 'the topography has not been made (call read or from_heights first)'
      return
    end if
    if (c_gfmd_topo_last_error(p, buf, int(size(buf), c_int64_t)) < 0) return
    msg = buffer_text(buf)
  end function topo_message

  subroutine topo_finish(self, st, where, stat, errmsg)
    class(gfmd_topo_t), intent(in) :: self
    integer(c_int32_t), intent(in) :: st
    character(*), intent(in) :: where
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    if (st == GFMD_OK) then
      call finish(c_null_ptr, st, where, stat, errmsg)
    else
      call finish(c_null_ptr, st, where, stat, errmsg, topo_message(self%ptr))
    end if
  end subroutine topo_finish

  !> Read a topography file (format GFMD_TOPO_AUTO by default: detected), lengths converted to
  !> the caller's unit, `unit` metres long (default 1: metres) where the file has units.
  subroutine topo_read(self, path, unit, format, stat, errmsg)
    class(gfmd_topo_t), intent(inout) :: self
    character(*), intent(in) :: path
    real(dp), intent(in), optional :: unit
    integer, intent(in), optional :: format
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    type(c_ptr) :: p
    integer(c_int32_t) :: st, f
    real(c_double) :: u
    character(kind=c_char) :: buf(512)
    buf = char(0)
    u = 1.0_dp
    if (present(unit)) u = unit
    f = GFMD_TOPO_AUTO
    if (present(format)) f = int(format, c_int32_t)
    st = c_gfmd_topo_read(c_path(path), f, u, p, buf, int(size(buf), c_int64_t))
    if (st == GFMD_OK) then
      call c_gfmd_topo_destroy(self%ptr)
      self%ptr = p
    end if
    call finish(c_null_ptr, st, 'topo%read', stat, errmsg, buffer_text(buf))
  end subroutine topo_read

  !> A topography of h(nx, ny) (NaN at missing points) on lx x ly.
  subroutine topo_from_heights(self, h, lx, ly, stat, errmsg)
    class(gfmd_topo_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: h(:, :)
    real(dp), intent(in) :: lx, ly
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    type(c_ptr) :: p
    integer(c_int32_t) :: st
    st = c_gfmd_topo_from_heights(size(h, 1, kind=c_int64_t), size(h, 2, kind=c_int64_t), lx, ly, h, p)
    if (st == GFMD_OK) then
      call c_gfmd_topo_destroy(self%ptr)
      self%ptr = p
    end if
    call finish(c_null_ptr, st, 'topo%from_heights', stat, errmsg)
  end subroutine topo_from_heights

  !> The C handle (for calls of the C API beside the module's); the object still owns it.
  function gfmd_topo_c_handle(topo) result(handle)
    type(gfmd_topo_t), intent(in) :: topo
    type(c_ptr) :: handle
    handle = topo%ptr
  end function gfmd_topo_c_handle

  subroutine topo_destroy(self)
    class(gfmd_topo_t), intent(inout) :: self
    call c_gfmd_topo_destroy(self%ptr)
  end subroutine topo_destroy

  subroutine topo_final(self)
    type(gfmd_topo_t), intent(inout) :: self
    call c_gfmd_topo_destroy(self%ptr)
  end subroutine topo_final

  subroutine topo_get_grid(self, nx, ny, lx, ly, stat, errmsg)
    class(gfmd_topo_t), intent(in) :: self
    integer, intent(out) :: nx, ny
    real(dp), intent(out) :: lx, ly
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int64_t) :: gx, gy
    integer(c_int32_t) :: st
    gx = 0
    gy = 0
    lx = 0
    ly = 0
    st = c_gfmd_topo_get_grid(self%ptr, gx, gy, lx, ly)
    nx = int(gx)
    ny = int(gy)
    call topo_finish(self, st, 'topo%get_grid', stat, errmsg)
  end subroutine topo_get_grid

  !> format (GFMD_TOPO_*), has_units (the file gave physical units), missing (NaN points).
  subroutine topo_get_info(self, format, has_units, missing, stat, errmsg)
    class(gfmd_topo_t), intent(in) :: self
    integer, intent(out) :: format
    logical, intent(out) :: has_units
    integer, intent(out) :: missing
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: f, u, st
    integer(c_int64_t) :: m
    f = 0
    u = 0
    m = 0
    st = c_gfmd_topo_get_info(self%ptr, f, u, m)
    format = int(f)
    has_units = u /= 0
    missing = int(m)
    call topo_finish(self, st, 'topo%get_info', stat, errmsg)
  end subroutine topo_get_info

  subroutine topo_set_physical_size(self, lx, ly, stat, errmsg)
    class(gfmd_topo_t), intent(inout) :: self
    real(dp), intent(in) :: lx, ly
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call topo_finish(self, c_gfmd_topo_set_physical_size(self%ptr, lx, ly), 'topo%set_physical_size', stat, errmsg)
  end subroutine topo_set_physical_size

  !> h(nx, ny): the heights, NaN at missing points.
  subroutine topo_get_heights(self, h, stat, errmsg)
    class(gfmd_topo_t), intent(in) :: self
    real(dp), intent(inout), contiguous :: h(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer :: nx, ny, st
    real(dp) :: lx, ly
    call topo_get_grid(self, nx, ny, lx, ly, st)
    if (st == GFMD_OK .and. (size(h, 1) /= nx .or. size(h, 2) /= ny)) then
      call finish(c_null_ptr, int(GFMD_ERR_INVALID_ARG, c_int32_t), 'topo%get_heights', stat, errmsg, &
                  'h must have the shape (nx, ny) of the topography')
      return
    end if
    call topo_finish(self, c_gfmd_topo_get_heights(self%ptr, h), 'topo%get_heights', stat, errmsg)
  end subroutine topo_get_heights

  !> GFMD_FILL_LAPLACE (default) or GFMD_FILL_NEAREST.
  subroutine topo_fill_missing(self, method, stat, errmsg)
    class(gfmd_topo_t), intent(inout) :: self
    integer, intent(in), optional :: method
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: m
    m = GFMD_FILL_LAPLACE
    if (present(method)) m = int(method, c_int32_t)
    call topo_finish(self, c_gfmd_topo_fill_missing(self%ptr, m), 'topo%fill_missing', stat, errmsg)
  end subroutine topo_fill_missing

  !> GFMD_DETREND_HEIGHT, _PLANE (default) or _CURVATURE.
  subroutine topo_detrend(self, mode, stat, errmsg)
    class(gfmd_topo_t), intent(inout) :: self
    integer, intent(in), optional :: mode
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: m
    m = GFMD_DETREND_PLANE
    if (present(mode)) m = int(mode, c_int32_t)
    call topo_finish(self, c_gfmd_topo_detrend(self%ptr, m), 'topo%detrend', stat, errmsg)
  end subroutine topo_detrend

  !> Resample onto nx x ny points (Keys' cubic convolution; gfmd_topo_resample).
  subroutine topo_resample(self, nx, ny, stat, errmsg)
    class(gfmd_topo_t), intent(inout) :: self
    integer, intent(in) :: nx, ny
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call topo_finish(self, c_gfmd_topo_resample(self%ptr, int(nx, c_int64_t), int(ny, c_int64_t)), 'topo%resample', &
                     stat, errmsg)
  end subroutine topo_resample

  !> The radially averaged PSD over size(q) log-spaced bins (gfmd_topo_psd); count optional.
  subroutine topo_psd(self, q, c, count, window, stat, errmsg)
    class(gfmd_topo_t), intent(in) :: self
    real(dp), intent(inout), contiguous :: q(:), c(:)
    integer, intent(out), optional :: count(:)
    integer, intent(in), optional :: window
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int64_t), allocatable :: n(:)
    integer(c_int32_t) :: w, st
    w = GFMD_WINDOW_NONE
    if (present(window)) w = int(window, c_int32_t)
    if (size(c) /= size(q)) then
      call finish(c_null_ptr, int(GFMD_ERR_INVALID_ARG, c_int32_t), 'topo%psd', stat, errmsg, &
                  'q and c must have one size, the number of bins')
      return
    end if
    allocate (n(size(q)))
    st = c_gfmd_topo_psd(self%ptr, w, size(q, kind=c_int64_t), q, c, n)
    if (st == GFMD_OK .and. present(count)) count = int(n)
    call topo_finish(self, st, 'topo%psd', stat, errmsg)
  end subroutine topo_psd

  !> The profiles' PSD along x: q(0:nx/2), c(0:nx/2) allocated here.
  subroutine topo_profile_psd(self, q, c, window, stat, errmsg)
    class(gfmd_topo_t), intent(in) :: self
    real(dp), allocatable, intent(out) :: q(:), c(:)
    integer, intent(in), optional :: window
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: w, st
    integer(c_int64_t) :: n
    integer :: nx, ny
    real(dp) :: lx, ly
    n = 0
    w = GFMD_WINDOW_NONE
    if (present(window)) w = int(window, c_int32_t)
    call topo_get_grid(self, nx, ny, lx, ly, st)
    allocate (q(0:max(nx / 2, 0)), c(0:max(nx / 2, 0)))
    q = 0
    c = 0
    st = c_gfmd_topo_profile_psd(self%ptr, w, size(q, kind=c_int64_t), q, c, n)
    call topo_finish(self, st, 'topo%profile_psd', stat, errmsg)
  end subroutine topo_profile_psd

  !> rms height, slope and curvature from the spectrum (gfmd_topo_moments).
  subroutine topo_moments(self, rms_height, rms_slope, rms_curvature, window, stat, errmsg)
    class(gfmd_topo_t), intent(in) :: self
    real(dp), intent(out) :: rms_height, rms_slope, rms_curvature
    integer, intent(in), optional :: window
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: w
    w = GFMD_WINDOW_NONE
    if (present(window)) w = int(window, c_int32_t)
    rms_height = 0
    rms_slope = 0
    rms_curvature = 0
    call topo_finish(self, c_gfmd_topo_moments(self%ptr, w, rms_height, rms_slope, rms_curvature), 'topo%moments', &
                     stat, errmsg)
  end subroutine topo_moments

  !> Persson's A/A0 at sigma0 from the topography's spectrum on a body (default: a half-space,
  !> E* = 1); variance optional.
  !> The body and window of Persson's theory of a topography, the optional arguments defaulted:
  !> a half-space, E* = 1, no window.
  subroutine body_arguments(kind, width, nu, e_star, window, k, wd, n, e, w)
    integer, intent(in), optional :: kind, window
    real(dp), intent(in), optional :: width, nu, e_star
    integer(c_int32_t), intent(out) :: k, w
    real(c_double), intent(out) :: wd, n, e
    k = GFMD_GREEN_HALFSPACE
    if (present(kind)) k = int(kind, c_int32_t)
    w = GFMD_WINDOW_NONE
    if (present(window)) w = int(window, c_int32_t)
    wd = 0
    if (present(width)) wd = width
    n = 0
    if (present(nu)) n = nu
    e = 1
    if (present(e_star)) e = e_star
  end subroutine body_arguments

  subroutine topo_persson_contact_area(self, sigma0, area, kind, width, nu, e_star, window, variance, stat, errmsg)
    class(gfmd_topo_t), intent(in) :: self
    real(dp), intent(in) :: sigma0
    real(dp), intent(out) :: area
    integer, intent(in), optional :: kind, window
    real(dp), intent(in), optional :: width, nu, e_star
    real(dp), intent(out), optional :: variance
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: k, w
    real(c_double) :: wd, n, e, v
    call body_arguments(kind, width, nu, e_star, window, k, wd, n, e, w)
    area = 0
    v = 0
    call topo_finish(self, c_gfmd_topo_persson_contact_area(self%ptr, w, k, wd, n, e, sigma0, area, v), &
                     'topo%persson_contact_area', stat, errmsg)
    if (present(variance)) variance = v
  end subroutine topo_persson_contact_area

  !> Whether this build reads files of a format (GFMD_TOPO_*; x3p needs libzip and libxml2).
  logical function gfmd_topo_format_supported(format)
    integer, intent(in) :: format
    gfmd_topo_format_supported = c_gfmd_topo_format_supported(int(format, c_int32_t)) == 1
  end function gfmd_topo_format_supported

  !> Persson's mean gap at sigma0 > 0 (gfmd_topo_persson_mean_gap; gamma default 0.45).
  subroutine topo_persson_mean_gap(self, sigma0, mean_gap, kind, width, nu, e_star, window, gamma, stat, errmsg)
    class(gfmd_topo_t), intent(in) :: self
    real(dp), intent(in) :: sigma0
    real(dp), intent(out) :: mean_gap
    integer, intent(in), optional :: kind, window
    real(dp), intent(in), optional :: width, nu, e_star, gamma
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: k, w
    real(c_double) :: wd, n, e, g
    call body_arguments(kind, width, nu, e_star, window, k, wd, n, e, w)
    g = 0.45_dp
    if (present(gamma)) g = gamma
    mean_gap = 0
    call topo_finish(self, c_gfmd_topo_persson_mean_gap(self%ptr, w, k, wd, n, e, sigma0, g, mean_gap), &
                     'topo%persson_mean_gap', stat, errmsg)
  end subroutine topo_persson_mean_gap

end module gfmd
