"""One module per subcommand: ``NAME``, ``HELP``, ``add_arguments(parser)``, ``run(args) -> int``.

Shared helpers for the modules live here.
"""

from __future__ import annotations

import sys
from typing import Any

from swarmproof.models.fileio import dumps_json


def emit_json(obj: Any) -> None:
    """Print one deterministic JSON document on stdout (and nothing else there)."""
    sys.stdout.write(dumps_json(obj))
    sys.stdout.flush()


def human(args, *lines: str) -> None:
    """Print human-readable lines: stdout normally, stderr when ``--json`` is on."""
    stream = sys.stderr if getattr(args, "json", False) else sys.stdout
    for line in lines:
        print(line, file=stream)
