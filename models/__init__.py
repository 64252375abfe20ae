"""The mathematics and data of swarmproof: SE(2), lattice graphs, file formats.

May import numpy, scipy and networkx only (DESIGN.md section 1).
"""

from .errors import (AssumptionError, InputFileError, ProtocolError, SwarmproofError,
                     UsageError)
from .lattice import Edge, LatticeGraph
from .se2 import SE2, angle_diff, wrap_angle

__all__ = [
    "SE2", "wrap_angle", "angle_diff", "Edge", "LatticeGraph",
    "SwarmproofError", "UsageError", "InputFileError", "AssumptionError", "ProtocolError",
]
