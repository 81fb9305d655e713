"""python -m shipthermal: the command line (shipthermal.app.cli)."""

import sys

from .app.cli import main

sys.exit(main())
