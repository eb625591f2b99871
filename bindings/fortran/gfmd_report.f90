!> Status reporting shared by the modules gfmd and gfmd_mpi (not for users: module gfmd
!> re-exports gfmd_status_string): a C status becomes stat/errmsg, or a stop with the message.
module gfmd_report
  use, intrinsic :: iso_c_binding, only: c_ptr, c_associated, c_f_pointer, c_char, c_int32_t, c_int64_t
  use, intrinsic :: iso_fortran_env, only: error_unit
  use gfmd_c_api, only: c_strlen, c_gfmd_last_error, c_gfmd_last_error_length, c_gfmd_status_string
  implicit none
  private
  public :: c_string, handle_message, finish, gfmd_status_string, buffer_text

  integer(c_int32_t), parameter :: OK = 0, ERR_NULL = 1

contains

  !> Copy a NUL-terminated C string owned by the library.
  function c_string(p) result(s)
    type(c_ptr), intent(in) :: p
    character(:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: n, i
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate (character(len=n) :: s)
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end function c_string

  !> The handle's message of its last failure ('' if none or no handle).
  function handle_message(p) result(msg)
    type(c_ptr), intent(in) :: p
    character(:), allocatable :: msg
    character(kind=c_char), allocatable :: buf(:)
    integer(c_int64_t) :: n
    integer :: i
    msg = ''
    if (.not. c_associated(p)) return
    if (c_gfmd_last_error_length(p, n) /= OK) return
    allocate (buf(n))
    if (c_gfmd_last_error(p, buf, n) /= OK) return
    msg = repeat(" ", int(n) - 1)
    do i = 1, int(n) - 1
      msg(i:i) = buf(i)
    end do
  end function handle_message

  !> Report the status of a call: set stat/errmsg, or stop with the message when stat is absent.
  subroutine finish(p, st, where, stat, errmsg, detail)
    type(c_ptr), intent(in) :: p
    integer(c_int32_t), intent(in) :: st
    character(*), intent(in) :: where
    integer, intent(out), optional :: stat
    character(*), intent(out), optional :: errmsg
    character(*), intent(in), optional :: detail
    character(:), allocatable :: msg, why
    if (present(stat)) stat = int(st)
    if (st == OK) then
      if (present(errmsg)) errmsg = ''
      return
    end if
    if (present(detail)) then
      why = detail
    else if (.not. c_associated(p) .and. st == ERR_NULL) then
      why = 'the simulation has not been created (call create first)'
    else
      why = handle_message(p)
    end if
    msg = 'gfmd: ' // where // ': ' // gfmd_status_string(int(st))
    if (len(why) > 0) msg = msg // ': ' // why
    if (present(errmsg)) errmsg = msg
    if (.not. present(stat)) then
      write (error_unit, '(a)') msg
      error stop 1
    end if
  end subroutine finish

  !> Description of a status code.
  function gfmd_status_string(status) result(s)
    integer, intent(in) :: status
    character(:), allocatable :: s
    s = c_string(c_gfmd_status_string(int(status, c_int32_t)))
  end function gfmd_status_string

  !> The text in a NUL-terminated character buffer the library wrote (a load's errbuf).
  function buffer_text(buf) result(msg)
    character(kind=c_char), intent(in) :: buf(:)
    character(:), allocatable :: msg
    integer :: i, n
    n = 0
    do i = 1, size(buf)
      if (buf(i) == char(0)) exit
      n = i
    end do
    allocate (character(len=n) :: msg)
    do i = 1, n
      msg(i:i) = buf(i)
    end do
  end function buffer_text

end module gfmd_report
