"""Scene: particle spacing, fluids, particles, parameters and options."""
import math
import warnings

import numpy as np

from . import errors
from ._core import Owned, check, encode, index, int_array, real, real_array
from ._native import ffi, lib

KIND_FLUID = lib.MPS2P_KIND_FLUID
KIND_WALL = lib.MPS2P_KIND_WALL
KIND_DUMMY = lib.MPS2P_KIND_DUMMY
# a solver's fluid particle that left the domain (parameter out_limit): out
# of the run, frozen where it left; never a scene's
KIND_OUT = lib.MPS2P_KIND_OUT

# The C library counts cells as floor(side / l0 + 1e-6) (lib/core/scene.c): a
# side within this many l0 of a whole number is taken as that number.
_SNAP_TOLERANCE = 1e-6


def param_info():
    """{key: (default, description)} for every numeric parameter, in the C
    library's order."""
    count = ffi.new("size_t *")
    check(lib.mps2p_param_count(count))
    key, description, default = ffi.new("char **"), ffi.new("char **"), ffi.new("double *")
    info = {}
    for i in range(count[0]):
        check(lib.mps2p_param_info(i, key, description, default))
        info[ffi.string(key[0]).decode()] = (default[0], ffi.string(description[0]).decode())
    return info


def setting_kind(key):
    """"parameter" or "option" (effects included) for a known setting's key,
    else None (Scene.set's and the scene files' hints for a key given as the
    wrong kind)."""
    if key in param_info():
        return "parameter"
    return "option" if key in option_info() else None


def _wrong_kind(key, value):
    """Why a setting unknown as given is known as the other kind, or None."""
    kind = setting_kind(key)
    if isinstance(value, str) and kind == "parameter":
        return "%s is a numeric parameter: give it a number, not the string %r" % (key, value)
    if not isinstance(value, str) and kind == "option":
        return "%s is an option: give it one of its choices as a string (%s)" % (
            key, ", ".join(option_info()[key][1]))
    return None


def option_info():
    """{key: (default, choices, description)} for every option (named choice),
    in the C library's order; choices is a tuple of str."""
    count, choices = ffi.new("size_t *"), ffi.new("size_t *")
    check(lib.mps2p_option_count(count))
    key, description, default, name = (ffi.new("char **") for _ in range(4))
    info = {}
    for i in range(count[0]):
        check(lib.mps2p_option_info(i, key, description, default, choices))
        names = []
        for c in range(choices[0]):
            check(lib.mps2p_option_choice(i, c, name))
            names.append(ffi.string(name[0]).decode())
        info[ffi.string(key[0]).decode()] = (ffi.string(default[0]).decode(), tuple(names),
                                             ffi.string(description[0]).decode())
    return info


