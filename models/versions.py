"""The versions a result was made with: swarmproof, Python and numpy.

Baselines and counterexample files record them (DESIGN.md section 5,
"Baselines"), so that a verdict that changes between two machines can be
traced to a changed library rather than a changed algorithm.

>>> sorted(tool_versions())
['numpy', 'python', 'swarmproof']
"""

from __future__ import annotations

import platform

__all__ = ["tool_versions", "DEFAULT_READING"]

#: The reading version of an algorithm that declares none, and of a counterexample file or a
#: baseline that records none: they were written before readings were versioned (swarmproof
#: 0.1.0), when every bundled algorithm was at its first reading, ``"1"``.  (An algorithm's
#: reading is bumped whenever its behaviour changes on purpose: reference_impl/protocol.py.)
DEFAULT_READING = "1"


def tool_versions() -> dict[str, str]:
    """``{"swarmproof": ..., "python": ..., "numpy": ...}`` of this process."""
    import numpy

    try:
        from importlib.metadata import PackageNotFoundError, version

        try:
            own = version("swarmproof")
        except PackageNotFoundError:  # pragma: no cover - running from a source tree, not installed
            own = "unknown"
    except ImportError:  # pragma: no cover
        own = "unknown"
    return {"swarmproof": own, "python": platform.python_version(), "numpy": numpy.__version__}
