"""The versions a result was made with: swarmproof, Python, numpy and z3.

Baselines and counterexample files record them (DESIGN.md section 5,
"Baselines"), so that a verdict that changes between two machines can be
traced to a changed library rather than a changed algorithm.  z3 is recorded because the
proofs' budgets are counted in z3's resource units (``rlimit``), which change between z3
releases (docs/proofs.md "Budgets").

>>> sorted(tool_versions())
['numpy', 'python', 'swarmproof', 'z3']
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
    """``{"swarmproof": ..., "python": ..., "numpy": ..., "z3": ...}`` of this process (z3: the
    installed z3-solver distribution's version, read without importing z3)."""
    import numpy

    return {"swarmproof": _distribution("swarmproof"), "python": platform.python_version(),
            "numpy": numpy.__version__, "z3": _distribution("z3-solver")}


def _distribution(name: str) -> str:
    """The installed distribution's version, ``"unknown"`` when it is not installed (swarmproof
    run from a source tree)."""
    try:
        from importlib.metadata import PackageNotFoundError, version
    except ImportError:  # pragma: no cover
        return "unknown"
    try:
        return version(name)
    except PackageNotFoundError:  # pragma: no cover - running from a source tree, not installed
        return "unknown"
