"""Property tests of the scene-file loader (issue 7): any TOML document,
and any value in any key of a valid scene, either loads or raises
mps2p.SceneFileError. Never another exception type."""
import math
import os

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings, strategies as st  # noqa: E402

import mps2p  # noqa: E402

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    tomllib = None

SETTINGS = settings(max_examples=150, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])

HERE = os.path.dirname(os.path.abspath(__file__))
VALID_PATH = os.path.join(HERE, "..", "..", "examples", "scenes", "dam_break.toml")
with open(VALID_PATH, encoding="utf-8") as f:
    VALID = f.read()


def leaf_paths(node, prefix=()):
    """Every key path to a value of the document (list items by index)."""
    if isinstance(node, dict):
        items = node.items()
    elif isinstance(node, list):
        items = enumerate(node)
    else:
        return [prefix]
    paths = [prefix] if prefix else []
    for key, value in items:
        paths += leaf_paths(value, prefix + (key,))
    return paths


KEYS = leaf_paths(tomllib.loads(VALID)) if tomllib else [("run", "l0")]


def must_load_or_refuse(text, tmp_path):
    """Loading (reading and checking) and building the scene (the C calls)
    either work or raise SceneFileError."""
    from mps2p.tools import scenefile
    path = tmp_path / "scene.toml"
    path.write_bytes(text.encode("utf-8", errors="surrogatepass"))
    try:
        scene = scenefile.load(str(path)).build()
    except mps2p.SceneFileError:
        return
    scene.close()


floats = st.one_of(st.floats(allow_nan=True, allow_infinity=True),
                   st.sampled_from([0.0, -0.0, 1e308, -1e308, 5e-324, 1e-300, 3.0e9]))
scalars = st.one_of(floats, st.integers(min_value=-2**70, max_value=2**70), st.booleans(),
                    st.text(max_size=12))
values = st.recursive(scalars, lambda inner: st.one_of(
    st.lists(inner, max_size=5), st.dictionaries(st.text(max_size=8), inner, max_size=4)),
    max_leaves=12)


def toml_value(value):
    """value as TOML text (nan and inf included, as TOML allows)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return '"' + "".join(c if c.isalnum() or c in " _-." else "\\u%04x" % ord(c)
                             for c in value if ord(c) < 0x10000 and not 0xD800 <= ord(c) <= 0xDFFF) + '"'
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return "{" + ", ".join('"%s" = %s' % (toml_value(k)[1:-1], toml_value(v))
                           for k, v in value.items()) + "}"


@SETTINGS
@given(text=st.text(max_size=300))
def test_any_text(text, tmp_path_factory):
    must_load_or_refuse(text, tmp_path_factory.mktemp("scene"))


@SETTINGS
@given(key=st.sampled_from(KEYS), value=values)
def test_any_value_in_a_valid_scene(key, value, tmp_path_factory):
    """A valid scene with one key's value replaced by anything."""
    if tomllib is None:
        pytest.skip("needs tomllib")
    document = tomllib.loads(VALID)
    *parents, last = key
    node = document
    for part in parents:
        node = node[part]
    node[last] = value
    must_load_or_refuse(dump(document), tmp_path_factory.mktemp("scene"))


@SETTINGS
@given(extra_key=st.text(min_size=1, max_size=10), value=values)
def test_unknown_keys(extra_key, value, tmp_path_factory):
    must_load_or_refuse(VALID + "\n%s = %s\n" % (toml_value(extra_key), toml_value(value)),
                        tmp_path_factory.mktemp("scene"))


def dump(document):
    """A small TOML writer for the scene's shapes (tables, arrays of tables)."""
    lines, tables = [], []
    for key, value in document.items():
        if isinstance(value, dict):
            tables.append((key, value))
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            tables.append((key, value))
        else:
            lines.append("%s = %s" % (toml_value(key), toml_value(value)))
    for key, value in tables:
        if isinstance(value, list):
            for item in value:
                lines.append("[[%s]]" % toml_value(key))
                lines += ["%s = %s" % (toml_value(k), toml_value(v)) for k, v in item.items()]
        else:
            sub = [(k, v) for k, v in value.items() if isinstance(v, dict)]
            lines.append("[%s]" % toml_value(key))
            lines += ["%s = %s" % (toml_value(k), toml_value(v))
                      for k, v in value.items() if not isinstance(v, dict)]
            for k, v in sub:
                lines.append("[%s.%s]" % (toml_value(key), toml_value(k)))
                lines += ["%s = %s" % (toml_value(kk), toml_value(vv)) for kk, vv in v.items()]
    return "\n".join(lines) + "\n"
