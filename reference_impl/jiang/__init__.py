"""Jiang et al.: decentralized repeating pattern formation by multiple robots.

Jiang, Liang, Cao, Wang, Chen, Liang, "Decentralized Algorithm for Repeating Pattern
Formation by Multiple Robots" (seed 002_297e720101d69cd2.txt; docs/references.md,
docs/jiang.md).

The package holds the reference implementation (:mod:`.algorithm`: Algorithm 1's basic
pattern generation and Algorithm 2's layered assembling; registered as ``jiang`` and the
printed Algorithm 2 as ``jiang-literal``).  The formation quality of Defs. 3-10 is a target
kind every algorithm shares (:mod:`swarmproof.models.formation_quality`); Sec. V-A's
experiments judge runs and live in ``benchmarks/jiang/``.
"""

from .algorithm import *  # noqa: F401,F403
from .algorithm import __all__  # noqa: F401
