"""Scene: particle spacing, fluids, particles, parameters and options."""
import numpy as np

from ._core import Owned, check, encode, real
from ._native import ffi, lib

KIND_FLUID = lib.MPS2P_KIND_FLUID
KIND_WALL = lib.MPS2P_KIND_WALL
KIND_DUMMY = lib.MPS2P_KIND_DUMMY


def param_info():
    """{key: (default, description)} for every numeric parameter, in the C
    library's order."""
    info = {}
    key, description, default = ffi.new("char **"), ffi.new("char **"), ffi.new("double *")
    index = 0
    while lib.mps2p_param_info(index, key, description, default) == lib.MPS2P_OK:
        info[ffi.string(key[0]).decode()] = (default[0], ffi.string(description[0]).decode())
        index += 1
    return info


class Scene(Owned):
    """A scene under construction (wraps mps2p_scene).

    Scene(l0, **parameters): parameters are the C library's numeric parameters
    by name (see param_info()); options (named choices such as
    pressure_solver="cg") may be passed the same way. The C handle is freed by
    close(), by leaving a `with` block, or when the object is collected."""

    _what = "scene"

    def __init__(self, l0, **settings):
        handle = ffi.new("mps2p_scene **")
        check(lib.mps2p_scene_create(real(l0, "l0"), handle))
        self._own(handle[0], lib.mps2p_scene_destroy)
        self.set(**settings)

    # -- fluids and particles ---------------------------------------------
    def add_fluid(self, name, density, viscosity):
        """Adds a fluid (density kg/m^3, kinematic viscosity m^2/s); returns its id."""
        fluid_id = ffi.new("int *")
        check(lib.mps2p_scene_add_fluid(self.handle, encode(name, "fluid name"),
                                        real(density, "density"), real(viscosity, "viscosity"),
                                        fluid_id))
        return fluid_id[0]

    @property
    def fluids(self):
        """[(name, density, viscosity)] in id order."""
        count = ffi.new("int *")
        check(lib.mps2p_scene_fluid_count(self.handle, count))
        name, density, viscosity = ffi.new("char **"), ffi.new("double *"), ffi.new("double *")
        result = []
        for i in range(count[0]):
            check(lib.mps2p_scene_get_fluid(self.handle, i, name, density, viscosity))
            result.append((ffi.string(name[0]).decode(), density[0], viscosity[0]))
        return result

    def add_fluid_box(self, fluid_id, x0, y0, x1, y1):
        check(lib.mps2p_scene_add_fluid_box(self.handle, int(fluid_id), *_box(x0, y0, x1, y1)))

    def add_wall_box(self, x0, y0, x1, y1):
        check(lib.mps2p_scene_add_wall_box(self.handle, *_box(x0, y0, x1, y1)))

    def add_tank(self, x0, y0, x1, y1, open_top=True):
        check(lib.mps2p_scene_add_tank(self.handle, *_box(x0, y0, x1, y1), 1 if open_top else 0))

    def add_particles(self, positions, kinds, fluid_ids=None, velocities=None):
        """Adds particles from arrays: positions (n, 2), kinds (n,) of
        KIND_FLUID/KIND_WALL/KIND_DUMMY, fluid_ids (n,) for fluid particles,
        velocities (n, 2) or None for rest. The arrays are copied."""
        positions = np.ascontiguousarray(positions, dtype=np.float64)
        if positions.ndim != 2 or positions.shape[1] != 2:
            raise ValueError("positions must have shape (n, 2), got %s" % (positions.shape,))
        n = positions.shape[0]
        kinds = _int_array(kinds, n, "kinds")
        ids = _int_array(fluid_ids, n, "fluid_ids") if fluid_ids is not None else None
        vel = None
        if velocities is not None:
            vel = np.ascontiguousarray(velocities, dtype=np.float64)
            if vel.shape != (n, 2):
                raise ValueError("velocities must have shape (%d, 2), got %s" % (n, vel.shape))
        check(lib.mps2p_scene_add_particles(
            self.handle, n, ffi.from_buffer("double[]", positions),
            ffi.from_buffer("double[]", vel) if vel is not None else ffi.NULL,
            ffi.from_buffer("int[]", kinds),
            ffi.from_buffer("int[]", ids) if ids is not None else ffi.NULL))

    # -- wall bodies (for forces on them and host-driven motion) ------------
    def add_body_box(self, name, x0, y0, x1, y1):
        """Fills a box with solid particles of body `name` (created if new); its id."""
        body = ffi.new("int *")
        check(lib.mps2p_scene_add_body_box(self.handle, encode(name, "body name"),
                                           *_box(x0, y0, x1, y1), body))
        return body[0]

    def add_body_particles(self, name, positions, kinds):
        """Adds wall/dummy particles (positions (n, 2), kinds (n,)) to body `name`."""
        positions = np.ascontiguousarray(positions, dtype=np.float64)
        if positions.ndim != 2 or positions.shape[1] != 2:
            raise ValueError("positions must have shape (n, 2), got %s" % (positions.shape,))
        kinds = _int_array(kinds, positions.shape[0], "kinds")
        body = ffi.new("int *")
        check(lib.mps2p_scene_add_body_particles(
            self.handle, encode(name, "body name"), positions.shape[0],
            ffi.from_buffer("double[]", positions), ffi.from_buffer("int[]", kinds), body))
        return body[0]

    def assign_body(self, name, x0, y0, x1, y1):
        """Moves the solids already in the box into body `name` (e.g. one tank wall)."""
        body = ffi.new("int *")
        check(lib.mps2p_scene_assign_body(self.handle, encode(name, "body name"),
                                          *_box(x0, y0, x1, y1), body))
        return body[0]

    @property
    def body_count(self):
        count = ffi.new("int *")
        check(lib.mps2p_scene_body_count(self.handle, count))
        return count[0]

    @property
    def particle_count(self):
        count = ffi.new("size_t *")
        check(lib.mps2p_scene_particle_count(self.handle, count))
        return count[0]

    # -- parameters and options -------------------------------------------
    def set(self, **settings):
        """Sets numeric parameters and options by name: set(cfl=0.1,
        pressure_solver="cg"). A str value is an option, a number a parameter."""
        for key, value in settings.items():
            if isinstance(value, str):
                self.set_option(key, value)
            else:
                self.set_param(key, value)

    def set_param(self, key, value):
        check(lib.mps2p_scene_set_param(self.handle, encode(key, "parameter name"),
                                        real(value, "parameter " + key)))

    def get_param(self, key):
        value = ffi.new("double *")
        check(lib.mps2p_scene_get_param(self.handle, encode(key, "parameter name"), value))
        return value[0]

    def set_option(self, key, value):
        check(lib.mps2p_scene_set_option(self.handle, encode(key, "option name"),
                                         encode(value, "option " + key)))

    def get_option(self, key):
        value = ffi.new("char **")
        check(lib.mps2p_scene_get_option(self.handle, encode(key, "option name"), value))
        return ffi.string(value[0]).decode()

    @property
    def params(self):
        """{key: value} of every numeric parameter."""
        return {key: self.get_param(key) for key in param_info()}

    def set_domain(self, xmin, ymin, xmax, ymax):
        check(lib.mps2p_scene_set_domain(self.handle, *_box(xmin, ymin, xmax, ymax)))


def _box(*values):
    return [real(v, "coordinate") for v in values]


def _int_array(values, n, what):
    array = np.asarray(values)
    if array.shape != (n,):
        raise ValueError("%s must have shape (%d,), got %s" % (what, n, array.shape))
    if array.size and not np.issubdtype(array.dtype, np.integer):
        raise TypeError("%s must hold integers, got %s" % (what, array.dtype))
    return np.ascontiguousarray(array, dtype=np.intc)
