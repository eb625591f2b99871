! The Fortran twin of the seed paper's Fig. 3 sweep (gfmd_paper, apps/paper/): the
! same substrate, bodies and loads through the module gfmd, the same CSV columns, and the
! half-space's kappa by gfmd_least_squares.
!
!   paper_fig3 [N [R [OUT [W ...]]]]    defaults: N = 256, R = 32 (lambda_r = R lambda_s),
!                                       OUT = fig3_area_fortran.csv, W = the C program's list
program paper_fig3
  use gfmd
  implicit none
  real(dp), parameter :: lambda_s = 4.0_dp, hurst = 0.8_dp, gradient = 1.0_dp, e_star = 1.0_dp
  integer, parameter :: seed = 2016
  real(dp), parameter :: area_grid(10) = [0.004_dp, 0.008_dp, 0.016_dp, 0.03_dp, 0.05_dp, 0.08_dp, &
                                          0.12_dp, 0.18_dp, 0.27_dp, 0.4_dp]
  real(dp), allocatable :: widths(:), h(:, :), a(:, :), b(:)
  real(dp) :: bandwidth, l, u_max, sigma0, area, persson, gap, u_el, kappa(1)
  type(gfmd_sim_t) :: surface, sim
  integer :: n, nw, i, k, u, m, nargs
  integer :: steps
  character(256) :: arg, out

  n = 256
  bandwidth = 32.0_dp
  out = 'fig3_area_fortran.csv'
  nargs = command_argument_count()
  if (nargs >= 1) then
    call get_command_argument(1, arg)
    read (arg, *) n
  end if
  if (nargs >= 2) then
    call get_command_argument(2, arg)
    read (arg, *) bandwidth
  end if
  if (nargs >= 3) call get_command_argument(3, out)
  if (nargs >= 4) then
    nw = nargs - 3
    allocate (widths(nw))
    do i = 1, nw
      call get_command_argument(3 + i, arg)
      read (arg, *) widths(i)
    end do
  else
    widths = [0.0_dp, 100.0_dp, 10.0_dp, 4.0_dp, 2.0_dp, 1.0_dp, 0.5_dp, 0.25_dp, 0.177_dp, 0.125_dp, &
              0.088_dp, 0.0625_dp, 0.044_dp]
    nw = size(widths)
  end if

  l = real(n, dp)
  ! FFTW_ESTIMATE: the same plans in every run whatever else the machine does, so the C study
  ! with --planner estimate makes the same library calls on the same plans (compare_twin.cmake)
  call surface%create(n, n, l, l, planner=GFMD_PLANNER_ESTIMATE)
  call surface%set_threads(1)
  call surface%generate_selfaffine(hurst, bandwidth * lambda_s, lambda_s, gradient, seed, GFMD_DIST_UNIFORM)
  allocate (h(n, n))
  call surface%get_heights(h)
  u_max = maxval(h) - sum(h) / real(n, dp)**2

  open (newunit=u, file=trim(out), status='replace', action='write')
  write (u, '(a)') 'body,W,sigma0,sigma0_over_Eg,rel_area,persson_area,mean_gap,separation,u_el,steps'
  allocate (a(size(area_grid), 1), b(size(area_grid)))
  m = 0
  do i = 1, nw
    sim = surface                                 ! deep copy: same substrate, planned once more
    if (widths(i) > 0.0_dp) call sim%set_green(GFMD_GREEN_LAYER_FLUID, widths(i) * lambda_s)
    write (*, '(/,a,g0)') 'W = w/lambda_s = ', widths(i)
    write (*, '(a12,2a10,a12,a8)') 'sigma0/E*g', 'A/A0', 'Persson', 'U_el', 'steps'
    do k = 1, size(area_grid)
      call sim%persson_load(area_grid(k), sigma0)     ! the load at which Persson's A/A0 is the target
      call sim%set_pressure(sigma0)
      call sim%relax(0.0_dp, 2000000, steps)
      call sim%get_contact_area(area)
      call sim%persson_contact_area(sigma0, persson)
      call sim%get_mean_gap(gap)
      call sim%get_energies(elastic=u_el)
      write (*, '(es12.4,2f10.5,es12.4,i8)') sigma0 / (e_star * gradient), area, persson, u_el, steps
      write (u, '(a,",",g0,7(",",es17.10),",",i0)') trim(body_name(widths(i))), widths(i), sigma0, &
        sigma0 / (e_star * gradient), area, persson, gap, gap / u_max, u_el, steps
      if (widths(i) == 0.0_dp .and. area <= 0.1_dp) then
        m = m + 1
        a(m, 1) = sigma0 / (e_star * gradient)
        b(m) = area
      end if
    end do
  end do
  close (u)
  if (m >= 2) then
    call gfmd_least_squares(a(1:m, :), b(1:m), kappa)
    write (*, '(/,a,f7.4,a)') 'kappa (half-space, A/A0 <= 0.1) = ', kappa(1), ' (gfmd_least_squares)'
  end if
  write (*, '(a)') 'wrote ' // trim(out)

contains

  function body_name(w) result(name)
    real(dp), intent(in) :: w
    character(:), allocatable :: name
    if (w > 0.0_dp) then
      name = 'layer'
    else
      name = 'halfspace'
    end if
  end function body_name
end program paper_fig3
