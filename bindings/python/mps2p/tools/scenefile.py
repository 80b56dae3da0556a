"""Scene files: a TOML description of a run (fluids, particles, parameters,
end time, output schedule, probes), checked strictly: an unknown key, a wrong
type or impossible geometry is refused with the file, the key and the reason.

Layout (every table is optional unless marked):

    [run]                       # required
    name = "dam_break"          # the output folder's name, out/<name> (default: the
                                # file's name): 1 to 100 letters, digits, _ - . not
                                # starting with . (one path component, never a path)
    description = "..."         # one line, shown by `mps2p examples`
    l0 = 0.01                   # particle spacing (m), required
    end_time = 1.0              # s, required
    snapshot_every = 0.1        # s between snapshots (0 = first and last only;
                                # at most 100,000 snapshots in a run)
    picture_times = [0.1, 0.4]  # snapshots drawn in the pictures (default: six, evenly)
    series_every = 0.01         # s between probe samples (0 = every step; at most
                                # 10,000,000 samples in a run)

    [parameters]                # numeric parameters of the C library, by name
    [options]                   # named choices, e.g. pressure_solver = "cg"
    [effects]                   # viscosity = "off" (auto | on | off), as option effect.<name>

    [[fluid]]                   # name, density (kg/m^3), viscosity (m^2/s)
    [[fluid_box]]               # fluid = "water", box = [x0, y0, x1, y1]
    [[tank]]                    # box = [x0, y0, x1, y1], open_top = true
    [[wall_box]]                # box = [x0, y0, x1, y1]
    [[particles]]               # file = "x.npz" or "x.h5" with positions (n,2),
                                # kinds (n,), fluid_ids (n,), velocities (n,2) optional

    [[probe]]                   # name, type and the type's keys:
      type = "pressure"         #   at = [x, y]
      type = "front"            #   fluid = "water", below = 0.02 (m); optional
                                #   compare = "martin_moyce_1952", column_width = 0.15
      type = "elevation"        #   fluid = "water", x = 0.3 (m): a wave gauge, the top of
                                #   the fluid there; optional half_width (m, default l0)
      type = "count"            #   fluid = "water": its particles (all, not only in the domain)
      type = "stat"             #   stat = "kinetic_energy" (any solver statistic)
"""
import difflib
import math
import os
import re
import stat
import warnings

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

import numpy as np

from .. import errors
from ..scene import KIND_FLUID, Scene, setting_kind
from ..solver import STAT_KEYS

NUMBER = "number"
STRING = "string"
BOOL = "bool"
BOX = "box"
POINT = "point"
TIMES = "times"

SCHEMA = {
    "run": ({"l0": NUMBER, "end_time": NUMBER, "snapshot_every": NUMBER,
             "series_every": NUMBER, "name": STRING, "description": STRING,
             "picture_times": TIMES},
            {"l0", "end_time"}),
    "fluid": ({"name": STRING, "density": NUMBER, "viscosity": NUMBER},
              {"name", "density", "viscosity"}),
    "fluid_box": ({"fluid": STRING, "box": BOX}, {"fluid", "box"}),
    "tank": ({"box": BOX, "open_top": BOOL}, {"box"}),
    "wall_box": ({"box": BOX}, {"box"}),
    "particles": ({"file": STRING}, {"file"}),
    "probe": ({"name": STRING, "type": STRING, "at": POINT, "fluid": STRING,
               "below": NUMBER, "stat": STRING, "compare": STRING, "column_width": NUMBER,
               "x": NUMBER, "half_width": NUMBER},
              {"name", "type"}),
}
ARRAYS_OF_TABLES = ("fluid", "fluid_box", "tank", "wall_box", "particles", "probe")
PROBE_KEYS = {"pressure": {"at"}, "front": {"fluid", "below", "compare", "column_width"},
              "elevation": {"fluid", "x", "half_width"}, "count": {"fluid"}, "stat": {"stat"}}
