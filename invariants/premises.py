"""Runtime monitors of the proof suite's premises (issue 5, second part).

The z3 lemmas (:mod:`swarmproof.checkers.proofs`, docs/proofs.md) are about
mathematics; these pure checks over a trace say whether a run met the
lemmas' premises at every step, which is what ties the proofs to the code.
Each failure names its lemma.

* :func:`step_bounded` — no robot moves more than ``v*dt`` in a step (the
  "moves at most v dt" premise of ``bounded_range``, ``nclb_link_kept`` and
  ``spanning_tree_kept``).
* :func:`parents_in_bounded_ranges` — every robot that moves in a step ends
  inside the bounded range (001 Def. 8: disc of radius ``phi - v*dt``) of
  each child it declared for that step (``nclb_link_kept``).  Children are
  read from the controller state key ``"children"`` of the state recorded
  after the step decided (song2016's documented state).
* :func:`relocate_path_in_range` — while the relocate robot's parent is the
  root, the root does not move and both ends of the relocate robot's step are
  strictly within ``phi`` of it (the premises of ``relocate_stays_in_range``,
  so the whole straight path is).

:func:`check_premises` runs all three.  Positions are compared with a
tolerance of ``tol * phi`` (default 1e-9) for the engine's floating point.

Blind spots: poses are sampled at step ends (straight-line motion is assumed
in between, as the lemmas assume); a state without the keys ``children``,
``relocate``, ``parent``, ``root_id`` makes the corresponding monitor
``inconclusive`` rather than ``held``; the monitors check premises, not the
paper's case analysis (which link is in which case).

References
----------
000_3ad33c5b62f11d5f.txt Lemma 7; 001_7a4e517b856331bc.txt Lemma 7, Def. 8,
Sec. V-C (NCLB, relocate robot), Lemma 11.

Examples
--------
>>> import numpy as np
>>> from swarmproof.models.trace import Trace
>>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.2, 0, 0]]], dtype=float)
>>> st = (("children", ()), ("relocate", False))
>>> t = Trace(ids=[1, 2], poses=poses, states=[(st, st)] * 2)
>>> step_bounded(t, v=0.1, dt=1.0).witness
{'step': 0, 'robot': 2, 'moved': 0.2, 'limit': 0.1, 'lemma': 'bounded_range'}
"""

from __future__ import annotations

import math

import numpy as np

from .result import InvariantResult, state_value

__all__ = ["step_bounded", "parents_in_bounded_ranges", "relocate_path_in_range",
           "check_premises", "params_of"]

_MISSING = object()


def params_of(trace) -> tuple:
    """``(phi, v, dt)`` from ``trace.meta["params"]`` (the engine records them)."""
    p = trace.meta.get("params") or {}
    try:
        return float(p["range"]), float(p["v"]), float(p["dt"])
    except (KeyError, TypeError, ValueError):
        raise ValueError("trace.meta['params'] must hold range, v and dt; "
                         "pass phi, v and dt explicitly") from None


def _slot(trace) -> dict:
    return {int(i): k for k, i in enumerate(trace.ids.tolist())}


def step_bounded(trace, v: float, dt: float, *, tol: float = 1e-9) -> InvariantResult:
    """No robot moves more than ``v*dt`` between consecutive recorded steps.

    Lemma: ``bounded_range`` (000/001 Lemma 7, "each moves at most v dt")."""
    lim = v * dt
    for t in range(trace.steps):
        both = trace.present_at(t) & trace.present_at(t + 1)
        d = np.hypot(*(trace.poses[t + 1][:, :2] - trace.poses[t][:, :2]).T)
        bad = np.flatnonzero(both & (d > lim * (1 + tol) + tol))
        if bad.size:
            k = int(bad[0])
            return InvariantResult(
                "premise:step_bounded", "violated", "bounded_range (000/001 Lemma 7)",
                {"step": t, "robot": int(trace.ids[k]), "moved": round(float(d[k]), 12),
                 "limit": lim, "lemma": "bounded_range"},
                f"robot {int(trace.ids[k])} moved {float(d[k]):.6g} > v*dt = {lim:.6g} in step {t}")
    return InvariantResult("premise:step_bounded", "held", "bounded_range (000/001 Lemma 7)",
                           None, f"every robot moved at most v*dt in all {trace.steps} steps")


