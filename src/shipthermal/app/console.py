"""Where the command line's messages go, and its exit codes.

Results go to stdout; progress, notes and errors to stderr (:class:`Console`). Exit codes:
0 success, 2 user error, 1 internal failure, 130 interrupted (Ctrl-C), 143 terminated
(SIGTERM, raised as :class:`Terminated` so a run directory records it as interrupted).
"""

from __future__ import annotations

import sys

EXIT_OK, EXIT_FAILURE, EXIT_USER, EXIT_INTERRUPTED, EXIT_TERMINATED = 0, 1, 2, 130, 143


class Terminated(KeyboardInterrupt):
    """SIGTERM, handled like Ctrl-C (the run directory records 'interrupted')."""


class Console:
    """Where messages go: results to stdout; progress and notes to stderr.

    ``quiet``: no progress bars and no notes (results and errors only); ``verbose``: stage
    details and tracebacks of internal failures.
    """

    def __init__(self, quiet: bool = False, verbose: bool = False):
        self.quiet = quiet
        self.verbose = verbose and not quiet
        self.progress = not quiet

    def info(self, msg: str) -> None:
        if not self.quiet:
            print(msg, file=sys.stderr, flush=True)

    def debug(self, msg: str) -> None:
        if self.verbose:
            print(f"  {msg}", file=sys.stderr, flush=True)

    def out(self, msg: str) -> None:
        print(msg, flush=True)

    def error(self, msg: str) -> None:
        print(msg, file=sys.stderr, flush=True)
