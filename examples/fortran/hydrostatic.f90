! Still water from Fortran: a tank 0.1 m deep and wide, l0 = 0.01 m, the
! default scheme (docs/validation.md), run to end_time (0.2 s); prints the
! pressure of the bottom row of water (its middle half, averaged over the
! second half of the run) against rho g h.
!
!   hydrostatic [end_time [tolerance]]
!
! The bottom row's centres are l0/2 above the floor, so the row sees a depth
! of h - l0/2: the reference is rho g (h - l0/2) (rho g h is printed too; the
! default scheme puts the pressure's zero at the water's top, half a spacing
! above the free-surface particles' centres). Measured: 932.5 Pa over 1-2 s
! (+0.06 %). With a tolerance (a fraction), exits 1 when the bottom pressure
! is farther than that from rho g (h - l0/2); and whenever a call fails.
program hydrostatic
  use, intrinsic :: iso_c_binding
  use mps2p
  implicit none
  real(c_double), parameter :: l0 = 0.01_c_double, depth = 0.1_c_double, &
       width = 0.1_c_double, rho = 1000.0_c_double, g = 9.81_c_double
  type(c_ptr) :: scene = c_null_ptr, solver = c_null_ptr
  integer(c_int) :: water, bottom_row
  integer(c_size_t) :: n
  real(c_double), allocatable :: position(:, :), pressure(:)
  integer(c_int), allocatable :: kind(:)
  logical, allocatable :: probe(:)
  integer, parameter :: samples = 10
  integer :: sample
  real(c_double) :: end_time, time, p_bottom, expected, shifted, tolerance
  character(32) :: argument

  end_time = 0.2_c_double
  tolerance = -1
  if (command_argument_count() >= 1) then
    call get_command_argument(1, argument)
    read (argument, *) end_time
  end if
  if (command_argument_count() >= 2) then
    call get_command_argument(2, argument)
    read (argument, *) tolerance
  end if

  call must(mps2p_scene_create(l0, scene), "scene")
  call must(mps2p_scene_add_fluid(scene, "water", rho, 1.0e-6_c_double, water), "fluid")
  call must(mps2p_scene_add_fluid_box(scene, water, 0.0_c_double, 0.0_c_double, width, depth), &
       "water")
  call must(mps2p_scene_add_tank(scene, 0.0_c_double, 0.0_c_double, width, depth + 0.1_c_double, &
       .true.), "tank")
  call must(mps2p_solver_create(scene, solver), "solver")
  call mps2p_scene_destroy(scene)

  call must(mps2p_solver_particle_count(solver, n), "count")
  allocate(position(2, n), pressure(n), kind(n), probe(n))
  call must(mps2p_solver_get_kinds(solver, kind), "kinds")
  ! the mean over the bottom row of water (centres at l0/2) and over the
  ! second half of the run, every 0.01 s: the still water's pressure
  ! oscillates about its mean after the start from rest
  p_bottom = 0
  do sample = 1, samples
    call must(mps2p_solver_advance_to(solver, end_time * (samples + sample) / (2 * samples)), &
         "advance")
    call must(mps2p_solver_get_positions(solver, position), "positions")
    call must(mps2p_solver_get_pressure(solver, pressure), "pressure")
    probe = kind == MPS2P_KIND_FLUID .and. position(2, :) < l0 .and. &
         abs(position(1, :) - width / 2) < width / 4
    bottom_row = count(probe)
    p_bottom = p_bottom + sum(pressure, mask=probe) / bottom_row / samples
  end do
  call must(mps2p_solver_get_time(solver, time), "time")
  call mps2p_solver_destroy(solver)
  deallocate(position, pressure, kind, probe) ! the main program's arrays are never freed for it
  expected = rho * g * depth
  shifted = rho * g * (depth - l0 / 2)
  print '(a, f6.3, a, i0, a)', "hydrostatic: t = ", time, " s, ", n, " particles"
  print '(a, i0, a, f8.2, a)', "bottom row (", bottom_row, " particles): p = ", p_bottom, " Pa"
  print '(a, f8.2, a, sp, f6.2, a)', "rho g h          = ", expected, " Pa (", &
       100 * (p_bottom - expected) / expected, " %)"
  print '(a, f8.2, a, sp, f6.2, a)', "rho g (h - l0/2) = ", shifted, " Pa (", &
       100 * (p_bottom - shifted) / shifted, " %)"
  if (tolerance >= 0 .and. abs(p_bottom - shifted) > tolerance * shifted) then
    print '(a, f6.3)', "hydrostatic: bottom pressure off by more than ", tolerance
    error stop 1
  end if

contains

  subroutine must(status, what)
    integer(c_int), intent(in) :: status
    character(*), intent(in) :: what
    if (status < 0) then
      print '(5a)', what, ": ", mps2p_status_string(status), ": ", mps2p_last_error()
      error stop 1
    end if
  end subroutine

end program hydrostatic