FRONT_REFERENCES = ("martin_moyce_1952",)
# Probe names become HDF5 series names (lib/io/results_file.c: 1 to 64 of these).
PROBE_NAME = re.compile(r"^[A-Za-z0-9_-][A-Za-z0-9_.-]{0,63}$")
# A run's name is the folder out/<name>: one path component, never "", "." or "..".
RUN_NAME = re.compile(r"^[A-Za-z0-9_-][A-Za-z0-9_.-]{0,99}$")
# Each scheduled time is kept in a list, each snapshot in the results file:
# a schedule finer than this is refused rather than filling memory and disk.
MAX_SNAPSHOTS = 100000
MAX_SAMPLES = 10000000


class SceneFile:
    """A checked scene file. `build()` makes the mps2p.Scene; the rest is the
    run's plan (end time, schedule, probes) for mps2p.run."""

    def __init__(self, path, text, data):
        self.path = path
        self.text = text
        self.data = data

    # The [run] table's values, read from data (a script may change either:
    # sf.l0 = 0.02 or sf.data["run"]["l0"] = 0.02, before make_solver()).
    def _run_value(key, default=None):
        def get(self):
            return self.data["run"].get(key, default)

        def set(self, value):
            self.data["run"][key] = value
        return property(get, set, doc="[run] %s" % key)

    l0 = _run_value("l0")
    end_time = _run_value("end_time")
    snapshot_every = _run_value("snapshot_every", 0.0)
    series_every = _run_value("series_every", 0.0)
    picture_times = _run_value("picture_times")
    del _run_value

    @property
    def fluids(self):
        """The fluids' names, in id order (from data)."""
        return [f["name"] for f in self.data.get("fluid", [])]

    @property
    def probes(self):
        """The [[probe]] tables (from data)."""
        return self.data.get("probe", [])

    @property
    def name(self):
        """[run] name, or the file's name without .toml."""
        return self.data["run"].get("name") or default_name(self.path)

    def error(self, key, reason):
        return errors.SceneFileError("%s: %s: %s" % (self.path, key, reason))

    def build(self):
        """The scene, built in the order the C library needs (radii before
        tanks, whose thickness depends on them)."""
        scene = Scene(self.l0)
        try:
            self._build_into(scene)
        except errors.SceneFileError:
            scene.close()
            raise
        return scene

    def threads(self):
        """The solver's parameter threads: the file's (or `mps2p run
        --threads`), else the environment variable MPS2P_THREADS (as the
        benchmarks read it; 0 = OpenMP's default), else 1. The results do not depend
        on it."""
        if "threads" in self.data.get("parameters", {}):
            return float(self.data["parameters"]["threads"])
        text = os.environ.get("MPS2P_THREADS", "").strip()
        if not text:
            return 1.0
        if text == "auto":  # as mps2p run --threads auto
            from .run import auto_threads
            return float(auto_threads()[0])
        try:
            value = int(text)
        except ValueError:
            value = -1
        if not 0 <= value <= 1024:
            raise errors.SceneFileError("environment variable MPS2P_THREADS: a thread count "
                                        "0 to 1024 (0: every core) or auto, got %r" % text)
        return float(value)

    def make_solver(self):
        """The solver for this scene; what the C library refuses at creation
        (an effect the scene cannot support, overlapping particles) is reported
        against this file."""
        from ..solver import Solver
        threads = self.threads()
        with self.build() as scene:
            scene.set_param("threads", threads)
            try:
                return Solver(scene)
            except errors.Error as e:
                raise errors.SceneFileError("%s: %s%s" % (self.path, self._overlap(str(e)), e)) \
                    from e

    def _overlap(self, message):
        """"fluid_box[0] overlaps tank[0]: " for the library's message about
        two particles too close together, from the items that added them."""
        found = re.match(r"particles (\d+) and (\d+) are ", message)
        if not found:
            return ""
        keys = []
        for index in map(int, found.groups()):
            # the first item whose particles reach past the index added it
            keys.append(next((key for key, end in self._added if index < end), None))
        if None in keys:
            return ""
        if keys[0] == keys[1]:
            return "%s: " % keys[0]
        return "%s overlaps %s: " % tuple(keys)

    def _build_into(self, scene):
        self._added = []  # (key, particle count after it), to name overlapping items

        def call(key, function, *args):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", errors.SnapWarning)
                try:
                    result = function(*args)
                except (errors.Error, TypeError, ValueError) as e:
                    # a box over an earlier one: name the item that added it
                    found = re.search(r"overlaps particles (\d+) to ", str(e))
                    other = found and next((k for k, end in self._added
                                            if int(found.group(1)) < end), None)
                    if other:
                        raise self.error("%s overlaps %s" % (key, other), str(e)) from e
                    raise self.error(key, str(e)) from e
            self._added.append((key, scene.particle_count))
            for w in caught:  # the same warning, naming the file and key
                warnings.warn("%s: %s: %s" % (self.path, key, w.message), w.category,
                              stacklevel=4)
            return result

        # a scheme sets several parameters and options: first, so that the
        # file's own settings override it
        options = dict(self.data.get("options", {}))
        if "scheme" in options:
            call("options.scheme", scene.set_option, "scheme", options.pop("scheme"))
        for key, value in self.data.get("parameters", {}).items():
            call("parameters." + key, scene.set_param, key, value)
        for key, value in options.items():
            call("options." + key, scene.set_option, key, value)
        for key, value in self.data.get("effects", {}).items():
            call("effects." + key, scene.set_option, "effect." + key, value)
        ids = {}
        for i, f in enumerate(self.data.get("fluid", [])):
            ids[f["name"]] = call("fluid[%d]" % i, scene.add_fluid, f["name"], f["density"],
                                  f["viscosity"])
        for i, b in enumerate(self.data.get("fluid_box", [])):
            key = "fluid_box[%d]" % i
            call(key, scene.add_fluid_box, ids[b["fluid"]], *self._on_lattice(key, b["box"]))
        for i, t in enumerate(self.data.get("tank", [])):
            key = "tank[%d]" % i
            call(key, scene.add_tank, *self._on_lattice(key, t["box"]), t.get("open_top", True))
        self._warn_boxes_outside_tanks()
        self._warn_probes_out_of_the_fluid()
        for i, w in enumerate(self.data.get("wall_box", [])):
            key = "wall_box[%d]" % i
            call(key, scene.add_wall_box, *self._on_lattice(key, w["box"]))
        for i, p in enumerate(self.data.get("particles", [])):
            key = "particles[%d]" % i
            arrays = self._read_particles(key, p["file"])
            call(key, scene.add_particles, arrays["positions"], arrays["kinds"],
                 arrays.get("fluid_ids"), arrays.get("velocities"))
        if scene.particle_count == 0:
            raise self.error("fluid_box", "the scene has no particles")

    def _on_lattice(self, key, box):
        """The box with each corner coordinate that is not a whole number of
        l0 moved down onto the l0 lattice from the origin (the others as
        written): every box of the file then lies on one lattice, and boxes
        that touch in the file touch on it, at any l0 (`--l0`, check_run's
        l0). Filled from its own corner instead, a box off the lattice put
        its particles a fraction of a spacing off its neighbours' (the
        pressure solve answers that with a spike) or reached into them
        (refused: drop_into_pool.toml at l0 = 0.015 m)."""
        moved = lattice_box(box, self.l0)
        if moved != list(box):
            if moved[2] <= moved[0] or moved[3] <= moved[1]:
                raise self.error(key, "%s is %s than l0 = %g m on the lattice of l0 (%s)"
                                 % (list(box), "narrower" if moved[2] <= moved[0] else "lower",
                                    self.l0, _rounded(moved)))
            warnings.warn("%s: %s: %s moved onto the lattice of l0 = %g m: %s"
                          % (self.path, key, list(box), self.l0, _rounded(moved)),
                          errors.SnapWarning, stacklevel=4)
        return moved

    def _warn_boxes_outside_tanks(self):
        """A fluid box wholly outside every tank (beside it, under its floor,
        over a closed top) is allowed, but no wall holds its fluid (under
        gravity it falls out of the domain): said before the run, not 0.3 s
        into it. A wall box that reaches below the fluid box's top within its
        width may hold it (a shelf, a basin of the file's own). (A box
        reaching into a wall is refused by the library: boxes may touch, not
        overlap.)"""
        tanks, walls = self.data.get("tank", []), self.data.get("wall_box", [])
        if not tanks or self.data.get("particles"):
            return  # walls of particle files may hold it

        def meets(box, tank):
            x0, y0, x1, y1 = tank["box"]
            top = math.inf if tank.get("open_top", True) else y1
            return box[0] < x1 and box[2] > x0 and box[1] < top and box[3] > y0

        def under(box, wall):
            x0, y0, x1, _ = wall["box"]
            return box[0] < x1 and box[2] > x0 and y0 < box[3]

        for i, b in enumerate(self.data.get("fluid_box", [])):
            if not any(meets(b["box"], t) for t in tanks) and \
                    not any(under(b["box"], w) for w in walls):
                warnings.warn("%s: fluid_box[%d]: %s lies outside every tank: no wall holds "
                              "its fluid" % (self.path, i, list(b["box"])),
                              UserWarning, stacklevel=4)

    def _warn_probes_out_of_the_fluid(self):
        """A pressure probe reads the fluid's pressure around its point: 0 inside
        a wall box or outside every tank (a tank's walls lie outside its box),
        for the whole run, which reads like a quiet gauge. Said when built."""
        tanks, walls = self.data.get("tank", []), self.data.get("wall_box", [])

        def inside(point, box, open_top=False):
            x0, y0, x1, y1 = box
            return x0 < point[0] < x1 and y0 < point[1] and (open_top or point[1] < y1)

        for i, p in enumerate(self.data.get("probe", [])):
            if p.get("type") != "pressure":
                continue
            where = next((j for j, w in enumerate(walls) if inside(p["at"], w["box"])), None)
            if where is not None:
                warnings.warn("%s: probe[%d]: %s lies inside wall_box[%d]: a pressure probe "
                              "reads the fluid's pressure, 0 inside a wall (a wall gauge goes "
                              "half a spacing in front of the wall's face)"
                              % (self.path, i, list(p["at"]), where), UserWarning, stacklevel=4)
            elif tanks and not self.data.get("particles") and not any(
                    inside(p["at"], t["box"], t.get("open_top", True)) for t in tanks):
                warnings.warn("%s: probe[%d]: %s lies outside every tank (its walls lie "
                              "outside its box): it reads 0 unless fluid comes there"
                              % (self.path, i, list(p["at"])), UserWarning, stacklevel=4)

    def _read_particles(self, key, name):
        path = name if os.path.isabs(name) else os.path.join(os.path.dirname(self.path), name)
        if not os.path.exists(path):
            raise self.error(key + ".file", "no such file: %s" % path)
        odd = _not_regular(path)
        if odd:
            raise self.error(key + ".file", "%s is %s, not a regular file" % (path, odd))
        try:
            if path.endswith(".npz"):
                with np.load(path) as f:
                    arrays = {k: np.array(f[k]) for k in f.files}
            elif path.endswith((".h5", ".hdf5")):
                import h5py
                with h5py.File(path, "r") as f:
                    arrays = {k: np.array(f[k]) for k in f.keys()}
            else:
                raise self.error(key + ".file", "must end in .npz or .h5, got %s" % name)
        except errors.SceneFileError:
            raise
        except Exception as e:  # a damaged file: say which and why
            raise self.error(key + ".file", "cannot read %s: %s" % (path, e)) from e
        allowed = {"positions", "kinds", "fluid_ids", "velocities"}
        unknown = sorted(set(arrays) - allowed)
        if unknown:
            raise self.error(key + ".file", "%s: unknown arrays %s (allowed: %s)"
                             % (path, unknown, sorted(allowed)))
        for needed in ("positions", "kinds"):
            if needed not in arrays:
                raise self.error(key + ".file", "%s has no array '%s'" % (path, needed))
        # shapes and kinds of number here, with the file's name; ranges in the binding
        n = arrays["positions"].shape[0] if arrays["positions"].ndim == 2 else -1
        for name_, shape, integer in (("positions", (n, 2), False), ("kinds", (n,), True),
                                      ("fluid_ids", (n,), True), ("velocities", (n, 2), False)):
            if name_ not in arrays:
                continue
            array = arrays[name_]
            wanted = "(n, 2)" if len(shape) == 2 else "(n,)"
            if n < 0 or array.shape != shape:
                raise self.error(key + ".file", "%s: %s must have shape %s%s, got %s"
                                 % (path, name_, wanted, "" if n < 0 or name_ == "positions"
                                    else " with n = %d as positions" % n, array.shape))
            kind = array.dtype.kind
            if (integer and kind not in "iu") or (not integer and kind not in "iuf"):
                raise self.error(key + ".file", "%s: %s must hold %s, got %s"
                                 % (path, name_, "integers" if integer else "real numbers",
                                    array.dtype))
        # fluid particles need their fluid (walls and dummies do without)
        if "fluid_ids" not in arrays and np.any(np.asarray(arrays["kinds"]) == KIND_FLUID):
            raise self.error(key + ".file", "%s has fluid particles (kinds 0) but no array "
                             "'fluid_ids'" % path)
        return arrays


