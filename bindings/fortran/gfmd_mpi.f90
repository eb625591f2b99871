!> gfmd on grids distributed over MPI ranks (libgfmd_mpi), for Fortran.
!>
!>   use gfmd
!>   use gfmd_mpi
!>   use mpi_f08
!>   type(gfmd_sim_t) :: sim
!>   call gfmd_sim_create_mpi(sim, nx, ny, lx, ly, MPI_COMM_WORLD, planner=GFMD_PLANNER_ESTIMATE)
!>   call gfmd_mpi_get_local_grid(sim, local_ny, y0)      ! this rank owns rows y0 .. y0+local_ny-1
!>   call gfmd_mpi_set_local_heights(sim, h)               ! h(nx, local_ny): the C slab, no transposes
!>
!> The communicator is a type(MPI_Comm) (mpi_f08) or a default integer (the mpi module, mpif.h).
!> A distributed handle is then used through the type-bound procedures of module gfmd, every call
!> collective (all ranks, same order, same arguments; see gfmd_mpi.h); whole-grid fields are
!> refused on more than one rank, the local ones below take their place.  Destroy it explicitly on
!> every rank before MPI_Finalize (`call sim%destroy()`): destruction is collective.
!> Every procedure takes optional `stat` and `errmsg`, as in module gfmd.
module gfmd_mpi
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_char, c_null_char, c_double, &
                                         c_int, c_int32_t, c_int64_t
  use mpi_f08, only: MPI_Comm
  use gfmd, only: gfmd_sim_t, gfmd_sim_adopt, gfmd_sim_c_handle, dp, GFMD_OK, GFMD_PLANNER_MEASURE
  use gfmd_report, only: finish, buffer_text
  implicit none
  private

  public :: gfmd_sim_create_mpi, gfmd_sim_load_mpi, gfmd_mpi_get_local_grid, gfmd_mpi_get_ranks
  public :: gfmd_mpi_set_local_heights, gfmd_mpi_get_local_heights, gfmd_mpi_get_local_surface
  public :: gfmd_mpi_get_local_gap, gfmd_mpi_get_local_pressure, gfmd_mpi_get_local_contact_patches

  !> Create a distributed simulation on a communicator (collective).
  interface gfmd_sim_create_mpi
    module procedure create_f08, create_int
  end interface gfmd_sim_create_mpi

  !> Load a checkpoint into a distributed simulation (collective).
  interface gfmd_sim_load_mpi
    module procedure load_f08, load_int
  end interface gfmd_sim_load_mpi

  interface
    ! int32_t gfmd_sim_create_mpi_f(MPI_Fint comm, int64_t nx, int64_t ny, double lx, double ly,
    !                               int32_t planner, gfmd_sim **out);
    function c_create(comm, nx, ny, lx, ly, planner, out) bind(C, name='gfmd_sim_create_mpi_f') result(st)
      import :: c_int, c_int64_t, c_double, c_int32_t, c_ptr
      integer(c_int), value :: comm
      integer(c_int64_t), value :: nx, ny
      real(c_double), value :: lx, ly
      integer(c_int32_t), value :: planner
      type(c_ptr), intent(out) :: out
      integer(c_int32_t) :: st
    end function c_create
    ! int32_t gfmd_sim_load_mpi_f(MPI_Fint comm, const char *path, gfmd_sim **out, char *errbuf, int64_t errlen);
    function c_load(comm, path, out, errbuf, errlen) bind(C, name='gfmd_sim_load_mpi_f') result(st)
      import :: c_int, c_char, c_ptr, c_int64_t, c_int32_t
      integer(c_int), value :: comm
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(out) :: out
      character(kind=c_char), intent(inout) :: errbuf(*)
      integer(c_int64_t), value :: errlen
      integer(c_int32_t) :: st
    end function c_load
    ! int32_t gfmd_mpi_get_local_grid(const gfmd_sim *s, int64_t *local_ny, int64_t *y0);
    function c_local_grid(s, local_ny, y0) bind(C, name='gfmd_mpi_get_local_grid') result(st)
      import :: c_ptr, c_int64_t, c_int32_t
      type(c_ptr), value :: s
      integer(c_int64_t), intent(out) :: local_ny, y0
      integer(c_int32_t) :: st
    end function c_local_grid
    ! int32_t gfmd_mpi_get_ranks(const gfmd_sim *s, int32_t *ranks);
    function c_ranks(s, ranks) bind(C, name='gfmd_mpi_get_ranks') result(st)
      import :: c_ptr, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t), intent(out) :: ranks
      integer(c_int32_t) :: st
    end function c_ranks
    ! int32_t gfmd_mpi_set_local_heights(gfmd_sim *s, const double *h, int64_t ld);
    function c_set_heights(s, h, ld) bind(C, name='gfmd_mpi_set_local_heights') result(st)
      import :: c_ptr, c_double, c_int64_t, c_int32_t
      type(c_ptr), value :: s
      real(c_double), intent(in) :: h(*)
      integer(c_int64_t), value :: ld
      integer(c_int32_t) :: st
    end function c_set_heights
    ! int32_t gfmd_mpi_get_local_<field>(const gfmd_sim *s, double *out, int64_t ld);
    function c_get_heights(s, x, ld) bind(C, name='gfmd_mpi_get_local_heights') result(st)
      import :: c_ptr, c_double, c_int64_t, c_int32_t
      type(c_ptr), value :: s
      real(c_double), intent(inout) :: x(*)
      integer(c_int64_t), value :: ld
      integer(c_int32_t) :: st
    end function c_get_heights
    function c_get_surface(s, x, ld) bind(C, name='gfmd_mpi_get_local_surface') result(st)
      import :: c_ptr, c_double, c_int64_t, c_int32_t
      type(c_ptr), value :: s
      real(c_double), intent(inout) :: x(*)
      integer(c_int64_t), value :: ld
      integer(c_int32_t) :: st
    end function c_get_surface
    function c_get_gap(s, x, ld) bind(C, name='gfmd_mpi_get_local_gap') result(st)
      import :: c_ptr, c_double, c_int64_t, c_int32_t
      type(c_ptr), value :: s
      real(c_double), intent(inout) :: x(*)
      integer(c_int64_t), value :: ld
      integer(c_int32_t) :: st
    end function c_get_gap
    function c_get_pressure(s, x, ld) bind(C, name='gfmd_mpi_get_local_pressure') result(st)
      import :: c_ptr, c_double, c_int64_t, c_int32_t
      type(c_ptr), value :: s
      real(c_double), intent(inout) :: x(*)
      integer(c_int64_t), value :: ld
      integer(c_int32_t) :: st
    end function c_get_pressure
    ! int32_t gfmd_mpi_get_local_contact_patches(const gfmd_sim *s, int32_t connectivity, int64_t *labels,
    !                                            int64_t ld, int64_t *npatches);
    function c_get_local_contact_patches(s, connectivity, labels, ld, npatches) &
        bind(C, name='gfmd_mpi_get_local_contact_patches') result(st)
      import :: c_ptr, c_int64_t, c_int32_t
      type(c_ptr), value :: s
      integer(c_int32_t), value :: connectivity
      integer(c_int64_t), intent(inout) :: labels(*)
      integer(c_int64_t), value :: ld
      integer(c_int64_t), intent(out) :: npatches
      integer(c_int32_t) :: st
    end function c_get_local_contact_patches
  end interface

  abstract interface
    function local_getter(s, x, ld) result(st)
      import :: c_ptr, c_double, c_int64_t, c_int32_t
      type(c_ptr), value :: s
      real(c_double), intent(inout) :: x(*)
      integer(c_int64_t), value :: ld
      integer(c_int32_t) :: st
    end function local_getter
  end interface

