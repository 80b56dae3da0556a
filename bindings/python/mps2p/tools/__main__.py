"""python -m mps2p.tools: the mps2p command."""
import sys

from .cli import main

sys.exit(main())