# A scene file lists boxes and settings (a few kB); particles come in particle
# files. Beyond this it is not a scene file, and reading on would only fill memory.
MOST_SCENE_BYTES = 16 << 20


# A coordinate within this many l0 of a whole number of l0 is on the lattice
# (the C library's tolerance in counting a box's cells).
_ON_LATTICE = 1e-6


def lattice_box(box, l0):
    """The box as a scene file builds it at l0: each corner coordinate that is
    not a whole number of l0 moved down onto the lattice from the origin."""
    moved = []
    for c in box:
        cells = c / l0
        # beyond 2^52 cells every float is whole (and the C library refuses
        # such a box): as written
        if not abs(cells) < 2.0 ** 52 or abs(cells - round(cells)) <= _ON_LATTICE:
            moved.append(c)
        else:
            moved.append(math.floor(cells) * l0)
    return moved


def _rounded(values):
    return "[%s]" % ", ".join("%.6g" % v for v in values)


def _not_regular(path):
    """What path is when it is not a regular file (reading a FIFO blocks
    forever, /dev/zero never ends), else None."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return None  # opening it says why
    if stat.S_ISREG(mode):
        return None
    return ("a directory" if stat.S_ISDIR(mode) else "a FIFO" if stat.S_ISFIFO(mode)
            else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else "a socket")


def load(path):
    """Reads and checks a scene file; returns a SceneFile."""
    odd = _not_regular(path)
    if odd:
        raise errors.SceneFileError("%s: cannot read: it is %s, not a regular file" % (path, odd))
    try:
        with open(path, "rb") as f:
            raw = f.read(MOST_SCENE_BYTES + 1)
    except OSError as e:
        raise errors.SceneFileError("%s: cannot read: %s" % (path, e.strerror or e)) from e
    if len(raw) > MOST_SCENE_BYTES:
        raise errors.SceneFileError("%s: larger than %d MiB: not a scene file (particles go "
                                    "in a .npz or .h5 particle file, [[particles]] file = ...)"
                                    % (path, MOST_SCENE_BYTES >> 20))
    try:
        text = raw.decode("utf-8")
        data = tomllib.loads(text)
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise errors.SceneFileError("%s: not valid TOML: %s" % (path, e)) from e
    except RecursionError:
        raise errors.SceneFileError("%s: not a scene file: arrays or tables nested too deep"
                                    % path) from None
    check(path, data)
    return SceneFile(path, text, data)


def check(path, data):
    """Refuses unknown keys, wrong types and impossible values, naming each
    key: every problem of the file's structure at once, then (once that is
    sound) every problem of its values, one line each."""
    problems = []

    def fail(key, reason):
        problems.append("%s: %s: %s" % (path, key, reason))

    def stop_if_any():
        if problems:
            raise errors.SceneFileError("\n".join(problems))

    known = set(SCHEMA) | {"parameters", "options", "effects"}
    for key in data:
        if key in known:
            continue
        # a setting written outside its table: say where it belongs
        try:
            kind = setting_kind(key)
        except Exception:  # no library to ask: no hint
            kind = None
        where = kind and kind + "s"
        if where:
            fail(key, "%s is one of the library's %s: put it under [%s]" % (key, where, where))
        else:
            fail(key, "unknown table%s (known: %s)"
                 % (_did_you_mean(key, known), ", ".join(sorted(known))))
    if "run" not in data:
        fail("run", "missing: a scene needs [run] with l0 and end_time")
    for section in ("parameters", "options", "effects"):
        table = data.get(section, {})
        if not isinstance(table, dict):
            fail(section, "must be a table")
            continue
        for key, value in table.items():
            want_str = section != "parameters"
            if want_str and not isinstance(value, str):
                fail("%s.%s" % (section, key), "must be a string, got %r%s" % (
                    value, _elsewhere(key, "parameter")))
            if not want_str and not _is_number(value):
                fail("%s.%s" % (section, key), "must be a finite number, got %r%s" % (
                    value, _elsewhere(key, "option")))
    for section, (fields, required) in SCHEMA.items():
        if section not in data:
            continue
        entries = data[section]
        if section in ARRAYS_OF_TABLES:
            if not isinstance(entries, list):
                fail(section, "must be an array of tables ([[%s]])" % section)
                continue
            labelled = [("%s[%d]" % (section, i), e) for i, e in enumerate(entries)]
        else:
            if not isinstance(entries, dict):
                fail(section, "must be a table ([%s])" % section)
                continue
            labelled = [(section, entries)]
        for label, entry in labelled:
            if not isinstance(entry, dict):
                fail(label, "must be a table")
                continue
            for key, value in entry.items():
                if key not in fields:
                    fail("%s.%s" % (label, key), "unknown key%s (known: %s)"
                         % (_did_you_mean(key, fields), ", ".join(sorted(fields))))
                else:
                    _check_value(fail, "%s.%s" % (label, key), fields[key], value)
            for key in sorted(required - set(entry)):
                fail("%s.%s" % (label, key), "missing")
    stop_if_any()  # what follows reads the values the structure promised
    run = data["run"]
    for key in ("l0", "end_time"):
        if not run[key] > 0:
            fail("run." + key, "must be > 0, got %r" % run[key])
    if "name" in run and not RUN_NAME.match(run["name"]):
        fail("run.name", "must be 1 to 100 letters, digits, _ - . not starting with . (it "
             "names the folder out/<name>), got %s" % _shorten(run["name"]))
    for key in ("snapshot_every", "series_every"):
        if key in run and run[key] < 0:
            fail("run." + key, "must be >= 0, got %r" % run[key])
    if run["end_time"] > 0:
        schedule_problem = check_schedule(run["end_time"], run.get("snapshot_every", 0.0),
                                          run.get("series_every", 0.0))
        if schedule_problem:
            fail(*schedule_problem)
    for t in run.get("picture_times", []) if run["end_time"] > 0 else []:
        if not 0 <= t <= run["end_time"]:
            fail("run.picture_times", "each time must be in [0, end_time], got %r" % t)
    names = [f["name"] for f in data.get("fluid", [])]
    if len(set(names)) != len(names):
        fail("fluid", "fluid names must be unique, got %s" % names)
    for i, b in enumerate(data.get("fluid_box", [])):
        if b["fluid"] not in names:
            fail("fluid_box[%d].fluid" % i, "no fluid named %r (fluids: %s)" % (b["fluid"], names))
    _check_probes(fail, data.get("probe", []), names)
    stop_if_any()


def check_schedule(end_time, snapshot_every, series_every):
    """(key, reason) when the output schedule up to end_time is too fine to
    keep, else None."""
    for key, every, most, what in (("run.snapshot_every", snapshot_every, MAX_SNAPSHOTS,
                                    "snapshots"),
                                   ("run.series_every", series_every, MAX_SAMPLES, "samples")):
        if every > 0 and end_time / every > most:
            return key, ("%r s gives %.3g %s up to %g s, more than %d; use a coarser interval%s"
                         % (every, end_time / every, what, end_time, most,
                            " or 0 (every step)" if what == "samples" else ""))
    return None


def _did_you_mean(key, known):
    """", did you mean end_time?" for a near miss (as the library says for
    parameters), else ""."""
    close = difflib.get_close_matches(key, sorted(known), n=1, cutoff=0.75)
    return ", did you mean %s?" % close[0] if close else ""


def default_name(path):
    """The run's name when [run] has none: the file's name without .toml,
    made one safe path component."""
    stem = os.path.splitext(os.path.basename(path))[0]
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", stem)[:100].lstrip(".")
    return name or "run"


def _shorten(text, most=60):
    return repr(text) if len(text) <= most else "%r... (%d characters)" % (text[:most], len(text))


def _check_probes(fail, probes, fluid_names):
    seen = set()
    for i, p in enumerate(probes):
        label = "probe[%d]" % i
        if not PROBE_NAME.match(p["name"]):
            fail(label + ".name", "1 to 64 letters, digits, _ - . not starting with ., got %s"
                 % _shorten(p["name"]))
        if p["name"] in seen:
            fail(label + ".name", "another probe is called %r" % p["name"])
        seen.add(p["name"])
        kind = p["type"]
        if kind not in PROBE_KEYS:
            fail(label + ".type", "must be one of %s, got %r%s"
                 % (sorted(PROBE_KEYS), kind, _did_you_mean(str(kind), PROBE_KEYS)))
            continue
        extra = set(p) - {"name", "type"} - PROBE_KEYS[kind]
        if extra:
            fail(label, "keys %s do not apply to a %s probe" % (sorted(extra), kind))
        missing = PROBE_KEYS[kind] - set(p)
        if kind == "front":
            missing -= {"below", "compare", "column_width"}
            if ("compare" in p) != ("column_width" in p):
                fail(label, "compare and column_width go together (the reference's Z = z/a "
                     "needs the column width a)")
            if "compare" in p and p["compare"] not in FRONT_REFERENCES:
                fail(label + ".compare", "must be one of %s, got %r"
                     % (list(FRONT_REFERENCES), p["compare"]))
            if "column_width" in p and not p["column_width"] > 0:
                fail(label + ".column_width", "must be > 0, got %r" % p["column_width"])
        if kind == "elevation":
            missing -= {"half_width"}
            if "half_width" in p and not p["half_width"] > 0:
                fail(label + ".half_width", "must be > 0, got %r" % p["half_width"])
        if missing:
            fail(label, "a %s probe needs %s" % (kind, sorted(missing)))
            continue
        if "fluid" in p and p["fluid"] not in fluid_names:
            fail(label + ".fluid", "no fluid named %r (fluids: %s)" % (p["fluid"], fluid_names))
        if kind == "stat" and p["stat"] not in STAT_KEYS:
            fail(label + ".stat", "must be one of %s, got %r" % (", ".join(STAT_KEYS), p["stat"]))
        if kind == "front" and "below" in p and not p["below"] > 0:
            fail(label + ".below", "must be > 0, got %r" % p["below"])


def _elsewhere(key, kind):
    """A hint when `key` is a known parameter (kind "parameter") or option
    ("option") of the library, which belongs in the other table."""
    try:
        if setting_kind(key) != kind:
            return ""
    except Exception:  # no library to ask: no hint
        return ""
    return (" (%s is a parameter: put it under [parameters])" % key if kind == "parameter"
            else " (%s is an option: put it under [options], as a string)" % key)


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and \
        math.isfinite(value)


def _check_value(fail, key, kind, value):
    if kind == NUMBER and not _is_number(value):
        fail(key, "must be a finite number, got %r" % (value,))
    if kind == STRING and not isinstance(value, str):
        fail(key, "must be a string, got %r" % (value,))
    if kind == BOOL and not isinstance(value, bool):
        fail(key, "must be true or false, got %r" % (value,))
    if kind == TIMES and not (isinstance(value, list) and value and
                              all(map(_is_number, value)) and len(value) <= 12):
        fail(key, "must be a list of 1 to 12 numbers, got %r" % (value,))
    if kind in (BOX, POINT):
        size = 4 if kind == BOX else 2
        if not (isinstance(value, list) and len(value) == size and all(map(_is_number, value))):
            fail(key, "must be %d numbers, got %r" % (size, value))
            return
        if kind == BOX and not (value[2] > value[0] and value[3] > value[1]):
            fail(key, "box [x0, y0, x1, y1] needs x1 > x0 and y1 > y0, got %r" % (value,))