contains

  subroutine create_int(sim, nx, ny, lx, ly, comm, planner, stat, errmsg)
    type(gfmd_sim_t), intent(inout) :: sim
    integer, intent(in) :: nx, ny
    real(dp), intent(in) :: lx, ly
    integer, intent(in) :: comm  !< a Fortran communicator handle (mpi module, mpif.h)
    integer, intent(in), optional :: planner
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    type(c_ptr) :: p
    integer(c_int32_t) :: st, pl
    pl = GFMD_PLANNER_MEASURE
    if (present(planner)) pl = int(planner, c_int32_t)
    p = c_null_ptr
    st = c_create(int(comm, c_int), int(nx, c_int64_t), int(ny, c_int64_t), lx, ly, pl, p)
    if (st == GFMD_OK) call gfmd_sim_adopt(sim, p)
    call finish(c_null_ptr, st, 'create', stat, errmsg, '')
  end subroutine create_int

  subroutine create_f08(sim, nx, ny, lx, ly, comm, planner, stat, errmsg)
    type(gfmd_sim_t), intent(inout) :: sim
    integer, intent(in) :: nx, ny
    real(dp), intent(in) :: lx, ly
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in), optional :: planner
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call create_int(sim, nx, ny, lx, ly, comm%MPI_VAL, planner, stat, errmsg)
  end subroutine create_f08

  subroutine load_int(sim, path, comm, stat, errmsg)
    type(gfmd_sim_t), intent(inout) :: sim
    character(*), intent(in) :: path
    integer, intent(in) :: comm
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    type(c_ptr) :: p
    integer(c_int32_t) :: st
    character(kind=c_char) :: buf(512)
    buf = c_null_char
    p = c_null_ptr
    st = c_load(int(comm, c_int), trim(path) // c_null_char, p, buf, int(size(buf), c_int64_t))
    if (st == GFMD_OK) call gfmd_sim_adopt(sim, p)
    call finish(c_null_ptr, st, 'load', stat, errmsg, buffer_text(buf))
  end subroutine load_int

  subroutine load_f08(sim, path, comm, stat, errmsg)
    type(gfmd_sim_t), intent(inout) :: sim
    character(*), intent(in) :: path
    type(MPI_Comm), intent(in) :: comm
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call load_int(sim, path, comm%MPI_VAL, stat, errmsg)
  end subroutine load_f08

  !> This rank's rows: y0 .. y0 + local_ny - 1 of the global grid (0-based, as in C).  Local.
  subroutine gfmd_mpi_get_local_grid(sim, local_ny, y0, stat, errmsg)
    type(gfmd_sim_t), intent(in) :: sim
    integer, intent(out) :: local_ny, y0
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int64_t) :: n, first
    integer(c_int32_t) :: st
    n = 0
    first = 0
    st = c_local_grid(gfmd_sim_c_handle(sim), n, first)
    local_ny = int(n)
    y0 = int(first)
    call finish(gfmd_sim_c_handle(sim), st, 'get_local_grid', stat, errmsg)
  end subroutine gfmd_mpi_get_local_grid

  !> Ranks of the simulation's communicator (1 for a serial simulation).  Local.
  subroutine gfmd_mpi_get_ranks(sim, ranks, stat, errmsg)
    type(gfmd_sim_t), intent(in) :: sim
    integer, intent(out) :: ranks
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    integer(c_int32_t) :: n, st
    n = 0
    st = c_ranks(gfmd_sim_c_handle(sim), n)
    ranks = int(n)
    call finish(gfmd_sim_c_handle(sim), st, 'get_ranks', stat, errmsg)
  end subroutine gfmd_mpi_get_ranks

  !> This rank's rows of the substrate, h(ld, local_ny) with ld = size(h, 1) >= nx.  Collective.
  subroutine gfmd_mpi_set_local_heights(sim, h, stat, errmsg)
    type(gfmd_sim_t), intent(inout) :: sim
    real(dp), intent(in), contiguous :: h(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    type(c_ptr) :: p
    integer(c_int32_t) :: st
    real(dp) :: none(1)
    p = gfmd_sim_c_handle(sim)
    if (size(h) > 0) then
      st = c_set_heights(p, h, int(size(h, 1), c_int64_t))
    else  ! a rank without rows: nothing to pass, the call is still collective
      st = c_set_heights(p, none, int(max(size(h, 1), 1), c_int64_t))
    end if
    call finish(p, st, 'set_local_heights', stat, errmsg)
  end subroutine gfmd_mpi_set_local_heights

  subroutine get_local(sim, getter, x, where, stat, errmsg)
    type(gfmd_sim_t), intent(in) :: sim
    procedure(local_getter) :: getter
    real(dp), intent(inout), contiguous :: x(:, :)
    character(*), intent(in) :: where
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    type(c_ptr) :: p
    integer(c_int32_t) :: st
    real(dp) :: none(1)
    p = gfmd_sim_c_handle(sim)
    if (size(x) > 0) then
      st = getter(p, x, int(size(x, 1), c_int64_t))
    else
      st = getter(p, none, int(max(size(x, 1), 1), c_int64_t))
    end if
    call finish(p, st, where, stat, errmsg)
  end subroutine get_local

  !> This rank's rows of the substrate / surface / gap / contact pressure into x(ld, local_ny).  Local.
  subroutine gfmd_mpi_get_local_heights(sim, h, stat, errmsg)
    type(gfmd_sim_t), intent(in) :: sim
    real(dp), intent(inout), contiguous :: h(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call get_local(sim, c_get_heights, h, 'get_local_heights', stat, errmsg)
  end subroutine gfmd_mpi_get_local_heights

  subroutine gfmd_mpi_get_local_surface(sim, z, stat, errmsg)
    type(gfmd_sim_t), intent(in) :: sim
    real(dp), intent(inout), contiguous :: z(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call get_local(sim, c_get_surface, z, 'get_local_surface', stat, errmsg)
  end subroutine gfmd_mpi_get_local_surface

  subroutine gfmd_mpi_get_local_gap(sim, gap, stat, errmsg)
    type(gfmd_sim_t), intent(in) :: sim
    real(dp), intent(inout), contiguous :: gap(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call get_local(sim, c_get_gap, gap, 'get_local_gap', stat, errmsg)
  end subroutine gfmd_mpi_get_local_gap

  subroutine gfmd_mpi_get_local_pressure(sim, p, stat, errmsg)
    type(gfmd_sim_t), intent(in) :: sim
    real(dp), intent(inout), contiguous :: p(:, :)
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    call get_local(sim, c_get_pressure, p, 'get_local_pressure', stat, errmsg)
  end subroutine gfmd_mpi_get_local_pressure

  !> This rank's rows of the contact patches' labels into labels(nx, local_ny) (default integers;
  !> the labels of the whole grid, the same at any number of ranks) and their number.  Collective.
  subroutine gfmd_mpi_get_local_contact_patches(sim, labels, npatches, connectivity, stat, errmsg)
    type(gfmd_sim_t), intent(in) :: sim
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
    allocate (lab(max(size(labels, 1), 1), max(size(labels, 2), 1)))
    st = c_get_local_contact_patches(gfmd_sim_c_handle(sim), conn, lab, int(max(size(labels, 1), 1), c_int64_t), n)
    if (st == GFMD_OK) then
      labels = int(lab(1:size(labels, 1), 1:size(labels, 2)))
      npatches = int(n)
    end if
    call finish(gfmd_sim_c_handle(sim), st, 'get_local_contact_patches', stat, errmsg)
  end subroutine gfmd_mpi_get_local_contact_patches

end module gfmd_mpi