def parents_in_bounded_ranges(trace, phi: float, v: float, dt: float, *,
                              tol: float = 1e-9) -> InvariantResult:
    """Every robot that moves in step ``t`` ends within ``phi - v*dt`` of the
    position at ``t`` of each child it declared for step ``t`` (001 Def. 8, NCLB).

    Lemma: ``nclb_link_kept``."""
    radius = phi - v * dt
    slot = _slot(trace)
    checked = 0
    for t in range(trace.steps):
        after = trace.states[t + 1]
        for k in range(trace.n):
            if not (trace.present_at(t)[k] and trace.present_at(t + 1)[k]):
                continue
            children = state_value(after[k], "children", _MISSING)
            if children is _MISSING:
                return InvariantResult("premise:nclb", "inconclusive", "nclb_link_kept (001 Sec. V-C)",
                                       None, f"robot {int(trace.ids[k])} has no 'children' in its state")
            p1 = trace.poses[t + 1][k, :2]
            if np.array_equal(p1, trace.poses[t][k, :2]):
                continue  # did not move: nothing to check (the link case "parent still")
            for c in children or ():
                j = slot.get(int(c))
                if j is None or not trace.present_at(t)[j]:
                    continue
                checked += 1
                d = float(np.hypot(*(p1 - trace.poses[t][j, :2])))
                if d > radius + tol * phi:
                    return InvariantResult(
                        "premise:nclb", "violated", "nclb_link_kept (001 Sec. V-C, Def. 8)",
                        {"step": t, "parent": int(trace.ids[k]), "child": int(c),
                         "distance": round(d, 12), "bounded_range": radius,
                         "lemma": "nclb_link_kept"},
                        f"robot {int(trace.ids[k])} ended step {t} {d:.6g} from the old position of "
                        f"its child {int(c)}, outside its bounded range phi - v*dt = {radius:.6g}")
    return InvariantResult("premise:nclb", "held", "nclb_link_kept (001 Sec. V-C, Def. 8)", None,
                           f"{checked} moving-parent/child pairs inside the child's bounded range",
                           applicable=checked > 0, detail={"checked": checked})


def relocate_path_in_range(trace, phi: float, *, tol: float = 1e-9) -> InvariantResult:
    """While the relocate robot's parent is the root: the root stays still and
    both ends of the relocate robot's step are strictly within ``phi`` of it.

    Lemma: ``relocate_stays_in_range`` (then the straight path between them is
    within ``phi`` too)."""
    slot = _slot(trace)
    checked = 0
    for t in range(trace.steps):
        after = trace.states[t + 1]
        for k in range(trace.n):
            relocate = state_value(after[k], "relocate", _MISSING)
            if relocate is _MISSING:
                return InvariantResult("premise:relocate", "inconclusive",
                                       "relocate_stays_in_range (001 Sec. V-C)", None,
                                       f"robot {int(trace.ids[k])} has no 'relocate' in its state")
            if not relocate:
                continue
            parent, root = state_value(after[k], "parent"), state_value(after[k], "root_id")
            if parent is None or parent != root:
                continue
            q = slot.get(int(root))
            if q is None or not (trace.present_at(t)[q] and trace.present_at(t + 1)[q]):
                continue
            checked += 1
            r0, r1 = trace.poses[t][q, :2], trace.poses[t + 1][q, :2]
            a, b = trace.poses[t][k, :2], trace.poses[t + 1][k, :2]
            witness = {"step": t, "relocate": int(trace.ids[k]), "root": int(root),
                       "lemma": "relocate_stays_in_range"}
            if not np.array_equal(r0, r1):
                return InvariantResult("premise:relocate", "violated",
                                       "relocate_stays_in_range (001 Sec. V-C)",
                                       {**witness, "root_moved": round(float(np.hypot(*(r1 - r0))), 12)},
                                       f"the root {int(root)} moved in step {t}")
            for end, p in (("start", a), ("end", b)):
                d = float(np.hypot(*(p - r0)))
                if not d < phi * (1 + tol):
                    return InvariantResult(
                        "premise:relocate", "violated", "relocate_stays_in_range (001 Sec. V-C)",
                        {**witness, "at": end, "distance": round(d, 12), "range": phi},
                        f"the relocate robot {int(trace.ids[k])} is {d:.6g} >= phi from the root "
                        f"at the {end} of step {t}")
    return InvariantResult("premise:relocate", "held", "relocate_stays_in_range (001 Sec. V-C)",
                           None, f"{checked} relocate steps under the root within range",
                           applicable=checked > 0, detail={"checked": checked})


def check_premises(trace, phi: float | None = None, v: float | None = None,
                   dt: float | None = None) -> list:
    """All premise monitors over one trace (parameters from ``trace.meta`` when omitted)."""
    if phi is None or v is None or dt is None:
        mphi, mv, mdt = params_of(trace)
        phi = mphi if phi is None else phi
        v = mv if v is None else v
        dt = mdt if dt is None else dt
    if not (math.isfinite(phi) and phi > 0 and v >= 0 and dt > 0):
        raise ValueError(f"phi={phi!r}, v={v!r}, dt={dt!r} must be positive finite numbers")
    return [step_bounded(trace, v, dt), parents_in_bounded_ranges(trace, phi, v, dt),
            relocate_path_in_range(trace, phi)]
