"""The experiments of Jiang et al. (002 Sec. V-A) as functions: seeded starts and one summarised run.

Sec. V-A places ``|F_d|`` robots "randomly and uniformly in the working
plane" (a 15 m x 15 m square for n = 50..300), moves them at 10 cm/s, and
reports the formation quality and the total distance; it compares with Song's
algorithm [16] (001).  :func:`uniform_start` draws such a start (seeded; a
minimum separation keeps robots distinct, Def. 1); :func:`run_sec5` runs one
and returns its figures; ``benchmarks/jiang/bench_jiang.py`` tables them
(docs/jiang.md).

>>> s = uniform_start(20, 0)
>>> s.n, bool((s.poses[:, :2] >= 0).all() and (s.poses[:, :2] <= 15).all())
(20, True)
"""

from __future__ import annotations

from swarmproof.models.trace import InitialConfiguration

__all__ = ["AREA", "ROBOT_RADIUS", "uniform_start", "shape_key", "run_sec5"]

#: 002 Sec. V-A: "a square of 15m x 15m" for n = 50..300.
AREA = 15.0
#: 002 Sec. V-B: the PiBots are cylinders of radius 7 cm (the collision figure uses it).
ROBOT_RADIUS = 0.07


def uniform_start(n: int, seed: int, *, area: float = AREA, min_separation: float = 2 * ROBOT_RADIUS
                  ) -> InitialConfiguration:
    """``n`` robots uniformly at random in ``[0, area]^2``, at least ``min_separation`` apart
    (:func:`~swarmproof.reference_impl.initial.random_uniform`; campaign cells with
    ``start: {uniform: 15, separation: 0.14}`` draw the same starts)."""
    from swarmproof.reference_impl.initial import random_uniform

    return random_uniform(n, seed, side=area, min_separation=min_separation)


def shape_key(pattern, poses) -> str:
    """The formation up to translation, as a short digest: the positions with Sec. V-A's origin
    ("the leftmost point in the first line", the lowest row within ``tol``) subtracted, on a grid
    of 10 ``tol``.  Two runs with one key stand in the same formation; no desired formation fixed
    before the runs can align at 1 with two runs of different keys (docs/jiang.md, "Fig. 7a's
    quality").

    >>> from swarmproof.models.repeating_pattern import load_pattern
    >>> p = load_pattern("square-dots")
    >>> shape_key(p, p.formation(4)) == shape_key(p, p.formation(4) + (3.0, 2.0))
    True
    >>> shape_key(p, p.formation(4)) == shape_key(p, p.formation(5)[[0, 1, 2, 4]])
    False
    """
    import hashlib

    import numpy as np

    xy = np.asarray(poses, dtype=float).reshape(len(poses), -1)[:, :2]
    low = xy[xy[:, 1] <= xy[:, 1].min() + pattern.tol]
    g = max(pattern.tol, 1e-12) * 10
    rel = np.rint((xy - low[np.argmin(low[:, 0])]) / g).astype(np.int64)
    rel = rel[np.lexsort((rel[:, 1], rel[:, 0]))]
    return hashlib.sha1(rel.tobytes()).hexdigest()[:12]


def run_sec5(algorithm_name: str, pattern, n: int, seed: int, *, start: InitialConfiguration | None = None,
             range: float = 1.5) -> dict:
    """One run of ``algorithm_name`` toward ``pattern`` from :func:`uniform_start` (or ``start``),
    checked as ``swarmproof simulate`` checks it (:func:`~swarmproof.checkers.runs.run_and_check`):
    status, steps, total distance, minimum separation, the collisions at radius 7 cm, and the
    pattern's figures (epsilon of Def. 9, its parts, and Sec. V-A's alignment), and the final
    formation's :func:`shape_key`."""
    from swarmproof.checkers.runs import run_and_check

    init = start if start is not None else uniform_start(n, seed)
    checked = run_and_check(algorithm_name, pattern, seed=seed, initial=init, phi=range)
    doc = checked.doc
    m, sep = doc["metrics"], doc["min_separation"]
    return {"n": n, "seed": seed, "status": doc["status"], "steps": doc["steps"],
            "total_distance": doc["total_distance"], "min_separation": sep,
            "collides": bool(sep is not None and sep < 2 * ROBOT_RADIUS),
            "epsilon": m["epsilon"], "epsilon_exact": m["epsilon_exact"], "gamma": m["basic_fulfillment_exact"],
            "delta": m["assembling_fulfillment_exact"], "method": m["method"], "alignment": m["alignment"],
            "shape": shape_key(pattern, checked.result.final_poses)}
