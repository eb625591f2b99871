!> A "legacy" contact code that already has its own height array: it reads a measured surface
!> from a plain text file, hands it to gfmd as h(nx, ny) (no copies, no transposes) and asks
!> for the contact area, gap and energies at a few loads.
!>
!>   legacy_code [heights-file]      (default: legacy_heights.txt)
program legacy_code
  use gfmd
  implicit none
  character(len=512) :: path
  character(len=256) :: line, msg
  real(dp), allocatable :: h(:, :), p(:, :)
  real(dp) :: lx, ly, sigma0, area, gap, u_el, u_ad
  integer :: nx, ny, u, j, k, st, steps
  type(gfmd_sim_t) :: sim

  path = 'legacy_heights.txt'
  if (command_argument_count() >= 1) call get_command_argument(1, path)

  ! The legacy part: the code's own reader and arrays.
  open (newunit=u, file=trim(path), status='old', action='read', iostat=st)
  if (st /= 0) then
    print '(a)', 'cannot open ' // trim(path)
    error stop 2
  end if
  do
    read (u, '(a)') line
    if (line(1:1) /= '#') exit
  end do
  read (line, *) nx, ny, lx, ly
  allocate (h(nx, ny), p(nx, ny))
  do j = 1, ny
    read (u, *) h(:, j)
  end do
  close (u)
  print '(a, i0, " x ", i0, a, f0.1, " x ", f0.1)', 'read ', nx, ny, ' heights on a cell ', lx, ly

  ! The library part.
  call sim%create(nx, ny, lx, ly)
  call sim%set_heights(h)
  call sim%set_green(GFMD_GREEN_LAYER_FLUID, 2.0_dp)   ! a sheet 2 grid spacings thick
  print '(a12, a10, a10, a14, a14, a7)', 'sigma0', 'A/A0', 'mean gap', 'U_el', 'U_ad', 'steps'
  do k = 1, 4
    sigma0 = 0.002_dp * 4.0_dp**(k - 1)
    call sim%set_pressure(sigma0)
    call sim%relax(steps=steps, stat=st, errmsg=msg)
    if (st /= GFMD_OK) then
      print '(a)', trim(msg)
      error stop 1
    end if
    call sim%get_contact_area(area)
    call sim%get_mean_gap(gap)
    call sim%get_energies(u_el, u_ad)
    print '(es12.4, f10.5, f10.5, es14.5, es14.5, i7)', sigma0, area, gap, u_el, u_ad, steps
  end do
  ! Back into the legacy code's arrays: the contact pressure field, same layout.
  call sim%get_pressure(p)
  print '(a, es12.5, a, es12.5, a)', 'mean pressure ', sum(p) / (nx * ny), ' (load ', sigma0, ')'
  call sim%destroy()
  deallocate (h, p)
end program legacy_code
