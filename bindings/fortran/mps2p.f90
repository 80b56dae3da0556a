! Fortran 2008 interface to libmps2p (include/mps2p.h), through iso_c_binding.
!
! The C functions are bound privately (c_* below); the public procedures of
! the same names as in C are thin wrappers that take Fortran strings (trimmed
! and NUL-terminated here), Fortran arrays (their length passed for them) and
! return the C status (MPS2P_OK = 0, negative MPS2P_ERR_* on failure; the
! message is mps2p_last_error()). Handles are type(c_ptr); destroy accepts
! c_null_ptr. Vectors are arrays of shape (2, n): x in row 1, y in row 2,
! which is C's interleaved layout. Only what a still-water or dam-break run
! needs is bound: scene, solver, results, statistics, errors.
module mps2p
  use, intrinsic :: iso_c_binding
  implicit none
  private

  ! status codes (include/mps2p.h, section 1; they never change)
  integer(c_int), parameter, public :: MPS2P_OK = 0, MPS2P_STOPPED = 1, &
       MPS2P_ERR_NULL = -1, MPS2P_ERR_INVALID = -2, MPS2P_ERR_UNKNOWN_KEY = -3, &
       MPS2P_ERR_NOMEM = -4, MPS2P_ERR_STATE = -5, MPS2P_ERR_BUFFER = -6, &
       MPS2P_ERR_SOLVE = -7, MPS2P_ERR_DIVERGED = -8, MPS2P_ERR_IO = -9
  ! particle kinds
  integer(c_int), parameter, public :: MPS2P_KIND_FLUID = 0, MPS2P_KIND_WALL = 1, &
       MPS2P_KIND_DUMMY = 2, MPS2P_KIND_OUT = 3

  public :: mps2p_scene_create, mps2p_scene_destroy, mps2p_scene_add_fluid, &
       mps2p_scene_add_fluid_box, mps2p_scene_add_tank, mps2p_scene_set_param, &
       mps2p_scene_set_option, mps2p_solver_create, mps2p_solver_destroy, &
       mps2p_solver_step, mps2p_solver_advance_to, mps2p_solver_particle_count, &
       mps2p_solver_get_positions, mps2p_solver_get_velocities, &
       mps2p_solver_get_pressure, mps2p_solver_get_kinds, mps2p_solver_get_time, &
       mps2p_solver_get_stat, mps2p_last_error, mps2p_status_string

  interface
    integer(c_int) function c_scene_create(l0, scene) bind(C, name="mps2p_scene_create")
      import :: c_int, c_double, c_ptr
      real(c_double), value :: l0
      type(c_ptr), intent(out) :: scene
    end function
    subroutine c_scene_destroy(scene) bind(C, name="mps2p_scene_destroy")
      import :: c_ptr
      type(c_ptr), value :: scene
    end subroutine
    integer(c_int) function c_scene_add_fluid(scene, name, density, viscosity, fluid_id) &
         bind(C, name="mps2p_scene_add_fluid")
      import :: c_int, c_double, c_ptr, c_char
      type(c_ptr), value :: scene
      character(kind=c_char), dimension(*), intent(in) :: name
      real(c_double), value :: density, viscosity
      integer(c_int), intent(out) :: fluid_id
    end function
    integer(c_int) function c_scene_add_fluid_box(scene, fluid_id, x0, y0, x1, y1) &
         bind(C, name="mps2p_scene_add_fluid_box")
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: scene
      integer(c_int), value :: fluid_id
      real(c_double), value :: x0, y0, x1, y1
    end function
    integer(c_int) function c_scene_add_tank(scene, x0, y0, x1, y1, open_top) &
         bind(C, name="mps2p_scene_add_tank")
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: scene
      real(c_double), value :: x0, y0, x1, y1
      integer(c_int), value :: open_top
    end function
    integer(c_int) function c_scene_set_param(scene, key, value) &
         bind(C, name="mps2p_scene_set_param")
      import :: c_int, c_double, c_ptr, c_char
      type(c_ptr), value :: scene
      character(kind=c_char), dimension(*), intent(in) :: key
      real(c_double), value :: value
    end function
    integer(c_int) function c_scene_set_option(scene, key, value) &
         bind(C, name="mps2p_scene_set_option")
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: scene
      character(kind=c_char), dimension(*), intent(in) :: key, value
    end function
    integer(c_int) function c_solver_create(scene, solver) bind(C, name="mps2p_solver_create")
      import :: c_int, c_ptr
      type(c_ptr), value :: scene
      type(c_ptr), intent(out) :: solver
    end function
    subroutine c_solver_destroy(solver) bind(C, name="mps2p_solver_destroy")
      import :: c_ptr
      type(c_ptr), value :: solver
    end subroutine
    integer(c_int) function c_solver_step(solver) bind(C, name="mps2p_solver_step")
      import :: c_int, c_ptr
      type(c_ptr), value :: solver
    end function
    integer(c_int) function c_solver_advance_to(solver, end_time, progress, user_data) &
         bind(C, name="mps2p_solver_advance_to")
      import :: c_int, c_double, c_ptr, c_funptr
      type(c_ptr), value :: solver
      real(c_double), value :: end_time
      type(c_funptr), value :: progress
      type(c_ptr), value :: user_data
    end function
    integer(c_int) function c_solver_particle_count(solver, count) &
         bind(C, name="mps2p_solver_particle_count")
      import :: c_int, c_ptr, c_size_t
      type(c_ptr), value :: solver
      integer(c_size_t), intent(out) :: count
    end function
    integer(c_int) function c_solver_get_positions(solver, out, length) &
         bind(C, name="mps2p_solver_get_positions")
      import :: c_int, c_ptr, c_double, c_size_t
      type(c_ptr), value :: solver
      real(c_double), intent(out) :: out(*)
      integer(c_size_t), value :: length
    end function
    integer(c_int) function c_solver_get_velocities(solver, out, length) &
         bind(C, name="mps2p_solver_get_velocities")
      import :: c_int, c_ptr, c_double, c_size_t
      type(c_ptr), value :: solver
      real(c_double), intent(out) :: out(*)
      integer(c_size_t), value :: length
    end function
    integer(c_int) function c_solver_get_pressure(solver, out, length) &
         bind(C, name="mps2p_solver_get_pressure")
      import :: c_int, c_ptr, c_double, c_size_t
      type(c_ptr), value :: solver
      real(c_double), intent(out) :: out(*)
      integer(c_size_t), value :: length
    end function
    integer(c_int) function c_solver_get_kinds(solver, out, length) &
         bind(C, name="mps2p_solver_get_kinds")
      import :: c_int, c_ptr, c_size_t
      type(c_ptr), value :: solver
      integer(c_int), intent(out) :: out(*)
      integer(c_size_t), value :: length
    end function
    integer(c_int) function c_solver_get_time(solver, time) bind(C, name="mps2p_solver_get_time")
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: solver
      real(c_double), intent(out) :: time
    end function
    integer(c_int) function c_solver_get_stat(solver, key, value) &
         bind(C, name="mps2p_solver_get_stat")
      import :: c_int, c_ptr, c_double, c_char
      type(c_ptr), value :: solver
      character(kind=c_char), dimension(*), intent(in) :: key
      real(c_double), intent(out) :: value
    end function
    type(c_ptr) function c_last_error() bind(C, name="mps2p_last_error")
      import :: c_ptr
    end function
    type(c_ptr) function c_status_string(status) bind(C, name="mps2p_status_string")
      import :: c_ptr, c_int
      integer(c_int), value :: status
    end function
    integer(c_size_t) function c_strlen(text) bind(C, name="strlen")
      import :: c_size_t, c_ptr
      type(c_ptr), value :: text
    end function
  end interface

