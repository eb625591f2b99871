!> The seed paper's thin-layer load sweep (Putignano, Dapp & Mueser, Biomimetics 1, 7 (2016)):
!> a self-affine substrate (H = 0.8, lambda_s = 4a, lambda_r = L/8, rms gradient 1, E* = 1),
!> elastic layers of width w = W lambda_s on a fluid foundation, the load stepped up from one
!> equilibrium to the next; prints A/A0, mean gap and energies per load.
!>
!>   thin_layer_sweep [n]        (grid n x n, default 256; the tests run n = 64)
program thin_layer_sweep
  use gfmd
  implicit none
  real(dp), parameter :: widths(3) = [4.0_dp, 1.0_dp, 0.5_dp]   ! W = w / lambda_s
  integer, parameter :: nloads = 8
  character(len=32) :: arg
  type(gfmd_sim_t) :: sim
  real(dp) :: l, lambda_s, sigma0, area, gap, u_el, u_ad
  integer :: n, iw, k, steps

  n = 256
  if (command_argument_count() >= 1) then
    call get_command_argument(1, arg)
    read (arg, *) n
  end if
  l = real(n, dp)
  lambda_s = 4.0_dp
  call sim%create(n, n, l, l)
  print '(a, a, a, i0, a, i0)', 'gfmd ', gfmd_version(), ' thin-layer sweep on ', n, ' x ', n
  do iw = 1, size(widths)
    call sim%generate_selfaffine(0.8_dp, l / 8.0_dp, lambda_s, 1.0_dp, seed=2016)   ! resets the body
    call sim%set_green(GFMD_GREEN_LAYER_FLUID, widths(iw) * lambda_s)
    print '(/, a, f0.2)', 'layer on a fluid foundation, W = ', widths(iw)
    print '(a4, a12, a10, a10, a14, a7)', 'W', 'sigma0/E*g', 'A/A0', 'mean gap', 'U_el', 'steps'
    do k = 0, nloads - 1
      sigma0 = 1e-3_dp * 100.0_dp**(real(k, dp) / (nloads - 1))
      call sim%set_pressure(sigma0)
      call sim%relax(steps=steps)
      call sim%get_contact_area(area)
      call sim%get_mean_gap(gap)
      call sim%get_energies(u_el, u_ad)
      print '(f4.2, es12.4, f10.5, f10.5, es14.5, i7)', widths(iw), sigma0, area, gap, u_el, steps
    end do
  end do
  call sim%destroy()
end program thin_layer_sweep
