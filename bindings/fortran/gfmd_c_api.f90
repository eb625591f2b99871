!> Raw bind(C) interfaces to every function of the gfmd C API (gfmd.h), one to one.
!> Users call the module `gfmd` instead; this layer only states the C prototypes in Fortran.
module gfmd_c_api
  use, intrinsic :: iso_c_binding, only: c_ptr, c_int32_t, c_int64_t, c_double, c_char, c_size_t
  implicit none
  private
  public :: c_gfmd_version, c_gfmd_status_string, c_gfmd_last_error, c_gfmd_last_error_length
  public :: c_gfmd_sim_create, c_gfmd_sim_create_ex, c_gfmd_restart_solver, c_gfmd_sim_clone, c_gfmd_sim_destroy, c_gfmd_get_grid
  public :: c_gfmd_set_modulus, c_gfmd_set_green, c_gfmd_set_poisson, c_gfmd_green_factor
  public :: c_gfmd_set_heights, c_gfmd_get_heights, c_gfmd_generate_selfaffine
  public :: c_gfmd_set_mean_displacement, c_gfmd_get_mean_displacement, c_gfmd_get_mean_pressure
  public :: c_gfmd_set_pressure, c_gfmd_set_adhesion, c_gfmd_set_timestep, c_gfmd_set_damping
  public :: c_gfmd_set_solver, c_gfmd_get_dynamics, c_gfmd_step, c_gfmd_relax, c_gfmd_get_residual, &
    c_gfmd_relax_multilevel
  public :: c_gfmd_reset, c_gfmd_get_contact_area, c_gfmd_get_mean_gap, c_gfmd_get_energies
  public :: c_gfmd_get_gap, c_gfmd_get_surface, c_gfmd_get_pressure, c_strlen
  public :: c_gfmd_sim_save, c_gfmd_sim_load, c_gfmd_set_threads, c_gfmd_get_threads, &
    c_gfmd_get_solver, c_gfmd_set_boundary, c_gfmd_get_boundary
  public :: c_gfmd_set_fft_planner, c_gfmd_import_wisdom, c_gfmd_export_wisdom
  public :: c_gfmd_persson_variance, c_gfmd_persson_contact_area, c_gfmd_persson_load, c_gfmd_least_squares
  public :: c_gfmd_set_hardness, c_gfmd_get_hardness, c_gfmd_get_plasticity
  public :: c_gfmd_label_patches, c_gfmd_get_contact_patches, c_gfmd_get_patch_property
  public :: c_gfmd_topo_read, c_gfmd_topo_from_heights, c_gfmd_topo_destroy, c_gfmd_topo_last_error, &
            c_gfmd_topo_get_grid, c_gfmd_topo_get_info, c_gfmd_topo_set_physical_size, c_gfmd_topo_get_heights, &
            c_gfmd_topo_fill_missing, c_gfmd_topo_detrend, c_gfmd_topo_resample, c_gfmd_topo_psd, c_gfmd_topo_profile_psd, &
            c_gfmd_topo_moments, c_gfmd_topo_persson_mean_gap, c_gfmd_topo_format_supported, c_gfmd_topo_persson_contact_area
  public :: c_gfmd_get_pressure_histogram, c_gfmd_persson_pressure_distribution

  interface
    ! const char *gfmd_version(void);
    function c_gfmd_version() bind(C, name="gfmd_version") result(r)
      import :: c_ptr
      type(c_ptr) :: r
    end function

    ! const char *gfmd_status_string(int32_t status);
    function c_gfmd_status_string(status) bind(C, name="gfmd_status_string") result(r)
      import :: c_ptr, c_int32_t
      integer(c_int32_t), value :: status
      type(c_ptr) :: r
    end function

    ! int32_t gfmd_last_error(const gfmd_sim *s, char *buf, int64_t len);
    function c_gfmd_last_error(s, buf, len) bind(C, name="gfmd_last_error") result(r)
      import :: c_ptr, c_char, c_int32_t, c_int64_t
      type(c_ptr), value :: s
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_int64_t), value :: len
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_last_error_length(const gfmd_sim *s, int64_t *needed);
    function c_gfmd_last_error_length(s, needed) bind(C, name="gfmd_last_error_length") result(r)
      import :: c_ptr, c_int32_t, c_int64_t
      type(c_ptr), value :: s
      integer(c_int64_t), intent(out) :: needed
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_sim_create(int64_t nx, int64_t ny, double lx, double ly, gfmd_sim **out);
    function c_gfmd_sim_create(nx, ny, lx, ly, out) bind(C, name="gfmd_sim_create") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      integer(c_int64_t), value :: nx, ny
      real(c_double), value :: lx, ly
      type(c_ptr), intent(out) :: out
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_sim_clone(const gfmd_sim *s, gfmd_sim **out);
    function c_gfmd_sim_clone(s, out) bind(C, name="gfmd_sim_clone") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      type(c_ptr), intent(out) :: out
      integer(c_int32_t) :: r
    end function

    ! void gfmd_sim_destroy(gfmd_sim **sim);
    subroutine c_gfmd_sim_destroy(sim) bind(C, name="gfmd_sim_destroy")
      import :: c_ptr
      type(c_ptr), intent(inout) :: sim
    end subroutine

    ! int32_t gfmd_get_grid(const gfmd_sim *s, int64_t *nx, int64_t *ny, double *lx, double *ly);
    function c_gfmd_get_grid(s, nx, ny, lx, ly) bind(C, name="gfmd_get_grid") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: s
      integer(c_int64_t), intent(out) :: nx, ny
      real(c_double), intent(out) :: lx, ly
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_modulus(gfmd_sim *s, double e_star);
    function c_gfmd_set_modulus(s, e_star) bind(C, name="gfmd_set_modulus") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: e_star
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_green(gfmd_sim *s, int32_t kind, double width);
    function c_gfmd_set_green(s, kind, width) bind(C, name="gfmd_set_green") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      integer(c_int32_t), value :: kind
      real(c_double), value :: width
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_poisson(gfmd_sim *s, double nu);
    function c_gfmd_set_poisson(s, nu) bind(C, name="gfmd_set_poisson") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: nu
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_green_factor(int32_t kind, double t, double nu, double *f);
    function c_gfmd_green_factor(kind, t, nu, f) bind(C, name="gfmd_green_factor") result(r)
      import :: c_int32_t, c_double
      integer(c_int32_t), value :: kind
      real(c_double), value :: t, nu
      real(c_double), intent(out) :: f
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_heights(gfmd_sim *s, const double *h);
    function c_gfmd_set_heights(s, h) bind(C, name="gfmd_set_heights") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(in) :: h(*)
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_heights(const gfmd_sim *s, double *h);
    function c_gfmd_get_heights(s, h) bind(C, name="gfmd_get_heights") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(inout) :: h(*)
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_generate_selfaffine(gfmd_sim *s, double hurst, double lambda_r, double lambda_s,
    !                                  double rms_gradient, uint64_t seed, int32_t distribution);
    function c_gfmd_generate_selfaffine(s, hurst, lambda_r, lambda_s, rms_gradient, seed, distribution) &
        bind(C, name="gfmd_generate_selfaffine") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: hurst, lambda_r, lambda_s, rms_gradient
      integer(c_int64_t), value :: seed  ! uint64_t: same bits for seeds >= 0
      integer(c_int32_t), value :: distribution
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_mean_displacement(gfmd_sim *s, double d);
    function c_gfmd_set_mean_displacement(s, d) bind(C, name="gfmd_set_mean_displacement") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: d
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_mean_displacement(const gfmd_sim *s, double *d);
    function c_gfmd_get_mean_displacement(s, d) bind(C, name="gfmd_get_mean_displacement") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: d
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_mean_pressure(const gfmd_sim *s, double *p);
    function c_gfmd_get_mean_pressure(s, p) bind(C, name="gfmd_get_mean_pressure") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: p
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_pressure(gfmd_sim *s, double sigma0);
    function c_gfmd_set_pressure(s, sigma0) bind(C, name="gfmd_set_pressure") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: sigma0
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_adhesion(gfmd_sim *s, double gamma0, double rho);
    function c_gfmd_set_adhesion(s, gamma0, rho) bind(C, name="gfmd_set_adhesion") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: gamma0, rho
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_timestep(gfmd_sim *s, double dt);
    function c_gfmd_set_timestep(s, dt) bind(C, name="gfmd_set_timestep") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: dt
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_damping(gfmd_sim *s, double eta);
    function c_gfmd_set_damping(s, eta) bind(C, name="gfmd_set_damping") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: eta
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_solver(gfmd_sim *s, int32_t solver);
    function c_gfmd_set_solver(s, solver) bind(C, name="gfmd_set_solver") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t), value :: solver
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_dynamics(const gfmd_sim *s, double *dt, double *eta);
    function c_gfmd_get_dynamics(s, dt, eta) bind(C, name="gfmd_get_dynamics") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: dt, eta
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_step(gfmd_sim *s, int64_t nsteps);
    function c_gfmd_step(s, nsteps) bind(C, name="gfmd_step") result(r)
      import :: c_ptr, c_int32_t, c_int64_t
      type(c_ptr), value :: s
      integer(c_int64_t), value :: nsteps
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_relax(gfmd_sim *s, double tol, int64_t max_steps, int64_t *steps_taken);
    function c_gfmd_relax_multilevel(s, tol, max_steps, levels, steps_taken, coarse_steps) &
        bind(C, name="gfmd_relax_multilevel") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: tol
      integer(c_int64_t), value :: max_steps
      integer(c_int32_t), value :: levels
      integer(c_int64_t), intent(out) :: steps_taken, coarse_steps
      integer(c_int32_t) :: r
    end function

    function c_gfmd_relax(s, tol, max_steps, steps_taken) bind(C, name="gfmd_relax") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: tol
      integer(c_int64_t), value :: max_steps
      integer(c_int64_t), intent(out) :: steps_taken
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_residual(const gfmd_sim *s, double *residual);
    function c_gfmd_get_residual(s, residual) bind(C, name="gfmd_get_residual") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: residual
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_sim_create_ex(int64_t nx, int64_t ny, double lx, double ly, int32_t nthreads,
    !                            int32_t planner, gfmd_sim **out);
    function c_gfmd_sim_create_ex(nx, ny, lx, ly, nthreads, planner, out) bind(C, name="gfmd_sim_create_ex") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      integer(c_int64_t), value :: nx, ny
      real(c_double), value :: lx, ly
      integer(c_int32_t), value :: nthreads, planner
      type(c_ptr), intent(out) :: out
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_restart_solver(gfmd_sim *s);
    function c_gfmd_restart_solver(s) bind(C, name="gfmd_restart_solver") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_reset(gfmd_sim *s);
    function c_gfmd_reset(s) bind(C, name="gfmd_reset") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_contact_area(const gfmd_sim *s, double *rel_area);
    function c_gfmd_get_contact_area(s, rel_area) bind(C, name="gfmd_get_contact_area") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: rel_area
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_mean_gap(const gfmd_sim *s, double *mean_gap);
    function c_gfmd_get_mean_gap(s, mean_gap) bind(C, name="gfmd_get_mean_gap") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: mean_gap
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_energies(const gfmd_sim *s, double *elastic, double *adhesive);
    function c_gfmd_get_energies(s, elastic, adhesive) bind(C, name="gfmd_get_energies") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: elastic, adhesive
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_gap(const gfmd_sim *s, double *gap);
    function c_gfmd_get_gap(s, gap) bind(C, name="gfmd_get_gap") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(inout) :: gap(*)
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_surface(const gfmd_sim *s, double *z);
    function c_gfmd_get_surface(s, z) bind(C, name="gfmd_get_surface") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(inout) :: z(*)
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_pressure(const gfmd_sim *s, double *p);
    function c_gfmd_get_pressure(s, p) bind(C, name="gfmd_get_pressure") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(inout) :: p(*)
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_sim_save(const gfmd_sim *s, const char *path);
    function c_gfmd_sim_save(s, path) bind(C, name="gfmd_sim_save") result(r)
      import :: c_ptr, c_char, c_int32_t
      type(c_ptr), value :: s
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_sim_load(const char *path, gfmd_sim **out, char *errbuf, int64_t errlen);
    function c_gfmd_sim_load(path, out, errbuf, errlen) bind(C, name="gfmd_sim_load") result(r)
      import :: c_ptr, c_char, c_int32_t, c_int64_t
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(out) :: out
      character(kind=c_char), intent(out) :: errbuf(*)
      integer(c_int64_t), value :: errlen
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_threads(gfmd_sim *s, int32_t nthreads);
    function c_gfmd_set_threads(s, nthreads) bind(C, name="gfmd_set_threads") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t), value :: nthreads
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_solver(const gfmd_sim *s, int32_t *solver);
    function c_gfmd_set_boundary(s, boundary) bind(C, name="gfmd_set_boundary") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t), value :: boundary
      integer(c_int32_t) :: r
    end function

    function c_gfmd_get_boundary(s, boundary) bind(C, name="gfmd_get_boundary") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t), intent(out) :: boundary
      integer(c_int32_t) :: r
    end function

    function c_gfmd_get_solver(s, solver) bind(C, name="gfmd_get_solver") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t), intent(out) :: solver
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_threads(const gfmd_sim *s, int32_t *nthreads);
    function c_gfmd_get_threads(s, nthreads) bind(C, name="gfmd_get_threads") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t), intent(out) :: nthreads
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_fft_planner(gfmd_sim *s, int32_t planner);
    function c_gfmd_set_fft_planner(s, planner) bind(C, name="gfmd_set_fft_planner") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t), value :: planner
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_import_wisdom(const char *path);
    function c_gfmd_import_wisdom(path) bind(C, name="gfmd_import_wisdom") result(r)
      import :: c_char, c_int32_t
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_export_wisdom(const char *path);
    function c_gfmd_export_wisdom(path) bind(C, name="gfmd_export_wisdom") result(r)
      import :: c_char, c_int32_t
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int32_t) :: r
    end function

    ! size_t strlen(const char *s);   (C library, to read the library's strings)
    function c_strlen(s) bind(C, name="strlen") result(r)
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: r
    end function

    ! int32_t gfmd_persson_variance(const gfmd_sim *s, double *variance);
    function c_gfmd_persson_variance(s, variance) bind(C, name="gfmd_persson_variance") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: variance
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_persson_contact_area(const gfmd_sim *s, double sigma0, double *rel_area);
    function c_gfmd_persson_contact_area(s, sigma0, rel_area) bind(C, name="gfmd_persson_contact_area") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: sigma0
      real(c_double), intent(out) :: rel_area
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_persson_load(const gfmd_sim *s, double rel_area, double *sigma0);
    function c_gfmd_persson_load(s, rel_area, sigma0) bind(C, name="gfmd_persson_load") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: rel_area
      real(c_double), intent(out) :: sigma0
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_least_squares(int64_t m, int64_t n, const double *a, const double *b, double *x,
    !                            double *rss);
    function c_gfmd_least_squares(m, n, a, b, x, rss) bind(C, name="gfmd_least_squares") result(r)
      import :: c_int32_t, c_int64_t, c_double
      integer(c_int64_t), value :: m, n
      real(c_double), intent(in) :: a(*), b(*)
      real(c_double), intent(out) :: x(*)
      real(c_double), intent(out) :: rss
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_set_hardness(gfmd_sim *s, double hardness);
    function c_gfmd_set_hardness(s, hardness) bind(C, name="gfmd_set_hardness") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: hardness
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_hardness(const gfmd_sim *s, double *hardness);
    function c_gfmd_get_hardness(s, hardness) bind(C, name="gfmd_get_hardness") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: hardness
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_plasticity(const gfmd_sim *s, double *plastic_area, double *plastic_volume);
    function c_gfmd_get_plasticity(s, plastic_area, plastic_volume) bind(C, name="gfmd_get_plasticity") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: s
      real(c_double), intent(out) :: plastic_area, plastic_volume
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_label_patches(int64_t nx, int64_t ny, const int32_t *mask, int32_t connectivity,
    !                            int32_t periodic, int64_t *labels, int64_t *npatches);
    function c_gfmd_label_patches(nx, ny, mask, connectivity, periodic, labels, npatches) &
        bind(C, name="gfmd_label_patches") result(r)
      import :: c_int32_t, c_int64_t
      integer(c_int64_t), value :: nx, ny
      integer(c_int32_t), intent(in) :: mask(*)
      integer(c_int32_t), value :: connectivity, periodic
      integer(c_int64_t), intent(inout) :: labels(*)
      integer(c_int64_t), intent(out) :: npatches
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_contact_patches(const gfmd_sim *s, int32_t connectivity, int64_t *labels,
    !                                  int64_t *npatches);
    function c_gfmd_get_contact_patches(s, connectivity, labels, npatches) &
        bind(C, name="gfmd_get_contact_patches") result(r)
      import :: c_ptr, c_int32_t, c_int64_t
      type(c_ptr), value :: s
      integer(c_int32_t), value :: connectivity
      integer(c_int64_t), intent(inout) :: labels(*)
      integer(c_int64_t), intent(out) :: npatches
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_patch_property(const gfmd_sim *s, int32_t connectivity, int32_t property,
    !                                 int64_t capacity, double *values, int64_t *npatches);
    function c_gfmd_get_patch_property(s, connectivity, property, capacity, values, npatches) &
        bind(C, name="gfmd_get_patch_property") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: s
      integer(c_int32_t), value :: connectivity, property
      integer(c_int64_t), value :: capacity
      real(c_double), intent(inout) :: values(*)
      integer(c_int64_t), intent(out) :: npatches
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_get_pressure_histogram(const gfmd_sim *s, int64_t nbins, double *range,
    !                                     double *fraction, double *mean);
    function c_gfmd_get_pressure_histogram(s, nbins, range, fraction, mean) &
        bind(C, name="gfmd_get_pressure_histogram") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: s
      integer(c_int64_t), value :: nbins
      real(c_double), intent(inout) :: range(2), fraction(*), mean(*)
      integer(c_int32_t) :: r
    end function

    ! int32_t gfmd_persson_pressure_distribution(const gfmd_sim *s, double sigma0, int64_t n,
    !                                            const double *p, double *density);
    function c_gfmd_persson_pressure_distribution(s, sigma0, n, p, density) &
        bind(C, name="gfmd_persson_pressure_distribution") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: s
      real(c_double), value :: sigma0
      integer(c_int64_t), value :: n
      real(c_double), intent(in) :: p(*)
      real(c_double), intent(inout) :: density(*)
      integer(c_int32_t) :: r
    end function

    ! the measured topographies (gfmd_topo_*)
    function c_gfmd_topo_read(path, format, unit, out, errbuf, errlen) bind(C, name="gfmd_topo_read") result(r)
      import :: c_ptr, c_char, c_int32_t, c_int64_t, c_double
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int32_t), value :: format
      real(c_double), value :: unit
      type(c_ptr), intent(out) :: out
      character(kind=c_char), intent(out) :: errbuf(*)
      integer(c_int64_t), value :: errlen
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_from_heights(nx, ny, lx, ly, h, out) bind(C, name="gfmd_topo_from_heights") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      integer(c_int64_t), value :: nx, ny
      real(c_double), value :: lx, ly
      real(c_double), intent(in) :: h(*)
      type(c_ptr), intent(out) :: out
      integer(c_int32_t) :: r
    end function
    subroutine c_gfmd_topo_destroy(t) bind(C, name="gfmd_topo_destroy")
      import :: c_ptr
      type(c_ptr), intent(inout) :: t
    end subroutine
    function c_gfmd_topo_last_error(t, buf, len) bind(C, name="gfmd_topo_last_error") result(r)
      import :: c_ptr, c_char, c_int32_t, c_int64_t
      type(c_ptr), value :: t
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_int64_t), value :: len
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_get_grid(t, nx, ny, lx, ly) bind(C, name="gfmd_topo_get_grid") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: t
      integer(c_int64_t), intent(out) :: nx, ny
      real(c_double), intent(out) :: lx, ly
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_get_info(t, format, has_units, missing) bind(C, name="gfmd_topo_get_info") result(r)
      import :: c_ptr, c_int32_t, c_int64_t
      type(c_ptr), value :: t
      integer(c_int32_t), intent(out) :: format, has_units
      integer(c_int64_t), intent(out) :: missing
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_set_physical_size(t, lx, ly) bind(C, name="gfmd_topo_set_physical_size") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: t
      real(c_double), value :: lx, ly
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_get_heights(t, h) bind(C, name="gfmd_topo_get_heights") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: t
      real(c_double), intent(inout) :: h(*)
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_fill_missing(t, method) bind(C, name="gfmd_topo_fill_missing") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: t
      integer(c_int32_t), value :: method
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_detrend(t, mode) bind(C, name="gfmd_topo_detrend") result(r)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: t
      integer(c_int32_t), value :: mode
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_resample(t, nx, ny) bind(C, name="gfmd_topo_resample") result(r)
      import :: c_ptr, c_int32_t, c_int64_t
      type(c_ptr), value :: t
      integer(c_int64_t), value :: nx, ny
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_psd(t, window, nbins, q, c, count) bind(C, name="gfmd_topo_psd") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: t
      integer(c_int32_t), value :: window
      integer(c_int64_t), value :: nbins
      real(c_double), intent(inout) :: q(*), c(*)
      integer(c_int64_t), intent(inout) :: count(*)
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_profile_psd(t, window, capacity, q, c, n) bind(C, name="gfmd_topo_profile_psd") result(r)
      import :: c_ptr, c_int32_t, c_int64_t, c_double
      type(c_ptr), value :: t
      integer(c_int32_t), value :: window
      integer(c_int64_t), value :: capacity
      real(c_double), intent(inout) :: q(*), c(*)
      integer(c_int64_t), intent(out) :: n
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_moments(t, window, h, s, k) bind(C, name="gfmd_topo_moments") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: t
      integer(c_int32_t), value :: window
      real(c_double), intent(out) :: h, s, k
      integer(c_int32_t) :: r
    end function
    function c_gfmd_topo_persson_contact_area(t, window, kind, width, nu, e_star, sigma0, area, variance) &
        bind(C, name="gfmd_topo_persson_contact_area") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: t
      integer(c_int32_t), value :: window, kind
      real(c_double), value :: width, nu, e_star, sigma0
      real(c_double), intent(out) :: area, variance
      integer(c_int32_t) :: r
    end function

    function c_gfmd_topo_format_supported(format) bind(C, name="gfmd_topo_format_supported") result(r)
      import :: c_int32_t
      integer(c_int32_t), value :: format
      integer(c_int32_t) :: r
    end function

    function c_gfmd_topo_persson_mean_gap(t, window, kind, width, nu, e_star, sigma0, gamma, mean_gap) &
        bind(C, name="gfmd_topo_persson_mean_gap") result(r)
      import :: c_ptr, c_int32_t, c_double
      type(c_ptr), value :: t
      integer(c_int32_t), value :: window, kind
      real(c_double), value :: width, nu, e_star, sigma0, gamma
      real(c_double), intent(out) :: mean_gap
      integer(c_int32_t) :: r
    end function
  end interface
end module gfmd_c_api
