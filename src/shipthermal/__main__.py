"""python -m shipthermal: the command line (shipthermal.cli)."""

import sys

from .cli import main

sys.exit(main())
