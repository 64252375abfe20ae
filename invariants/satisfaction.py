"""Lattice satisfaction (001 Def. 2): re-exported from :mod:`swarmproof.models.satisfaction`.

The decision procedure lives in models/ because a lattice graph is a target
(:mod:`swarmproof.models.targets`) and judges its own satisfaction; this module
keeps the invariants' import path working.
"""

from swarmproof.models.satisfaction import (DEFAULT_SAT_ANG_TOL, DEFAULT_SAT_POS_TOL, SatisfactionResult,
                                            satisfies_lattice)

__all__ = ["SatisfactionResult", "satisfies_lattice", "DEFAULT_SAT_POS_TOL", "DEFAULT_SAT_ANG_TOL",
           "judged_robots"]


def judged_robots(algorithm, result, target, params=None):
    """``(target, ids, poses)`` a run's final configuration is judged by: every present robot, less
    those the algorithm's ``out_of_formation(state)`` names (003 Sec. 3.5: a failed robot stands
    where it stopped, and the survivors re-form the pattern without it), against the target as the
    algorithm's ``judging_target(target, n_start, params)`` restates it (003: the last pattern of a
    switching sequence, with the span of the start kept, so fewer robots stand at a wider
    interval), or the target itself."""
    ids, poses = result.final_ids, result.final_poses
    restate = getattr(algorithm, "judging_target", None)
    if callable(restate):
        target = restate(target, int(result.trace.n), params)
    out = getattr(algorithm, "out_of_formation", None)
    if not callable(out):
        return target, ids, poses
    import numpy as np

    keep = np.array([not out(s) for s in result.final_states], dtype=bool)
    return target, ids[keep], poses[keep]
