"""What is built on the binding (mps2p): scene files (scenefile), a run of
one with its results, series and pictures (run, pictures), the
accuracy-cost study (study), the hard cases' stability checks (stability),
the example scenes (examples) and the mps2p command (cli)."""
from .examples import example_names, example_path

__all__ = ["example_names", "example_path"]