contains

  ! A Fortran string as C wants it: trailing blanks dropped, NUL added.
  pure function c_string(text) result(out)
    character(*), intent(in) :: text
    character(kind=c_char, len=len_trim(text) + 1) :: out
    out = trim(text) // c_null_char
  end function

  ! A copy of a NUL-terminated C string ("" for a null pointer).
  function f_string(text) result(out)
    type(c_ptr), intent(in) :: text
    character(:), allocatable :: out
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    if (.not. c_associated(text)) then
      out = ""
      return
    end if
    n = int(c_strlen(text))
    call c_f_pointer(text, chars, [n])
    allocate(character(n) :: out)
    do i = 1, n
      out(i:i) = chars(i)
    end do
  end function

  ! The calling thread's last error message.
  function mps2p_last_error() result(message)
    character(:), allocatable :: message
    message = f_string(c_last_error())
  end function

  ! The name of a status code, e.g. "MPS2P_ERR_INVALID".
  function mps2p_status_string(status) result(name)
    integer(c_int), intent(in) :: status
    character(:), allocatable :: name
    name = f_string(c_status_string(status))
  end function

  integer(c_int) function mps2p_scene_create(l0, scene) result(status)
    real(c_double), intent(in) :: l0
    type(c_ptr), intent(out) :: scene
    status = c_scene_create(l0, scene)
  end function

  subroutine mps2p_scene_destroy(scene)
    type(c_ptr), intent(inout) :: scene
    call c_scene_destroy(scene)
    scene = c_null_ptr
  end subroutine

  integer(c_int) function mps2p_scene_add_fluid(scene, name, density, viscosity, fluid_id) &
       result(status)
    type(c_ptr), intent(in) :: scene
    character(*), intent(in) :: name
    real(c_double), intent(in) :: density, viscosity
    integer(c_int), intent(out) :: fluid_id
    status = c_scene_add_fluid(scene, c_string(name), density, viscosity, fluid_id)
  end function

  integer(c_int) function mps2p_scene_add_fluid_box(scene, fluid_id, x0, y0, x1, y1) &
       result(status)
    type(c_ptr), intent(in) :: scene
    integer(c_int), intent(in) :: fluid_id
    real(c_double), intent(in) :: x0, y0, x1, y1
    status = c_scene_add_fluid_box(scene, fluid_id, x0, y0, x1, y1)
  end function

  ! open_top: .true. leaves the top open.
  integer(c_int) function mps2p_scene_add_tank(scene, x0, y0, x1, y1, open_top) result(status)
    type(c_ptr), intent(in) :: scene
    real(c_double), intent(in) :: x0, y0, x1, y1
    logical, intent(in) :: open_top
    status = c_scene_add_tank(scene, x0, y0, x1, y1, merge(1_c_int, 0_c_int, open_top))
  end function

  integer(c_int) function mps2p_scene_set_param(scene, key, value) result(status)
    type(c_ptr), intent(in) :: scene
    character(*), intent(in) :: key
    real(c_double), intent(in) :: value
    status = c_scene_set_param(scene, c_string(key), value)
  end function

  integer(c_int) function mps2p_scene_set_option(scene, key, value) result(status)
    type(c_ptr), intent(in) :: scene
    character(*), intent(in) :: key, value
    status = c_scene_set_option(scene, c_string(key), c_string(value))
  end function

  integer(c_int) function mps2p_solver_create(scene, solver) result(status)
    type(c_ptr), intent(in) :: scene
    type(c_ptr), intent(out) :: solver
    status = c_solver_create(scene, solver)
  end function

  subroutine mps2p_solver_destroy(solver)
    type(c_ptr), intent(inout) :: solver
    call c_solver_destroy(solver)
    solver = c_null_ptr
  end subroutine

  integer(c_int) function mps2p_solver_step(solver) result(status)
    type(c_ptr), intent(in) :: solver
    status = c_solver_step(solver)
  end function

  ! Advances to end_time exactly, without a progress callback.
  integer(c_int) function mps2p_solver_advance_to(solver, end_time) result(status)
    type(c_ptr), intent(in) :: solver
    real(c_double), intent(in) :: end_time
    status = c_solver_advance_to(solver, end_time, c_null_funptr, c_null_ptr)
  end function

  integer(c_int) function mps2p_solver_particle_count(solver, count) result(status)
    type(c_ptr), intent(in) :: solver
    integer(c_size_t), intent(out) :: count
    status = c_solver_particle_count(solver, count)
  end function

  ! out(2, n): out(1, i) = x, out(2, i) = y of particle i.
  integer(c_int) function mps2p_solver_get_positions(solver, out) result(status)
    type(c_ptr), intent(in) :: solver
    real(c_double), contiguous, intent(out) :: out(:, :)
    status = c_solver_get_positions(solver, out, size(out, kind=c_size_t))
  end function

  integer(c_int) function mps2p_solver_get_velocities(solver, out) result(status)
    type(c_ptr), intent(in) :: solver
    real(c_double), contiguous, intent(out) :: out(:, :)
    status = c_solver_get_velocities(solver, out, size(out, kind=c_size_t))
  end function

  integer(c_int) function mps2p_solver_get_pressure(solver, out) result(status)
    type(c_ptr), intent(in) :: solver
    real(c_double), contiguous, intent(out) :: out(:)
    status = c_solver_get_pressure(solver, out, size(out, kind=c_size_t))
  end function

  integer(c_int) function mps2p_solver_get_kinds(solver, out) result(status)
    type(c_ptr), intent(in) :: solver
    integer(c_int), contiguous, intent(out) :: out(:)
    status = c_solver_get_kinds(solver, out, size(out, kind=c_size_t))
  end function

  integer(c_int) function mps2p_solver_get_time(solver, time) result(status)
    type(c_ptr), intent(in) :: solver
    real(c_double), intent(out) :: time
    status = c_solver_get_time(solver, time)
  end function

  integer(c_int) function mps2p_solver_get_stat(solver, key, value) result(status)
    type(c_ptr), intent(in) :: solver
    character(*), intent(in) :: key
    real(c_double), intent(out) :: value
    status = c_solver_get_stat(solver, c_string(key), value)
  end function

end module mps2p
