"""Lattice satisfaction (001 Def. 2): re-exported from :mod:`swarmproof.models.satisfaction`.

The decision procedure lives in models/ because a lattice graph is a target
(:mod:`swarmproof.models.targets`) and judges its own satisfaction; this module
keeps the invariants' import path working.
"""

from swarmproof.models.satisfaction import (DEFAULT_SAT_ANG_TOL, DEFAULT_SAT_POS_TOL, SatisfactionResult,
                                            satisfies_lattice)

__all__ = ["SatisfactionResult", "satisfies_lattice", "DEFAULT_SAT_POS_TOL", "DEFAULT_SAT_ANG_TOL"]
