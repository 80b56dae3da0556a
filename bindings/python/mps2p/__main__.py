"""python -m mps2p: the mps2p command (mps2p.tools.cli)."""
import sys

from .tools.cli import main

sys.exit(main())
