"""Lattice satisfaction (001 Def. 2): re-exported from :mod:`swarmproof.models.satisfaction`.

The decision procedure lives in models/ because a lattice graph is a target
(:mod:`swarmproof.models.targets`) and judges its own satisfaction; this module
keeps the invariants' import path working.
"""

from swarmproof.models.satisfaction import (DEFAULT_SAT_ANG_TOL, DEFAULT_SAT_POS_TOL, SatisfactionResult,
                                            satisfies_lattice)

__all__ = ["SatisfactionResult", "satisfies_lattice", "DEFAULT_SAT_POS_TOL", "DEFAULT_SAT_ANG_TOL",
           "judged_robots"]


def judged_robots(algorithm, result):
    """``(ids, poses)`` of the final robots the target is judged on: every present robot, less those
    the algorithm's ``out_of_formation(state)`` names (003 Sec. 3.5: a failed robot stands where it
    stopped, and the survivors re-form the pattern without it)."""
    ids, poses = result.final_ids, result.final_poses
    out = getattr(algorithm, "out_of_formation", None)
    if not callable(out):
        return ids, poses
    import numpy as np

    keep = np.array([not out(s) for s in result.final_states], dtype=bool)
    return ids[keep], poses[keep]
