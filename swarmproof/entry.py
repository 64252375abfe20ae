"""The ``swarmproof`` console script's entry point: Ctrl-C is handled from the first moment.

The package's ``__init__`` imports nothing heavy, and this module imports only :mod:`sys`, so a
Ctrl-C while numpy, scipy, z3 and the commands load (the first half second of every command) ends
the command as one pressed later does: exit 130 and one line, never a traceback (issue 29 item 6;
the review of issue 34 found the window).
"""

from __future__ import annotations

import os
import sys

__all__ = ["main"]

INTERRUPTED = "swarmproof: interrupted (Ctrl-C); no report was written"


def main() -> None:  # pragma: no cover - exercised through the console script (tests/cli/test_interrupt.py)
    try:
        from swarmproof.cli import main as cli_main

        code = cli_main()
    except KeyboardInterrupt:
        # interrupted while the modules loaded (main() handles a Ctrl-C once the command runs): every
        # `finally` has run by now; the interpreter's own teardown is skipped, since objects cut off
        # half-built by the interrupt print "Exception ignored in ..." tracebacks when collected
        print(INTERRUPTED, file=sys.stderr)
        sys.stderr.flush()
        sys.stdout.flush()
        os._exit(130)
    sys.exit(code)
