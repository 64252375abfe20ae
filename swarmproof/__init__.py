"""swarmproof: machine-checked properties of decentralized multi-robot formation algorithms.

The public facade (DESIGN.md section 1).  Import from here or from the
subpackages ``swarmproof.models``, ``swarmproof.reference_impl``,
``swarmproof.invariants`` and ``swarmproof.checkers``.
"""

__version__ = "0.1.0"

from swarmproof.models import (SE2, AssumptionError, Edge, InputFileError, LatticeGraph,
                               SwarmproofError, UsageError)
from swarmproof.models.verdict import Verdict

__all__ = [
    "__version__", "SE2", "Edge", "LatticeGraph", "Verdict",
    "SwarmproofError", "UsageError", "InputFileError", "AssumptionError",
]
