"""Metrics of a run: fulfillment ratio Q, non-fulfillment ratio, execution time, distance, separation.

* :func:`fulfillment_ratio` -- 001 Sec. III-C-2: ``Q = (1/n) sum_i N_i / E_i``
  where ``N_i`` is the number of neighbors of robot i (robots strictly
  closer than phi) when it is static and ``E_i`` the number of out-edges of
  its role vertex.  Q needs a role per robot: by default the role function
  :func:`~swarmproof.invariants.satisfaction.satisfies_lattice` finds, so Q
  is None when the configuration does not satisfy the lattice (roles are
  then undefined).  A role with no out-edges contributes 1 if the robot
  has no neighbors (nothing missing), else the configuration would not
  satisfy the lattice.
* :func:`non_fulfillment_ratio` -- 000 Eq. 3: ``(1/n) sum_i (E_i - N_i) / E_i``,
  that is ``1 - Q`` for the same roles.
* :func:`execution_steps` -- 001 Def. 6 on a trace (re-exported from
  :mod:`~swarmproof.invariants.termination`).
* :func:`total_distance` -- the sum over robots and steps of the distance
  each robot's position moved (turning in place adds nothing).
* :func:`min_separation` -- the smallest distance between two present robots
  at any recorded step (step ends only; the explorer's collision property
  checks whole segments).

References
----------
001_7a4e517b856331bc.txt (Song & O'Kane 2016), Sec. III-C (Defs. 5-6, Q).
000_3ad33c5b62f11d5f.txt (Song & O'Kane 2014), Sec. III-C, Eq. 3.

Examples
--------
>>> from swarmproof.models.lattice import LatticeGraph
>>> from swarmproof.models.se2 import SE2
>>> sq = LatticeGraph("square", ["A"], [("A", "A", SE2(1, 0, 0)), ("A", "A", SE2(0, 1, 0)),
...                                     ("A", "A", SE2(-1, 0, 0)), ("A", "A", SE2(0, -1, 0))])
>>> four = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]      # 001 Fig. 8 right: Q = 0.5
>>> fulfillment_ratio([0, 1, 2, 3], four, sq, 1.2)
0.5
>>> non_fulfillment_ratio([0, 1, 2, 3], four, sq, 1.2)
0.5
>>> fulfillment_ratio([0, 1], [[0, 0, 0], [0.5, 0, 0]], sq, 1.2) is None
True
>>> min_separation(np.array([four], dtype=float))
1.0
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

# Q and the non-fulfillment ratio are a lattice target's own figures, so they live in models/
# (a lattice graph is a Target, models/targets.py); re-exported here.
from swarmproof.models.satisfaction import fulfillment_ratio, neighbor_counts, non_fulfillment_ratio

from .termination import execution_steps

__all__ = ["fulfillment_ratio", "non_fulfillment_ratio", "execution_steps", "total_distance",
           "min_separation", "neighbor_counts"]


def total_distance(trace) -> float:
    """Sum of the straight distances every robot's position moved, over all steps."""
    p = trace.poses
    if len(p) < 2:
        return 0.0
    d = np.diff(p[:, :, :2], axis=0)
    step = np.hypot(d[..., 0], d[..., 1])
    if trace.present is not None:
        step = step * (trace.present[1:] & trace.present[:-1])
    return float(step.sum())


def min_separation(trace_or_poses) -> float | None:
    """Smallest pairwise distance at any recorded step; None with fewer than two robots.

    Accepts a Trace or a ``(T+1, n, 3)`` array.  Steps identical to the previous are skipped.
    """
    if hasattr(trace_or_poses, "poses"):
        p, trace = trace_or_poses.poses, trace_or_poses
    else:
        p, trace = np.asarray(trace_or_poses, dtype=float), None
    best = None
    prev = None
    for t in range(len(p)):
        mask = trace.present_at(t) if trace is not None else np.ones(p.shape[1], dtype=bool)
        xy = p[t][mask, :2]
        if len(xy) < 2 or (prev is not None and np.array_equal(xy, prev)):
            continue
        prev = xy
        d, _ = cKDTree(xy).query(xy, k=2)
        m = float(d[:, 1].min())
        best = m if best is None else min(best, m)
    return best
