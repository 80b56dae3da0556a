#!/usr/bin/env python3
"""atheris (libFuzzer for Python) target: TOML scene files through the code
path of `mps2p run` (mps2p.tools.run): scenefile.load() reads and checks the bytes
(or, for inputs starting with a zero byte, the example dam break with values
replaced and keys added as the rest of the bytes say),
make_solver() builds the scene and the solver in the C library; a small
solver then takes two steps. Either a file loads and runs, or load and
make_solver raise mps2p.SceneFileError (a step may raise DivergedError or
SolveError); any other exception, and any crash in the C library, is a bug.

    python3 tests/fuzz/fuzz_scenefile.py [libFuzzer flags] [corpus dirs]

Without corpus directories it fuzzes a scratch copy of
tests/fuzz/corpus/scenefile (the example scenes); FUZZ_MERGE=1 merges what
adds coverage back into it. The library is MPS2P_LIBRARY, else build-rel's
(scripts/test-reliability.sh builds it). Valid but huge scenes are kept
small: memory_limit is lowered to 10 MB (a scene of 2e5 particles, a solver
of 1e4), as fuzz_scene.c skips big boxes."""
import atexit
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
os.environ.setdefault("MPS2P_LIBRARY", os.path.join(ROOT, "build-rel", "lib", "libmps2p.so.0"))

import atheris  # noqa: E402

with atheris.instrument_imports(include=["mps2p"]):
    import mps2p  # noqa: E402
    from mps2p.tools import scenefile  # noqa: E402

MEMORY_LIMIT = 1e7
MAX_STEPPED = 2000
SCRATCH = tempfile.mkdtemp(prefix="mps2p-fuzz-scenefile-")
PATH = os.path.join(SCRATCH, "scene.toml")
atexit.register(shutil.rmtree, SCRATCH, True)


try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

with open(os.path.join(ROOT, "examples", "scenes", "dam_break.toml"), "rb") as f:
    VALID = tomllib.load(f)
VALID["run"]["l0"] = 0.02  # small enough to step
AWKWARD = [0.0, -0.0, 1.0, -1.0, 0.01, 0.02, 0.1, 0.5, 1e300, -1e300, 1e-300, 5e-324,
           1.7976931348623157e308, float("nan"), float("inf"), float("-inf"), 1e9, 3e9,
           2**63, -2**63, 2**70, 1e11]


def toml_value(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if value != value:
            return "nan"
        if value in (float("inf"), float("-inf")):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise TypeError(value)


def toml_text(document):
    """TOML for a scene document (tables of scalars, arrays of tables)."""
    lines = []
    for name, table in document.items():
        for entry in table if isinstance(table, list) else [table]:
            lines.append(("[[%s]]" if isinstance(table, list) else "[%s]") % name)
            lines += ["%s = %s" % (key, toml_value(value)) for key, value in entry.items()]
    return "\n".join(lines) + "\n"


def fuzzed_value(fdp):
    kind = fdp.ConsumeIntInRange(0, 6)
    if kind == 0:
        return AWKWARD[fdp.ConsumeIntInRange(0, len(AWKWARD) - 1)]
    if kind == 1:
        return fdp.ConsumeRegularFloat()
    if kind == 2:
        return fdp.ConsumeIntInRange(-2**40, 2**40)
    if kind == 3:
        return fdp.ConsumeUnicodeNoSurrogates(fdp.ConsumeIntInRange(0, 12))
    if kind == 4:
        return fdp.ConsumeBool()
    if kind == 5:
        return [fdp.ConsumeRegularFloat() for _ in range(fdp.ConsumeIntInRange(0, 5))]
    return fdp.ConsumeFloatInRange(-0.5, 1.0)


def mutated_scene(fdp):
    """The valid dam break with some values replaced and keys added: reaches
    the C library far more often than mutated bytes, which are rarely TOML."""
    import copy
    document = copy.deepcopy(VALID)
    tables = [(name, entry) for name, table in document.items()
              for entry in (table if isinstance(table, list) else [table])]
    for _ in range(fdp.ConsumeIntInRange(1, 4)):
        name, entry = tables[fdp.ConsumeIntInRange(0, len(tables) - 1)]
        keys = sorted(entry)
        if keys and fdp.ConsumeBool():
            key = keys[fdp.ConsumeIntInRange(0, len(keys) - 1)]
        else:  # a parameter or option by name, or a key of its own
            params = sorted(mps2p.param_info())
            key = params[fdp.ConsumeIntInRange(0, len(params) - 1)] if fdp.ConsumeBool() \
                else fdp.ConsumeUnicodeNoSurrogates(6) or "x"
            if fdp.ConsumeBool():
                entry = document.setdefault("parameters", {})
        value = fuzzed_value(fdp)
        old = entry.get(key)
        if isinstance(old, list) and fdp.ConsumeBool():  # some corners of a box
            value = [fuzzed_value(fdp) if fdp.ConsumeBool() else v for v in old]
        entry[key] = value
    try:
        return toml_text(document).encode("utf-8")
    except (TypeError, UnicodeEncodeError):
        return b""


def test_one_input(data):
    if data[:1] == b"\x00" and len(data) > 1:  # a mutated valid scene
        data = mutated_scene(atheris.FuzzedDataProvider(data[1:]))
    with open(PATH, "wb") as f:
        f.write(data)
    try:
        scene_file = scenefile.load(PATH)
        parameters = scene_file.data.setdefault("parameters", {})
        asked = parameters.get("memory_limit", 0)
        if not (isinstance(asked, (int, float)) and 0 < asked < MEMORY_LIMIT):
            parameters["memory_limit"] = MEMORY_LIMIT
        solver = scene_file.make_solver()
    except mps2p.SceneFileError:
        return
    try:
        if solver.particle_count <= MAX_STEPPED:
            for _ in range(2):
                solver.step()
    except (mps2p.DivergedError, mps2p.SolveError):
        pass
    finally:
        solver.close()


def main():
    args = sys.argv[1:]
    if not any(a.startswith("-artifact_prefix=") for a in args):
        crashes = tempfile.mkdtemp(prefix="mps2p-fuzz-scenefile-crashes-")
        args.append("-artifact_prefix=%s/" % crashes)
    corpus_dirs = [a for a in args if not a.startswith("-")]
    seeds = os.path.join(HERE, "corpus", "scenefile")
    work = None
    if not corpus_dirs:
        work = tempfile.mkdtemp(prefix="mps2p-fuzz-scenefile-corpus-")
        for name in os.listdir(seeds):
            shutil.copy(os.path.join(seeds, name), work)
        args.append(work)
    try:
        if os.environ.get("FUZZ_MERGE") == "1" and work:
            # run, then merge in a child: atheris.Fuzz() does not return
            flags = [a for a in args if a.startswith("-")]
            run = subprocess.run([sys.executable, __file__] + flags + [work])
            subprocess.run([sys.executable, __file__, "-merge=1", seeds, work],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            sys.exit(run.returncode)
        atheris.Setup([sys.argv[0]] + args, test_one_input)
        atheris.Fuzz()
    finally:
        if work:
            shutil.rmtree(work, ignore_errors=True)
        shutil.rmtree(SCRATCH, ignore_errors=True)


if __name__ == "__main__":
    main()
