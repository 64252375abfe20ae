"""Wang & Rubenstein 2020: shape formation in homogeneous swarms using local task swapping.

Wang & Rubenstein, "Shape Formation in Homogeneous Swarms Using Local Task Swapping",
IEEE T-RO 2020 (seed 004_004a3703645971e3.txt; docs/references.md, docs/wang2020.md).

The package holds everything about this paper:

* :mod:`.algorithm` -- the reference implementation: grid waypoints, the motion planner
  (Algorithm 2), broadcast (Algorithm 3), the goal manager with its 2-way handshake
  (Algorithm 4), shape-complete detection (registered as ``wang2020``);
* :mod:`.fast` -- the vectorised path (``simulate --vectorised``), bit-identical to the
  reference;
* :mod:`.lemmas` -- the z3 encodings of Theorems IV-A.1/IV-A.2 and the planner's lemmas;
* :mod:`.monitors` -- the runtime monitors of those lemmas' premises on the grid;
* :mod:`.experiments` -- Sec. V's instances (Figs. 9-12), the centralized comparison.

The shapes and goal sets are a target kind every algorithm shares: :mod:`swarmproof.models.shapes`.
"""

from . import monitors as _monitors  # noqa: F401  (registers this paper's premise monitors)
from . import properties as _properties  # noqa: F401  (registers this paper's own properties)
from .algorithm import *  # noqa: F401,F403
from .algorithm import __all__  # noqa: F401