class Scene(Owned):
    """A scene under construction (wraps mps2p_scene).

    Scene(l0, **settings): l0 is the particle spacing (m); settings are the C
    library's numeric parameters by name (see param_info()) and options
    (named choices such as pressure_solver="cg", a str value). The C handle
    is freed by close(), by leaving a `with` block, or when the object is
    collected.

    Boxes are filled on the square lattice of spacing l0, a particle at the
    centre of each whole l0 x l0 cell: a side that is not a whole number of
    l0 is rounded down to one (0.15 m at l0 = 0.02 m holds 7 particles,
    0.14 m). The methods that fill boxes warn with mps2p.SnapWarning when
    they round."""

    _what = "scene"

    def __init__(self, l0, **settings):
        handle = ffi.new("mps2p_scene **")
        self.l0 = real(l0, "l0")
        check(lib.mps2p_scene_create(self.l0, handle))
        self._own(handle[0], lib.mps2p_scene_destroy)
        self.set(**settings)

    # -- fluids and particles ---------------------------------------------
    def add_fluid(self, name, density, viscosity):
        """Adds a fluid: name, density (kg/m^3), kinematic viscosity (m^2/s).
        Returns its id (0, 1, ... in order), for add_fluid_box and fluid_ids."""
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
        """Fills the box [x0, x1] x [y0, y1] (m) with particles of the fluid
        `fluid_id` (from add_fluid), one at the centre of each l0 x l0 cell
        from (x0, y0). A side that is not a whole number of l0 is rounded
        down (SnapWarning)."""
        fluid_id = index(fluid_id, "fluid_id")
        box = _box(x0, y0, x1, y1)
        check(lib.mps2p_scene_add_fluid_box(self.handle, fluid_id, *box))
        self._warn_if_snapped("fluid box", box)

    def add_wall_box(self, x0, y0, x1, y1):
        """Fills the box [x0, x1] x [y0, y1] (m) with solid particles on the
        same lattice (body "walls"); when the solver is built, those facing an
        empty lattice site become KIND_WALL, the others KIND_DUMMY. A side
        that is not a whole number of l0 is rounded down (SnapWarning)."""
        box = _box(x0, y0, x1, y1)
        check(lib.mps2p_scene_add_wall_box(self.handle, *box))
        self._warn_if_snapped("wall box", box)

    def add_tank(self, x0, y0, x1, y1, open_top=True):
        """Walls around the inner region [x0, x1] x [y0, y1] (m): left, right,
        bottom, and top unless open_top (the default: open). They are
        ceil(max radius / l0) layers thick for the radii set so far (set
        re_density/re_laplacian first: Solver refuses radii raised past them):
        the layer facing the inside is KIND_WALL, the ones behind KIND_DUMMY.
        The inner region is rounded down to whole l0 (SnapWarning)."""
        if not isinstance(open_top, (bool, int, np.bool_)):
            raise TypeError("open_top must be True or False, got %r" % (open_top,))
        box = _box(x0, y0, x1, y1)
        check(lib.mps2p_scene_add_tank(self.handle, *box, 1 if open_top else 0))
        self._warn_if_snapped("tank", box)

    def add_particles(self, positions, kinds, fluid_ids=None, velocities=None):
        """Adds particles from arrays: positions (n, 2) m, kinds (n,) of
        KIND_FLUID/KIND_WALL/KIND_DUMMY, fluid_ids (n,) for fluid particles
        (read only where the kind is fluid), velocities (n, 2) m/s or None for
        rest. The arrays are copied; integers must fit a C int."""
        positions = real_array(positions, (-1, 2), "positions")
        n = positions.shape[0]
        kinds = int_array(kinds, n, "kinds")
        ids = int_array(fluid_ids, n, "fluid_ids") if fluid_ids is not None else None
        vel = real_array(velocities, (n, 2), "velocities") if velocities is not None else None
        check(lib.mps2p_scene_add_particles(
            self.handle, n, ffi.from_buffer("double[]", positions),
            ffi.from_buffer("double[]", vel) if vel is not None else ffi.NULL,
            ffi.from_buffer("int[]", kinds),
            ffi.from_buffer("int[]", ids) if ids is not None else ffi.NULL))

    # -- wall bodies (for forces on them and host-driven motion) ------------
    def add_body_box(self, name, x0, y0, x1, y1):
        """Fills a box with solid particles of body `name` (created if new),
        as add_wall_box; returns the body id."""
        body = ffi.new("int *")
        box = _box(x0, y0, x1, y1)
        check(lib.mps2p_scene_add_body_box(self.handle, encode(name, "body name"), *box, body))
        self._warn_if_snapped("body box", box)
        return body[0]

    def add_body_particles(self, name, positions, kinds):
        """Adds wall/dummy particles (positions (n, 2) m, kinds (n,)) to body
        `name` (created if new); returns the body id."""
        positions = real_array(positions, (-1, 2), "positions")
        kinds = int_array(kinds, positions.shape[0], "kinds")
        body = ffi.new("int *")
        check(lib.mps2p_scene_add_body_particles(
            self.handle, encode(name, "body name"), positions.shape[0],
            ffi.from_buffer("double[]", positions), ffi.from_buffer("int[]", kinds), body))
        return body[0]

    def assign_body(self, name, x0, y0, x1, y1):
        """Moves the solids already in the box into body `name` (e.g. one tank
        wall); returns the body id. InvalidArgumentError when the box holds none."""
        body = ffi.new("int *")
        check(lib.mps2p_scene_assign_body(self.handle, encode(name, "body name"),
                                          *_box(x0, y0, x1, y1), body))
        return body[0]

    @property
    def body_count(self):
        """Bodies in the scene, "walls" (id 0) included."""
        count = ffi.new("int *")
        check(lib.mps2p_scene_body_count(self.handle, count))
        return count[0]

    @property
    def particle_count(self):
        """Particles added so far (fluid and solid)."""
        count = ffi.new("size_t *")
        check(lib.mps2p_scene_particle_count(self.handle, count))
        return int(count[0])

    # -- parameters and options -------------------------------------------
    def set(self, **settings):
        """Sets numeric parameters and options by name: set(cfl=0.1,
        pressure_solver="cg"). A str value is an option, a number a parameter.
        A scheme ("scheme": "corrected" or "koshizuka1996") is set first, so
        that the other settings given with it override its choices."""
        if "scheme" in settings:
            settings = dict(settings)
            self.set_option("scheme", settings.pop("scheme"))
        for key, value in settings.items():
            try:
                if isinstance(value, str):
                    self.set_option(key, value)
                else:
                    self.set_param(key, value)
            except errors.UnknownKeyError as e:
                hint = _wrong_kind(key, value)
                if hint:
                    raise errors.UnknownKeyError("%s: %s" % (e, hint), e.status,
                                                 e.status_name) from None
                raise

    def set_param(self, key, value):
        """Sets the numeric parameter `key` (param_info() lists them with
        their defaults and units). UnknownKeyError for an unknown key,
        InvalidArgumentError for a value out of its range."""
        check(lib.mps2p_scene_set_param(self.handle, encode(key, "parameter name"),
                                        real(value, "parameter " + str(key))))

    def get_param(self, key):
        """The numeric parameter `key` as set, or its default (float)."""
        value = ffi.new("double *")
        check(lib.mps2p_scene_get_param(self.handle, encode(key, "parameter name"), value))
        return value[0]

    def set_option(self, key, value):
        """Sets the option `key` to the choice `value` (both str), e.g.
        set_option("pressure_solver", "cg"); effects are options
        "effect.<name>" = "auto" | "on" | "off". include/mps2p.h lists them."""
        check(lib.mps2p_scene_set_option(self.handle, encode(key, "option name"),
                                         encode(value, "option " + str(key))))

    def get_option(self, key):
        """The option `key`'s choice as set, or its default (str)."""
        value = ffi.new("char **")
        check(lib.mps2p_scene_get_option(self.handle, encode(key, "option name"), value))
        return ffi.string(value[0]).decode()

    @property
    def params(self):
        """{key: value} of every numeric parameter."""
        return {key: self.get_param(key) for key in param_info()}

    def set_domain(self, xmin, ymin, xmax, ymax):
        """The box (m) outside which a particle counts as diverged. Default:
        the box around the initial particles widened by its own width and
        height on every side."""
        check(lib.mps2p_scene_set_domain(self.handle, *_box(xmin, ymin, xmax, ymax)))

    def _warn_if_snapped(self, what, box):
        x0, y0, x1, y1 = box
        for side, length in (("width", x1 - x0), ("height", y1 - y0)):
            cells = length / self.l0
            whole = math.floor(cells + _SNAP_TOLERANCE)
            if cells - whole > _SNAP_TOLERANCE:
                warnings.warn(
                    "%s (%g, %g) to (%g, %g): %s %g m is %.4g l0 (l0 = %g m), rounded down "
                    "to %d l0 = %g m" % (what, x0, y0, x1, y1, side, length, cells, self.l0,
                                         whole, whole * self.l0),
                    errors.SnapWarning, stacklevel=3)


def _box(*values):
    return [real(v, "coordinate") for v in values]


__all__ = ["Scene", "param_info", "option_info", "KIND_FLUID", "KIND_WALL", "KIND_DUMMY",
           "KIND_OUT"]
