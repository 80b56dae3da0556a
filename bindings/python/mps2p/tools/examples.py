"""The example scenes shipped inside the package (mps2p/tools/scenes/*.toml):
`mps2p examples` lists them and `mps2p run NAME` runs one by name."""
import difflib
import os

SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes")


def example_names():
    """The example scenes' names, sorted (dam_break, hydrostatic, ...)."""
    return sorted(name[:-5] for name in os.listdir(SCENES) if name.endswith(".toml"))


def example_path(name):
    """The path of the example scene `name` (with or without .toml);
    KeyError, listing the names, when there is none."""
    if not isinstance(name, str):
        raise TypeError("example name must be a str, got %s" % type(name).__name__)
    stem = name[:-5] if name.endswith(".toml") else name
    if stem not in example_names():
        raise KeyError("no example scene %r (examples: %s)" % (name, ", ".join(example_names())))
    return os.path.join(SCENES, stem + ".toml")


def resolve_scene(argument):
    """A scene argument of the command: an existing file, or a path (whose
    reading then fails with the file's name), as given; else the example of
    that name; else KeyError, saying it is neither and listing the examples."""
    if os.path.exists(argument) or os.sep in argument:
        return argument
    try:
        return example_path(argument)
    except KeyError:
        what = ("no such file, and not an example scene" if argument.endswith(".toml")
                else "neither a scene file nor an example scene")
        stem = argument[:-5] if argument.endswith(".toml") else argument
        close = difflib.get_close_matches(stem, example_names(), n=1, cutoff=0.75)
        hint = "; did you mean %s?" % close[0] if close else ""
        raise KeyError("%s: %s%s (examples: %s; 'mps2p examples' describes them)"
                       % (argument, what, hint, ", ".join(example_names()))) from None


__all__ = ["example_names", "example_path", "resolve_scene", "SCENES"]
