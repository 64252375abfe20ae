"""Lee & Chong: decentralized formation control for small teams of anonymous robots.

Lee & Chong, "Decentralized formation control for small-scale robot teams with anonymity",
Mechatronics (seed 003_8f3001202a798af8.txt; docs/references.md, docs/leechong.md).

The package holds everything about this paper:

* :mod:`.algorithm` -- the reference implementation: common origin, leader and direction,
  ID allocation (Algorithm 1), leader- and neighbor-referenced control (Algorithms 2-4),
  flocking, switching, failures (registered as ``leechong-leader``, ``leechong-neighbor``
  and their variants);
* :mod:`.checks` -- exact, exhaustive checks of Algorithm 1's ID formula and Algorithm 4's
  neighbor links (verify's ``formulas`` rows);
* :mod:`.patterns_check` -- every line pattern's targets are distinct (exact arithmetic).

The line patterns themselves (Table 1) are a target kind every algorithm shares:
:mod:`swarmproof.models.line_patterns`.
"""

from .algorithm import *  # noqa: F401,F403
from .algorithm import __all__  # noqa: F401
