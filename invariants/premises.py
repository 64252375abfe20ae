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
* :func:`children_toward_still_parents` — a robot whose parent stays still
  in a step does not end farther from it (``spanning_tree_kept``, case
  ``child_toward_still_parent``; the relocate robot excepted).
* :func:`descendants_in_parent_bounded_ranges` — song2014's reading of 000
  Lemma 7: every robot that moves in a step ends within ``phi - v*dt`` of
  the old position of the parent it chose (``bounded_range``'s premise
  ``child_in_parent_bounded_range``; state key ``"parent"``).

An algorithm's class says which monitors apply to it (``premise_monitors``;
song2016: the first four; song2014: the step bound and the last one); the
engine records them in ``trace.meta["premise_monitors"]`` and
:func:`check_premises` runs those of the trace.  Positions are
compared with a tolerance of ``tol * phi`` (default 1e-9) for the engine's
floating point.  Measured findings (docs/proofs.md, "Premise monitors"):
song2016 met every premise on all 240 acceptance runs; song2014 breaks
Lemma 7's premise under its own assumptions, because the engine's
differential drive (turn, then drive for the time left) stops a robot short
of its chosen point; with (nearly) instantaneous turns it holds.

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

from swarmproof.models.sensing import INCLUSIVE_SLACK

from .result import InvariantResult, state_value

__all__ = ["step_bounded", "parents_in_bounded_ranges", "relocate_path_in_range",
           "descendants_in_parent_bounded_ranges", "check_premises", "params_of", "MONITORS",
           "MONITOR_LEMMAS", "premise_monitors_of", "tree_links_in_proved_cases", "TREE_LINK_CASES", "TreeLinkCases",
           "grid_claims_distinct", "grid_priorities_distinct", "grid_spacing_bound", "grid_spacing_of_trace",
           "grid_waited_window", "grid_heard_neighbours", "GridHeard"]

_MISSING = object()


def params_of(trace) -> tuple:
    """``(phi, v, dt)`` from ``trace.meta["params"]`` (the engine records them)."""
    p = trace.meta.get("params") or {}
    try:
        return float(p["range"]), float(p["v"]), float(p["dt"])
    except (KeyError, TypeError, ValueError):
        raise ValueError("trace.meta['params'] must hold range, v and dt; "
                         "pass phi, v and dt explicitly") from None


def _steps(trace):
    """The steps a monitor examines: every step of a trace, or the one step of a
    :class:`_Window` (the streaming form, :class:`PremisesMonitor`)."""
    r = getattr(trace, "step_range", None)
    return range(trace.steps) if r is None else r


class _Window:
    """Two consecutive steps ``t0`` and ``t0 + 1`` seen as a trace indexed by absolute step,
    so the monitors examine exactly one step and name it by its number."""

    def __init__(self, ids, meta, prev, cur) -> None:
        (t0, p0, s0, m0), (t1, p1, s1, m1) = prev, cur
        self.ids, self.meta, self.n = ids, meta, len(ids)
        self.steps = t0 + 1
        self.step_range = range(t0, t0 + 1)
        # the frame kept after step t0 is the engine's step t1 (= t0 + 1)
        self.poses = {t0: p0, t0 + 1: p1}
        self.states = {t0: s0, t0 + 1: s1}
        self._present = {t0: m0, t0 + 1: m1}

    def present_at(self, t):
        return self._present[t]


def _present_robot_steps(trace):
    """``(t, k, before, after, p0, p1, pres0, pres1)`` for every examined step ``t`` and every
    robot slot ``k`` present at both of its ends (states and poses before and after the step)."""
    for t in _steps(trace):
        before, after = trace.states[t], trace.states[t + 1]
        p0, p1 = trace.poses[t], trace.poses[t + 1]
        pres0, pres1 = trace.present_at(t), trace.present_at(t + 1)
        for k in range(trace.n):
            if pres0[k] and pres1[k]:
                yield t, k, before, after, p0, p1, pres0, pres1


def _slot(trace) -> dict:
    return {int(i): k for k, i in enumerate(trace.ids.tolist())}


def step_bounded(trace, v: float, dt: float, *, tol: float = 1e-9) -> InvariantResult:
    """No robot moves more than ``v*dt`` between consecutive recorded steps.

    Lemma: ``bounded_range`` (000/001 Lemma 7, "each moves at most v dt")."""
    lim = v * dt
    for t in _steps(trace):
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


def _movers_in_bounded_ranges(trace, phi: float, v: float, dt: float, related, tol: float,
                              movers_only: bool = True):
    """Shared loop: a robot that moves in step ``t`` (any robot, unless ``movers_only``) must
    end within ``phi - v*dt`` of the step-``t`` position of every robot ``related(state_after)``
    names.

    Returns ``("missing", k, None)`` when a moving robot's state lacks the key,
    ``("violated", (t, k, j, d), checked)`` for the first robot outside, else
    ``("held", None, checked)``."""
    radius = phi - v * dt
    slot = _slot(trace)
    checked = 0
    for t, k, _, after, p0, p1, pres0, pres1 in _present_robot_steps(trace):
        others = related(after[k])
        if others is _MISSING:
            return "missing", k, None
        end = p1[k, :2]
        still = np.array_equal(end, p0[k, :2])
        if movers_only and still:
            continue  # did not move: nothing to check (the link case "still")
        for c in others or ():
            j = slot.get(int(c))
            if j is None or not pres0[j]:
                continue
            if still and pres1[j] and np.array_equal(p1[j, :2], p0[j, :2]):
                continue  # neither moved: the link is as it was (the case "both still")
            checked += 1
            d = float(np.hypot(*(end - p0[j, :2])))
            if d > radius + tol * phi:
                return "violated", (t, k, j, d), checked
    return "held", None, checked


def parents_in_bounded_ranges(trace, phi: float, v: float, dt: float, *,
                              tol: float = 1e-9) -> InvariantResult:
    """Every robot that moves in step ``t`` ends within ``phi - v*dt`` of the
    position at ``t`` of each child it declared for step ``t`` (001 Def. 8, NCLB).

    Lemma: ``nclb_link_kept``."""
    radius = phi - v * dt
    status, hit, checked = _movers_in_bounded_ranges(
        trace, phi, v, dt, lambda st: state_value(st, "children", _MISSING), tol)
    if status == "missing":
        return InvariantResult("premise:nclb", "inconclusive", "nclb_link_kept (001 Sec. V-C)",
                               None, f"robot {int(trace.ids[hit])} has no 'children' in its state")
    if status == "violated":
        t, k, j, d = hit
        return InvariantResult(
            "premise:nclb", "violated", "nclb_link_kept (001 Sec. V-C, Def. 8)",
            {"step": t, "parent": int(trace.ids[k]), "child": int(trace.ids[j]),
             "distance": round(d, 12), "bounded_range": radius, "lemma": "nclb_link_kept"},
            f"robot {int(trace.ids[k])} ended step {t} {d:.6g} from the old position of "
            f"its child {int(trace.ids[j])}, outside its bounded range phi - v*dt = {radius:.6g}")
    return InvariantResult("premise:nclb", "held", "nclb_link_kept (001 Sec. V-C, Def. 8)", None,
                           f"{checked} moving-parent/child pairs inside the child's bounded range",
                           applicable=checked > 0, detail={"checked": checked})


def descendants_in_parent_bounded_ranges(trace, phi: float, v: float, dt: float, *,
                                         tol: float = 1e-9) -> InvariantResult:
    """Every robot ends step ``t`` within ``phi - v*dt`` of the position at ``t`` of the
    parent it chose in step ``t``, unless neither moved (000 Lemma 7, Eqs. 5-7:
    the descendant's goal lies in the disc ``P_p`` of radius ``phi - v*dt``
    around its parent, Sec. IV-C step 3).

    The parent is read from the state key ``"parent"`` recorded after the step
    decided (song2014's documented state, docs/song2014.md).  Lemma:
    ``bounded_range`` (its premise ``child_in_parent_bounded_range``).  A robot that
    does not move is examined too when its parent moves (issue 19): a child that only
    turns in place while its parent drives away breaks the premise as surely as one that
    drives; when neither moves, the link is as it was.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.15, 0, 0]]], dtype=float)
    >>> st = ((("parent", None),), (("parent", 1),))
    >>> r = descendants_in_parent_bounded_ranges(Trace(ids=[1, 2], poses=poses, states=[st] * 2),
    ...                                          1.2, 0.1, 1.0)
    >>> r.status, r.witness["lemma"], r.witness["child"], r.witness["distance"]
    ('violated', 'bounded_range', 2, 1.15)
    """
    radius = phi - v * dt
    cites = "bounded_range (000 Lemma 7, Sec. IV-C)"
    status, hit, checked = _movers_in_bounded_ranges(
        trace, phi, v, dt, lambda st: _parent_list(state_value(st, "parent", _MISSING)), tol,
        movers_only=False)
    if status == "missing":
        return InvariantResult("premise:parent_bounded_range", "inconclusive", cites, None,
                               f"robot {int(trace.ids[hit])} has no 'parent' in its state")
    if status == "violated":
        t, k, j, d = hit
        return InvariantResult(
            "premise:parent_bounded_range", "violated", cites,
            {"step": t, "child": int(trace.ids[k]), "parent": int(trace.ids[j]),
             "distance": round(d, 12), "bounded_range": radius, "lemma": "bounded_range"},
            f"robot {int(trace.ids[k])} ended step {t} {d:.6g} from the old position of "
            f"its parent {int(trace.ids[j])}, outside the parent's disc phi - v*dt = {radius:.6g}")
    return InvariantResult("premise:parent_bounded_range", "held", cites, None,
                           f"{checked} child/parent pairs inside the parent's disc phi - v*dt",
                           applicable=checked > 0, detail={"checked": checked})


def _parent_list(parent):
    if parent is _MISSING:
        return _MISSING
    return () if parent is None else (parent,)


def relocate_path_in_range(trace, phi: float, *, tol: float = 1e-9) -> InvariantResult:
    """While the relocate robot's parent is the root: the root stays still and
    both ends of the relocate robot's step are strictly within ``phi`` of it.

    Lemma: ``relocate_stays_in_range`` (then the straight path between them is
    within ``phi`` too)."""
    slot = _slot(trace)
    checked = 0
    for t in _steps(trace):
        after = trace.states[t + 1]
        pres1 = trace.present_at(t + 1)
        for k in range(trace.n):
            if not pres1[k]:
                continue  # crashed or not yet added: no state to read
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


def children_toward_still_parents(trace, phi: float, v: float, dt: float, *,
                                  tol: float = 1e-9) -> InvariantResult:
    """A robot that moves in step ``t`` while its parent stays still ends no farther
    from the parent than it started (001 Sec. V-C: "the children ... will only move
    toward the robot"; case ``child_toward_still_parent`` of ``spanning_tree_kept``).

    The parent is the one named in the robot's state both before and after the
    step (state key ``"parent"``); the relocate robot (state key ``"relocate"``)
    is left to :func:`relocate_path_in_range`, since it heads for a vacancy, not
    for its parent, when the parent is the root.  Distances compare with a
    tolerance of ``tol * phi``.  Added 2026-11-24: a subtree robot that drove
    away from its still parent broke links with every other premise met
    (docs/song2016.md, "Case 3 steered to the nearest safe point").

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.1, 0, 0]]], dtype=float)
    >>> st = ((("parent", None), ("relocate", False)), (("parent", 1), ("relocate", False)))
    >>> r = children_toward_still_parents(Trace(ids=[1, 2], poses=poses, states=[st] * 2), 1.2, 0.1, 1.0)
    >>> r.status, r.witness["child"], r.witness["parent"], r.witness["after"]
    ('violated', 2, 1, 1.1)
    """
    cites = "spanning_tree_kept, case child_toward_still_parent (001 Sec. V-C, Lemma 11)"
    slot = _slot(trace)
    eps = tol * phi
    checked = 0
    for t, k, before, after, p0, p1, pres0, pres1 in _present_robot_steps(trace):
        par = state_value(before[k], "parent", _MISSING)
        if par is _MISSING:
            return InvariantResult("premise:child_toward_parent", "inconclusive", cites, None,
                                   f"robot {int(trace.ids[k])} has no 'parent' in its state")
        if par is None or state_value(after[k], "parent", None) != par:
            continue
        if state_value(before[k], "relocate", False) or state_value(after[k], "relocate", False):
            continue
        q = slot.get(int(par))
        if q is None or not (pres0[q] and pres1[q]):
            continue
        if math.hypot(*(p1[q, :2] - p0[q, :2])) > eps or math.hypot(*(p1[k, :2] - p0[k, :2])) <= eps:
            continue
        checked += 1
        d0 = math.hypot(*(p0[k, :2] - p0[q, :2]))
        d1 = math.hypot(*(p1[k, :2] - p0[q, :2]))
        if d1 > d0 + eps:
            child = int(trace.ids[k])
            return InvariantResult(
                "premise:child_toward_parent", "violated", cites,
                {"step": t, "child": child, "parent": int(par), "before": round(d0, 12),
                 "after": round(d1, 12), "lemma": "spanning_tree_kept"},
                f"robot {child} moved away from its still parent {int(par)} in step {t}: "
                f"{d0:.6g} -> {d1:.6g}")
    return InvariantResult("premise:child_toward_parent", "held", cites, None,
                           f"{checked} child moves toward a still parent, none away",
                           applicable=checked > 0, detail={"checked": checked})


#: The cases of ``spanning_tree_kept`` a link can be in (:func:`tree_links_in_proved_cases`);
#: the last is checked at run time only: no lemma with premises covers it (docs/proofs.md).
TREE_LINK_CASES = ("nclb", "child_not_farther_from_still_parent", "relocate_in_root_range_monitored")


def tree_links_in_proved_cases(trace, phi: float, v: float, dt: float, *,
                               tol: float = 1e-9) -> InvariantResult:
    """Every link of the tree a step decided falls in a case whose link-keeping is proved.

    For every robot ``c`` and the parent ``p`` it holds after step ``t`` (state key
    ``"parent"`` recorded after the step decided -- newly chosen parents included, the
    relocate robot included), when the two were neighbors at ``t``:

    * ``p`` moved in the step: case ``nclb`` (``nclb_link_kept``) -- ``c`` is among the
      children ``p`` decided the step with (state key ``"children"``) and ``p`` ended
      within ``phi - v*dt`` of ``c``'s position at ``t`` (Def. 8);
    * ``p`` stayed still: case ``child_not_farther_from_still_parent`` -- ``c`` does not
      end farther from ``p`` than it started (Sec. V-C: "children ... only move toward");
    * otherwise, for the relocate robot whose parent is the root (Sec. V-C case 2, toward
      the vacancy): ``relocate_in_root_range_monitored`` -- the end of its step strictly
      within ``phi`` of the still root.  This case is *not proved* (001 gives no argument
      for it; the conclusion is checked directly) and is counted apart.

    A link in none of these is *uncovered*: a link the proof of Lemma 11 does not cover,
    whether or not it broke.  The verdict is ``violated`` when any link is uncovered; the
    witness is the first uncovered link that broke (left the range) if one did, else the
    first uncovered one, and ``detail`` lists up to :data:`UNCOVERED_KEPT` of them
    (``[step, child, parent, broke, why]``; ``why`` is ``newly_chosen``, ``not_a_child``,
    ``outside_bounded_range``, ``moved_away_from_still_parent`` or
    ``relocate_away_from_non_root_parent``) with their count, so a tree-link break can be matched
    with the uncovered link behind it.  Lemma: ``spanning_tree_kept``.  Added by issue 19:
    the monitors before it missed links a child chose in the step (the parent cannot know
    of them: messages take one step) and the relocate robot's moves toward a non-root parent.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.array([[[0, 0, 0], [1.1, 0, 0]], [[-0.05, 0, 0], [1.1, 0, 0]]], dtype=float)
    >>> before = ((("parent", None), ("children", ())), (("parent", None), ("children", ())))
    >>> after = ((("parent", None), ("children", ())), (("parent", 1), ("children", ())))
    >>> r = tree_links_in_proved_cases(Trace(ids=[1, 2], poses=poses, states=[before, after]), 1.2, 0.05, 1.0)
    >>> r.status, r.witness["child"], r.witness["parent"], r.witness["newly_chosen"]
    ('violated', 2, 1, True)
    """
    acc = TreeLinkCases(phi, v, dt, tol=tol)
    acc.scan(trace)
    return acc.result()


#: How many uncovered links :class:`TreeLinkCases` lists (all are counted).
UNCOVERED_KEPT = 200


class TreeLinkCases:
    """The accumulating form of :func:`tree_links_in_proved_cases`: :meth:`scan` a whole trace
    or, step by step, the one-step windows of :class:`PremisesMonitor`; :meth:`result` judges
    everything scanned (it does not stop at the first uncovered link)."""

    cites = "spanning_tree_kept (001 Lemma 11's proof, Sec. V-C, Def. 8)"

    def __init__(self, phi: float, v: float, dt: float, *, tol: float = 1e-9) -> None:
        self.phi, self.radius, self.eps, self.tol = phi, phi - v * dt, tol * phi, tol
        self.counts = {c: 0 for c in TREE_LINK_CASES}
        self.uncovered: list = []      # [step, child, parent, broke], the first UNCOVERED_KEPT
        self.n_uncovered = 0
        self.first = None              # (witness, why) of the first uncovered link
        self.first_broken = None       # ... of the first that broke
        self.missing = None            # the message of a state without the keys

    def scan(self, trace) -> None:
        if self.missing is not None:
            return
        phi, eps, radius = self.phi, self.eps, self.radius
        slot = _slot(trace)
        for t, k, before, after, p0, p1, pres0, pres1 in _present_robot_steps(trace):
            par = state_value(after[k], "parent", _MISSING)
            if par is _MISSING:
                self.missing = f"robot {int(trace.ids[k])} has no 'parent' in its state"
                return
            if par is None:
                continue
            q = slot.get(int(par))
            if q is None or not (pres0[q] and pres1[q]):
                continue
            d0 = math.hypot(*(p0[k, :2] - p0[q, :2]))
            if not d0 < phi:
                continue  # not a link of the communication graph at t (tree_links counts it apart)
            child, parent = int(trace.ids[k]), int(par)
            newly = state_value(before[k], "parent", None) != par
            parent_moved = math.hypot(*(p1[q, :2] - p0[q, :2])) > eps
            relocate = bool(state_value(after[k], "relocate", False))
            to_root = par == state_value(after[k], "root_id", None)
            why = kind = None
            if parent_moved:
                kids = state_value(after[q], "children", _MISSING)
                if kids is _MISSING:
                    self.missing = f"robot {parent} has no 'children' in its state"
                    return
                reach = math.hypot(*(p1[q, :2] - p0[k, :2]))
                if child not in tuple(kids or ()):
                    kind = "newly_chosen" if newly else "not_a_child"
                    why = (f"the parent {parent} moved without {child} among the children it decided "
                           "the step with" + (f" ({child} chose it in this very step; messages take one "
                                              "step)" if newly else ""))
                elif reach > radius + eps:
                    kind = "outside_bounded_range"
                    why = (f"the parent {parent} ended {reach:.6g} from {child}'s old position, outside "
                           f"its bounded range phi - v*dt = {radius:.6g}")
                else:
                    self.counts["nclb"] += 1
            else:
                d1 = math.hypot(*(p1[k, :2] - p0[q, :2]))
                if d1 <= d0 + eps:
                    self.counts["child_not_farther_from_still_parent"] += 1
                elif relocate and to_root and d1 < phi * (1 + self.tol):
                    self.counts["relocate_in_root_range_monitored"] += 1
                else:
                    who = "the relocate robot" if relocate else "robot"
                    kind = ("relocate_away_from_non_root_parent" if relocate and not to_root
                            else "moved_away_from_still_parent")
                    why = (f"{who} {child} moved away from its still parent {parent} ({d0:.6g} -> {d1:.6g})"
                           + (", which is not the root" if relocate and not to_root else ""))
            if why is None:
                continue
            d_after = math.hypot(*(p1[k, :2] - p1[q, :2]))
            broke = not d_after < phi
            witness = {"step": t, "child": child, "parent": parent, "newly_chosen": bool(newly),
                       "parent_moved": bool(parent_moved), "distance_before": round(d0, 12),
                       "distance_after": round(d_after, 12), "broke": broke, "why": kind,
                       "lemma": "spanning_tree_kept"}
            self.n_uncovered += 1
            if len(self.uncovered) < UNCOVERED_KEPT:
                self.uncovered.append([t, child, parent, broke, kind])
            if self.first is None:
                self.first = (witness, why)
            if broke and self.first_broken is None:
                self.first_broken = (witness, why)

    def result(self) -> InvariantResult:
        name, cites = "premise:tree_link_cases", self.cites
        if self.missing is not None:
            return InvariantResult(name, "inconclusive", cites, None, self.missing)
        checked = sum(self.counts.values())
        detail = {"checked": checked, "cases": dict(self.counts), "uncovered": self.n_uncovered,
                  "uncovered_links": [list(u) for u in self.uncovered]}
        if self.first is not None:
            witness, why = self.first_broken or self.first
            t, c, p = witness["step"], witness["child"], witness["parent"]
            broke = (f"; it broke (distance {witness['distance_before']:.6g} -> {witness['distance_after']:.6g})"
                     if witness["broke"] else "")
            n_broke = sum(1 for u in self.uncovered if u[3])
            return InvariantResult(
                name, "violated", cites, witness,
                f"step {t}: the link child {c} -> parent {p} is in no proved case of Lemma 11's proof: "
                f"{why}{broke} ({self.n_uncovered} uncovered link-steps, {n_broke} of the listed ones broke)",
                detail=detail)
        return InvariantResult(name, "held", cites, None,
                               f"{checked} tree links in proved cases ({self.counts['relocate_in_root_range_monitored']} "
                               "relocate-robot links to the root checked directly, a case no lemma covers)",
                               applicable=checked > 0, detail=detail)


# ------------------------------------------------- grid waypoints (004, issue 15)

#: Cites of the grid monitors: the lemmas of :mod:`swarmproof.checkers.proofs_wang2020`.
_GRID_CITES = {
    "claims": "wang2020_separation_equal_speeds, wang2020_theorem_iv_a_2 (004 Thms. IV-A.1/IV-A.2, Constraints III-A.1/2)",
    "priorities": "wang2020_planner_vertex_one_moment, wang2020_lemma_iv_a_1 (004 Alg. 2 line 28, Sec. II-B)",
    "spacing": "wang2020_separation_equal_speeds, wang2020_planner_vertex_one_moment (004 Sec. III-A: 2 sqrt(2) r <= l <= R/2)",
    "waited": "wang2020_lemma_iv_a_1 (004 Alg. 2 line 30: waited longer than Delta t)",
    "heard": "wang2020_lemma_iv_a_1 (004 Sec. II-A c, e: every robot within R throughout the window heard)",
}


def _cell(value):
    """A waypoint from a state value: a pair of integers as a tuple, None stays None."""
    return None if value is None else tuple(int(c) for c in value)


def _grid_states(trace, t, keys):
    """``{slot: {key: value}}`` for the robots present at ``t``; ``(slot, key)`` of the first
    state that lacks a key instead, as ``("missing", slot, key)``."""
    out = {}
    pres = trace.present_at(t)
    for k in range(trace.n):
        if not pres[k]:
            continue
        st = trace.states[t][k]
        row = {}
        for key in keys:
            val = state_value(st, key, _MISSING)
            if val is _MISSING:
                return ("missing", k, key)
            row[key] = val
        out[k] = row
    return out


def _grid_steps(trace):
    """The recorded states a grid monitor reads: after every examined step (and the start)."""
    r = _steps(trace)
    return ([r.start] if r.start == 0 else []) + [t + 1 for t in r]


def grid_claims_distinct(trace, phi: float = 0.0, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """Claims distinct and no edge swap, in every recorded state (004 Constraints III-A.1/2, the
    conclusions of Thms. IV-A.1/IV-A.2 and premises of ``wang2020_separation_equal_speeds``).

    A robot's claim (Alg. 2's ``wp``) is its state's ``"next"`` when that is not None (the
    waypoint it moves or decided to move to), else its ``"cell"``.  Violated when two robots
    share a cell or a claim, or when one's ``next`` is the other's ``cell`` and the other way
    round (opposite travel on one edge).  A state without ``cell`` and ``next`` is
    ``inconclusive``.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.zeros((2, 2, 3)); poses[:, 1, 0] = 0.2
    >>> st = ((("cell", (0, 0)), ("next", (1, 1))), (("cell", (1, 0)), ("next", (1, 1))))
    >>> r = grid_claims_distinct(Trace(ids=[1, 2], poses=poses, states=[st, st]))
    >>> r.status, r.witness["robots"], r.witness["waypoint"], r.witness["lemma"]
    ('violated', [1, 2], [1, 1], 'wang2020_separation_equal_speeds')
    """
    name, cites = "premise:grid_claims", _GRID_CITES["claims"]
    checked = 0
    for t in _grid_steps(trace):
        rows = _grid_states(trace, t, ("cell", "next"))
        if isinstance(rows, tuple):
            return InvariantResult(name, "inconclusive", cites, None,
                                   f"robot {int(trace.ids[rows[1]])} has no {rows[2]!r} in its state at step {t}")
        cells, claims, nxt = {}, {}, {}
        for k, row in sorted(rows.items()):
            cell, n = _cell(row["cell"]), _claim_of(trace.states[t][k], row)
            if cell is None:                    # not started yet (no waypoint before its first tick)
                continue
            checked += 1
            nxt[k] = n
            claim = _cell(state_value(trace.states[t][k], "wp", None)) or (n if n is not None else cell)
            for what, key, table in (("cell", cell, cells), ("claim", claim, claims)):
                if key in table:
                    a, b = int(trace.ids[table[key]]), int(trace.ids[k])
                    return InvariantResult(
                        name, "violated", cites,
                        {"step": t, "robots": [a, b], "waypoint": list(key), "kind": f"shared_{what}",
                         "lemma": "wang2020_separation_equal_speeds"},
                        f"robots {a} and {b} share the {what} {key} at step {t} (Constraint III-A.1)")
                table[key] = k
        for k, n in nxt.items():
            if n is None:
                continue
            j = cells.get(n)
            if j is not None and j != k and nxt.get(j) == _cell(rows[k]["cell"]):
                a, b = sorted((int(trace.ids[k]), int(trace.ids[j])))
                return InvariantResult(
                    name, "violated", cites,
                    {"step": t, "robots": [a, b], "waypoint": list(n), "kind": "edge_swap",
                     "lemma": "wang2020_theorem_iv_a_2"},
                    f"robots {a} and {b} travel one edge in opposite directions at step {t} (Constraint III-A.2)")
    return InvariantResult(name, "held", cites, None, f"{checked} robot-states with distinct cells and claims",
                           applicable=checked > 0, detail={"checked": checked})


def grid_priorities_distinct(trace, phi: float, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """Robots within ``phi`` (= ``R``) of each other have distinct ``"priority"`` values in every
    recorded state (the lexicographic priority of distinct waypoints, 004 Sec. II-B; premise
    ``distinct_priorities`` of ``wang2020_planner_vertex_one_moment``).

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.zeros((2, 2, 3)); poses[:, 1, 0] = 0.2
    >>> st = ((("priority", (0, 0)),), (("priority", (0, 0)),))
    >>> grid_priorities_distinct(Trace(ids=[1, 2], poses=poses, states=[st, st]), 0.6).witness["robots"]
    [1, 2]
    """
    name, cites = "premise:grid_priorities", _GRID_CITES["priorities"]
    checked = 0
    for t in _grid_steps(trace):
        rows = _grid_states(trace, t, ("priority",))
        if isinstance(rows, tuple):
            return InvariantResult(name, "inconclusive", cites, None,
                                   f"robot {int(trace.ids[rows[1]])} has no 'priority' in its state at step {t}")
        p = trace.poses[t]
        ks = sorted(rows)
        for x, k in enumerate(ks):
            for j in ks[x + 1:]:
                if math.hypot(*(p[k, :2] - p[j, :2])) > phi * INCLUSIVE_SLACK:
                    continue
                if rows[k]["priority"] is None or rows[j]["priority"] is None:
                    continue                    # not started yet
                checked += 1
                if tuple(rows[k]["priority"]) == tuple(rows[j]["priority"]):
                    a, b = int(trace.ids[k]), int(trace.ids[j])
                    return InvariantResult(
                        name, "violated", cites,
                        {"step": t, "robots": [a, b], "priority": list(rows[k]["priority"]),
                         "lemma": "wang2020_planner_vertex_one_moment"},
                        f"robots {a} and {b}, within R, have the same priority at step {t}")
    return InvariantResult(name, "held", cites, None, f"{checked} pairs within R with distinct priorities",
                           applicable=checked > 0, detail={"checked": checked})


def grid_spacing_bound(l: float, r: float, R: float) -> InvariantResult:
    """``2 sqrt(2) r <= l <= R / 2`` (004 Sec. III-A), the grid-length premise of
    ``wang2020_separation_equal_speeds`` (lower bound) and of the planner lemmas (upper bound:
    agents that can conflict, at most ``2l`` apart, hear each other).  Sec. V's values pass:

    >>> grid_spacing_bound(0.20, 0.05, 0.6).status
    'held'
    >>> grid_spacing_bound(0.14, 0.05, 0.6).witness["bound"]
    'l >= 2 sqrt(2) r'
    """
    name, cites = "premise:grid_spacing", _GRID_CITES["spacing"]
    vals = {"l": l, "r": r, "R": R}
    for key, val in vals.items():
        if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
            return InvariantResult(name, "inconclusive", cites, None, f"{key}={val!r} is not a positive number")
    low = 2 * math.sqrt(2) * r
    for ok, bound in ((l >= low * (1 - 1e-12), "l >= 2 sqrt(2) r"), (l <= R / 2 * (1 + 1e-12), "l <= R/2")):
        if not ok:
            return InvariantResult(name, "violated", cites,
                                   {"step": 0, **vals, "bound": bound, "lemma": "wang2020_separation_equal_speeds"
                                    if bound.startswith("l >=") else "wang2020_planner_vertex_one_moment"},
                                   f"grid length l={l!r} breaks {bound} (r={r!r}, R={R!r})")
    return InvariantResult(name, "held", cites, None, f"2 sqrt(2) r = {low:.6g} <= l = {l:g} <= R/2 = {R / 2:g}")


def _grid_params(trace, phi: float):
    """``(l, r)`` from the trace's meta (``grid_spacing``; ``params.extra`` ``grid_spacing`` and
    ``robot_radius`` or ``radius``), None where absent."""
    meta = getattr(trace, "meta", None) or {}
    extra = (meta.get("params") or {}).get("extra") or {}
    l = meta.get("grid_spacing", extra.get("grid_spacing"))
    r = extra.get("robot_radius", extra.get("radius"))
    return l, r


def grid_spacing_of_trace(trace, phi: float, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """:func:`grid_spacing_bound` with ``l`` and ``r`` from ``trace.meta`` (``inconclusive``,
    never held, when the trace does not record them, e.g. a one-step streaming window)."""
    l, r = _grid_params(trace, phi)
    if l is None or r is None:
        return InvariantResult("premise:grid_spacing", "inconclusive", _GRID_CITES["spacing"], None,
                               "the trace records no grid_spacing and robot_radius (params.extra)")
    return grid_spacing_bound(float(l), float(r), phi)


def _claim_of(state, row):
    """The waypoint a robot travels to: with a ``"moving"`` key (the wang2020 controller), its
    ``"wp"`` while it moves and None while it waits (its ``"next"`` is then only an intent);
    without one, its ``"next"``."""
    moving = state_value(state, "moving", _MISSING)
    if moving is _MISSING:
        return _cell(row["next"])
    return _cell(state_value(state, "wp", None)) if moving else None


def _decided(trace, t, k):
    """Robot slot ``k`` set off in step ``t``: ``moving`` False before the step and True after when
    the state has that key (the wang2020 controller), else ``next`` None before, not None after."""
    m0 = state_value(trace.states[t][k], "moving", _MISSING)
    m1 = state_value(trace.states[t + 1][k], "moving", _MISSING)
    if m0 is not _MISSING and m1 is not _MISSING:
        return (not m0) and bool(m1)
    before = state_value(trace.states[t][k], "next", _MISSING)
    after = state_value(trace.states[t + 1][k], "next", _MISSING)
    if before is _MISSING or after is _MISSING:
        return _MISSING
    return before is None and after is not None


def grid_waited_window(trace, phi: float = 0.0, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """A robot that sets off in step ``t`` (its ``"next"`` None before, not None after) had waited
    at its waypoint longer than the window: state keys ``"waited"`` (time since ``last_check``
    when it decided) and ``"window"`` (its ``Delta t``), from the state after the step
    (004 Alg. 2 line 30; premise ``i_waited_longer_than_window`` of ``wang2020_lemma_iv_a_1``).

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.zeros((2, 1, 3))
    >>> before = ((("next", None), ("waited", 1.0), ("window", 2.0)),)
    >>> after = ((("next", (1, 0)), ("waited", 1.5), ("window", 2.0)),)
    >>> r = grid_waited_window(Trace(ids=[7], poses=poses, states=[before, after]))
    >>> r.status, r.witness["robot"], r.witness["waited"]
    ('violated', 7, 1.5)
    """
    name, cites = "premise:grid_waited", _GRID_CITES["waited"]
    checked = 0
    for t, k, before, after, *_ in _present_robot_steps(trace):
        went = _decided(trace, t, k)
        if went is _MISSING:
            return InvariantResult(name, "inconclusive", cites, None, f"robot {int(trace.ids[k])} has no 'next' in its state")
        if not went:
            continue
        waited, window = state_value(after[k], "waited", _MISSING), state_value(after[k], "window", _MISSING)
        if waited is _MISSING or window is _MISSING:
            return InvariantResult(name, "inconclusive", cites, None,
                                   f"robot {int(trace.ids[k])} set off in step {t} without 'waited' and 'window' in its state")
        checked += 1
        if not float(waited) > float(window):
            rid = int(trace.ids[k])
            return InvariantResult(name, "violated", cites,
                                   {"step": t, "robot": rid, "waited": float(waited), "window": float(window),
                                    "lemma": "wang2020_lemma_iv_a_1"},
                                   f"robot {rid} set off in step {t} after waiting {float(waited):g} <= Delta t = {float(window):g}")
    return InvariantResult(name, "held", cites, None, f"{checked} departures after waiting longer than the window",
                           applicable=checked > 0, detail={"checked": checked})


def grid_heard_neighbours(trace, phi: float, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """A robot that sets off in step ``t`` had heard, within its window, every robot that was within
    ``phi`` (= ``R``) of it throughout that window (004 Sec. II-A b, c, e; premise
    ``lossless_delivery_within_R`` of ``wang2020_lemma_iv_a_1``): the whole-trace form of
    :class:`GridHeard`, which states the premise exactly (which robots, which frames, which window).

    State keys, from the state after the step: ``"heard"`` (the ids the robot holds a message of in
    its ``msg_buff``, 004 Alg. 2 line 15) and ``"window"`` (its ``Delta t``, local clock units); a
    departure is read by ``"moving"`` (or ``"next"``).  The clocks come from ``trace.meta``
    (``clocks``: the engine's per-robot rates and ``broadcast_every``; else ``params.extra``'s
    ``clock_rate_min`` / ``clock_rate_max`` / ``broadcast_every``; else 1, the engine's defaults).

    Examples
    --------
    Robot 2 stands 0.2 m from robot 1 for three steps (a window of 2 steps, a broadcast every
    step); robot 1 sets off in step 2 without a message from it:

    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.zeros((4, 2, 3)); poses[:, 1, 0] = 0.2
    >>> wait = ((("moving", False), ("heard", ()), ("window", 2.0)),) * 2
    >>> went = ((("moving", True), ("heard", ()), ("window", 2.0)), wait[1])
    >>> r = grid_heard_neighbours(Trace(ids=[1, 2], poses=poses, states=[wait] * 3 + [went]), 0.6)
    >>> r.status, r.witness["robot"], r.witness["unheard"], r.witness["frames"]
    ('violated', 1, [2], [1, 2])

    Had robot 2 come within R only in step 2 (it was 0.8 m away before), nothing was owed yet:

    >>> poses[:2, 1, 0] = 0.8
    >>> r = grid_heard_neighbours(Trace(ids=[1, 2], poses=poses, states=[wait] * 3 + [went]), 0.6)
    >>> r.status, r.detail["arrived_unheard"]
    ('held', 1)
    """
    acc = GridHeard(phi, meta=getattr(trace, "meta", None))
    acc.scan(trace)
    return acc.result()


def _clock_facts(meta) -> tuple:
    """``(rates by slot or None, rate_min, rate_max, broadcast_every)`` from a trace's meta: the
    engine's recorded ``clocks`` (exact), else ``params.extra`` (bounds), else the engine's
    defaults (every rate 1, a broadcast every step)."""
    meta = meta or {}
    extra = (meta.get("params") or {}).get("extra") or {}
    try:
        lo = float(extra.get("clock_rate_min", 1.0))
        hi = float(extra.get("clock_rate_max", lo))
        every = float(extra.get("broadcast_every", 1.0))
    except (TypeError, ValueError):
        lo = hi = every = 1.0
    clocks = meta.get("clocks") or {}
    rates = clocks.get("rate")
    if rates is not None:
        rates = [float(x) for x in rates]
        every = float(clocks.get("broadcast_every", every))
        if rates:
            lo, hi = min(rates), max(rates)
    return rates, lo, hi, every


#: Frames :class:`GridHeard` keeps at least (a window longer than this many steps is still judged:
#: the history grows to the longest window read).
_HEARD_HISTORY = 64


class GridHeard:
    """The premise ``lossless_delivery_within_R`` of ``wang2020_lemma_iv_a_1``, exactly as the lemma
    uses it, over a whole trace or step by step (:meth:`scan` the one-step windows of
    :class:`PremisesMonitor`; it keeps the frames of the last windows itself).

    The statement (004 Lemma IV-A.1's proof, Sec. II-A b, c, e; the engine's timing,
    docs/engine.md): robot ``i`` sets off in step ``t`` (Alg. 2 lines 30-31) reading its
    ``msg_buff`` (line 15): the messages received in the steps ``u`` with ``t - W <= u <= t``,
    where ``W = floor(Delta t / rate_i)`` steps.  A message received in step ``u`` is a broadcast
    of step ``u - 1`` delivered to the robots within ``R`` (inclusive) at frame ``u``, the start of
    step ``u``.  Every robot ``j`` that was present and within ``R`` of ``i`` at *every* frame
    ``u`` of that window, and broadcast in it, must be among ``i``'s ``"heard"``.

    Why these robots.  The lemma's other agent ``a_j`` changes its claim to ``wp^1`` at
    ``t_j <= t*`` (the case the proof excludes); it waited more than ``Delta t`` one edge from
    ``wp^1`` before ``t_j`` and then travels toward ``wp^1``, so throughout ``i``'s window it is
    at most ``2 l <= R`` from ``i`` (Sec. III-A); every robot within ``R`` throughout is owed
    delivery by Sec. II-A c, e.  A robot that comes within ``R`` during the window is neither the
    lemma's ``a_j`` nor owed its earlier broadcasts (sent from beyond ``R``), so it is not checked
    (``detail["arrived_unheard"]`` counts those that were not heard; issue 15, the explorer's first
    counterexample, docs/wang2020.md).

    Where the window is not known exactly (the streaming form, which sees no per-robot clock
    rates): the span ``i``'s window may cover is taken at its longest (``rate_min``) for "within
    ``R`` throughout", and at its shortest (``rate_max``), less the boundary step (floating
    point at the cutoff), for "``j`` broadcast in it": ``K`` steps with ``K * rate_j >=
    broadcast_every``.  With equal rates (Sec. II-A a) both are the same window.  Receipts before
    step 1 do not exist (nobody broadcast before step 0).

    Blind spots: ``"heard"`` lists senders, not messages, so "every broadcast of ``j`` reached
    ``i``" is checked as "at least one did"; a window whose frames a sparse trace did not keep is
    not judged (``inconclusive`` if no violation is found; the streaming form sees every step).
    """

    name = "premise:grid_heard"

    def __init__(self, phi: float, meta=None) -> None:
        self.phi = float(phi)
        self.rates, self.rate_min, self.rate_max, self.every = _clock_facts(meta)
        self.frames: dict = {}         # engine step -> (xy (n, 2), present (n,))
        self.keep = _HEARD_HISTORY
        self.checked = 0               # departures judged
        self.owed = 0                  # (departure, robot) pairs owed delivery
        self.arrived_unheard = 0       # pairs within R at the departure, not throughout the window, unheard
        self.unjudged = 0              # departures whose window frames were not kept (sparse trace)
        self.first = None              # (witness, message) of the first violation
        self.missing = None            # message of a state without the keys

    def _rate(self, k: int, low: bool) -> float:
        if self.rates is not None and k < len(self.rates):
            return self.rates[k]
        return self.rate_min if low else self.rate_max

    def scan(self, trace) -> None:
        if self.missing is not None or self.first is not None:
            return
        times = getattr(trace, "times", None)
        at = (lambda f: f) if times is None else (lambda f: times[f])
        for t in _steps(trace):
            for f in (t, t + 1):
                step = at(f)
                if step not in self.frames:
                    self.frames[step] = (np.asarray(trace.poses[f])[:, :2].copy(), np.asarray(trace.present_at(f), bool).copy())
            a = at(t)
            for old in [s for s in self.frames if s < a - self.keep]:
                del self.frames[old]
            pres0, pres1 = trace.present_at(t), trace.present_at(t + 1)
            for k in range(trace.n):
                if not (pres0[k] and pres1[k]):
                    continue
                went = _decided(trace, t, k)
                if went is _MISSING:
                    self.missing = f"robot {int(trace.ids[k])} has no 'moving' or 'next' in its state"
                    return
                if not went:
                    continue
                after = trace.states[t + 1][k]
                heard, window = state_value(after, "heard", _MISSING), state_value(after, "window", _MISSING)
                if heard is _MISSING or window is _MISSING:
                    self.missing = (f"robot {int(trace.ids[k])} set off in step {a} without 'heard' and 'window' "
                                    "in its state")
                    return
                self._departure(trace, a, k, float(window), {int(h) for h in heard})
                if self.first is not None:
                    return

    def _departure(self, trace, a: int, k: int, window: float, heard: set) -> None:
        span = int(math.floor(window / self._rate(k, True) + 1e-9))       # the longest window, in steps
        sure = int(math.floor(window / self._rate(k, False) + 1e-9))      # the shortest
        self.keep = max(self.keep, span + 2)
        lo = max(1, a - span)                                             # receipts exist from step 1
        steps = range(lo, a + 1)
        if not steps:
            self.checked += 1                                             # step 0: nothing received yet
            return
        if any(u not in self.frames for u in steps):
            self.unjudged += 1
            return
        self.checked += 1
        xy = np.stack([self.frames[u][0] for u in steps])                 # (frames, n, 2)
        pres = np.stack([self.frames[u][1] for u in steps])
        d = np.hypot(xy[:, :, 0] - xy[:, k:k + 1, 0], xy[:, :, 1] - xy[:, k:k + 1, 1])
        within = (d <= self.phi * INCLUSIVE_SLACK) & pres & pres[:, k:k + 1]
        throughout = within.all(axis=0)
        now = within[-1]
        K = a - max(1, a - sure + 1) + 1                                  # broadcast steps surely read
        ids = trace.ids
        unheard, arrived = [], 0
        for j in range(trace.n):
            if j == k or not now[j]:
                continue
            rid = int(ids[j])
            if rid in heard:
                continue
            if not throughout[j]:
                arrived += 1
                continue
            if K * self._rate(j, True) < self.every * (1 - 1e-12):
                continue                                                  # j need not have broadcast in it
            unheard.append(rid)
        owed = int(sum(1 for j in range(trace.n) if j != k and throughout[j]))
        self.owed += owed
        self.arrived_unheard += arrived
        if unheard:
            rid = int(ids[k])
            witness = {"step": a, "robot": rid, "unheard": sorted(unheard), "frames": [lo, a],
                       "window_steps": span, "lemma": "wang2020_lemma_iv_a_1"}
            self.first = (witness, f"robot {rid} set off in step {a} without having heard {sorted(unheard)}, "
                                   f"within R throughout its window (steps {lo}..{a})")

    def result(self) -> InvariantResult:
        cites = _GRID_CITES["heard"]
        detail = {"checked": self.checked, "owed": self.owed, "arrived_unheard": self.arrived_unheard,
                  "unjudged": self.unjudged}
        if self.missing is not None:
            return InvariantResult(self.name, "inconclusive", cites, None, self.missing, detail=detail)
        if self.first is not None:
            witness, message = self.first
            return InvariantResult(self.name, "violated", cites, witness, message, detail=detail)
        if self.unjudged:
            return InvariantResult(self.name, "inconclusive", cites, None,
                                   f"{self.unjudged} departures whose window the trace did not keep (sparse); "
                                   f"{self.checked} judged, none unheard", detail=detail)
        return InvariantResult(self.name, "held", cites, None,
                               f"{self.checked} departures with every robot within R throughout the window heard "
                               f"({self.arrived_unheard} robots that came within R during a window, not owed)",
                               applicable=self.checked > 0, detail=detail)


def check_premises(trace, phi: float | None = None, v: float | None = None,
                   dt: float | None = None, monitors=None) -> list:
    """The premise monitors of the trace's algorithm over one trace.

    Parameters
    ----------
    trace : Trace
        A recorded run (the engine's ``simulate(...).trace``).
    phi, v, dt : float, optional
        Range, speed and step; from ``trace.meta["params"]`` when omitted.
    monitors : sequence of str, optional
        Names from :data:`MONITORS`.  By default those the engine recorded
        from the algorithm (``trace.meta["premise_monitors"]``); a trace
        without them (written by hand, or before they were recorded) needs
        ``monitors``.

    Returns
    -------
    list of InvariantResult
        One per monitor, in order.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.1, 0, 0]]], dtype=float)
    >>> st = ((("parent", None),), (("parent", 1),))
    >>> t = Trace(ids=[1, 2], poses=poses, states=[st] * 2, meta={"algorithm": "song2014",
    ...           "premise_monitors": ["step_bounded", "parent_bounded_range"],
    ...           "params": {"range": 1.2, "v": 0.1, "dt": 1.0}})
    >>> [(r.name, r.status) for r in check_premises(t)]
    [('premise:step_bounded', 'held'), ('premise:parent_bounded_range', 'held')]
    """
    if phi is None or v is None or dt is None:
        mphi, mv, mdt = params_of(trace)
        phi = mphi if phi is None else phi
        v = mv if v is None else v
        dt = mdt if dt is None else dt
    if not (math.isfinite(phi) and phi > 0 and v >= 0 and dt > 0):
        raise ValueError(f"phi={phi!r}, v={v!r}, dt={dt!r} must be positive finite numbers")
    if monitors is None:
        monitors = trace.meta.get("premise_monitors")
        if monitors is None:
            raise ValueError(f"trace of algorithm={trace.meta.get('algorithm')!r} names no premise monitors "
                             "(trace.meta['premise_monitors'], recorded by the engine from the algorithm's "
                             "premise_monitors); pass monitors=[...] from "
                             f"{sorted(MONITORS)!r}")
    return [MONITORS[m](trace, phi, v, dt) for m in _known(monitors)]


def _known(names) -> tuple:
    """``names`` as a tuple; ValueError naming the first that is not in :data:`MONITORS`."""
    names = tuple(names)
    for n in names:
        if n not in MONITORS:
            raise ValueError(f"premise monitor={n!r} is not known; use some of {sorted(MONITORS)!r}")
    return names


#: Every monitor by name: a function ``(trace, phi, v, dt) -> InvariantResult``.
MONITORS = {
    "step_bounded": lambda trace, phi, v, dt: step_bounded(trace, v, dt),
    "nclb": lambda trace, phi, v, dt: parents_in_bounded_ranges(trace, phi, v, dt),
    "relocate": lambda trace, phi, v, dt: relocate_path_in_range(trace, phi),
    "parent_bounded_range": lambda trace, phi, v, dt: descendants_in_parent_bounded_ranges(trace, phi, v, dt),
    "child_toward_parent": lambda trace, phi, v, dt: children_toward_still_parents(trace, phi, v, dt),
    "tree_link_cases": lambda trace, phi, v, dt: tree_links_in_proved_cases(trace, phi, v, dt),
    # 004's grid waypoints (issue 15): the premises of checkers/proofs_wang2020.py's lemmas
    "grid_claims": grid_claims_distinct,
    "grid_priorities": grid_priorities_distinct,
    "grid_spacing": grid_spacing_of_trace,
    "grid_waited": grid_waited_window,
    "grid_heard": grid_heard_neighbours,
}

#: The proof-suite lemma (``swarmproof prove`` id) whose premise each monitor checks.
MONITOR_LEMMAS = {"step_bounded": "bounded_range", "nclb": "nclb_link_kept",
                  "relocate": "relocate_stays_in_range", "parent_bounded_range": "bounded_range",
                  "child_toward_parent": "spanning_tree_kept", "tree_link_cases": "spanning_tree_kept",
                  "grid_claims": "wang2020_separation_equal_speeds",
                  "grid_priorities": "wang2020_planner_vertex_one_moment",
                  "grid_spacing": "wang2020_separation_equal_speeds",
                  "grid_waited": "wang2020_lemma_iv_a_1", "grid_heard": "wang2020_lemma_iv_a_1"}

#: Monitors with memory across steps, for :class:`PremisesMonitor`: name -> factory
#: ``(phi, v, dt, meta) -> object with scan(trace) and result()``.
_ACCUMULATING = {
    "tree_link_cases": lambda phi, v, dt, meta: TreeLinkCases(phi, v, dt),
    "grid_heard": lambda phi, v, dt, meta: GridHeard(phi, meta=meta),
}


def premise_monitors_of(algorithm) -> tuple:
    """The monitor names that apply to ``algorithm``: its class's ``premise_monitors``
    attribute (the lemmas its paper's proof uses), else ``()`` (no lemma premises declared).

    >>> premise_monitors_of(type("A", (), {"name": "mine"})())
    ()
    >>> premise_monitors_of(type("B", (), {"name": "mine", "premise_monitors": ("nclb",)})())
    ('nclb',)
    """
    names = getattr(algorithm, "premise_monitors", None)
    return _known(names or ())


class PremisesMonitor:
    """Streaming form of the ``premises`` property: the engine feeds it every step
    (``simulate(observers=...)``) and each monitor examines that one step, so a premise that
    fails at a step a sparse trace does not keep is found.  Verdicts as
    :func:`swarmproof.invariants.properties.premises`: the earliest violation over all
    monitors, inconclusive when a monitor cannot read its state keys or none is declared."""

    name = "premises"

    def __init__(self, monitors, phi: float, v: float, dt: float, *, meta=None) -> None:
        self.monitors = _known(monitors)
        self.phi, self.v, self.dt = float(phi), float(v), float(dt)
        #: run facts for the accumulating monitors (e.g. ``{"params": {"extra": ...}}``: the clock
        #: rates and broadcast period :class:`GridHeard` reads); the one-step windows carry no meta
        self.meta = dict(meta or {})
        self._prev = None
        self.steps = 0
        self.final: dict = {}            # monitor -> a violated or inconclusive result (it stops there)
        self.checked = {m: 0 for m in self.monitors}
        # monitors that keep memory across steps: they scan every step they see (tree_link_cases
        # judges them all, grid_heard keeps the frames of the last windows)
        self.accumulating = {m: _ACCUMULATING[m](self.phi, self.v, self.dt, self.meta) for m in self.monitors
                             if m in _ACCUMULATING}

    def start(self, ids) -> None:
        self.ids = np.asarray(ids)
        self.slot = {int(i): k for k, i in enumerate(self.ids.tolist())}

    def observe(self, t, poses, states, present) -> None:
        cur = (int(t), np.array(poses, copy=True), states, np.array(present, copy=True))
        prev, self._prev = self._prev, cur
        if prev is None:
            return
        self.steps += 1
        window = _Window(self.ids, {}, prev, cur)     # (GridHeard got self.meta when it was made)
        for name in self.monitors:
            if name in self.accumulating:
                self.accumulating[name].scan(window)
                continue
            if name in self.final:
                continue
            r = MONITORS[name](window, self.phi, self.v, self.dt)
            if r.status != "held":
                self.final[name] = r
            else:
                self.checked[name] += int((r.detail or {}).get("checked", 0))

    def results(self) -> list:
        """``(monitor, InvariantResult)`` over every step seen."""
        out = []
        for name in self.monitors:
            r = self.accumulating[name].result() if name in self.accumulating else self.final.get(name)
            if r is None:
                n = self.checked[name]
                applicable = n > 0 or name == "step_bounded"
                r = InvariantResult(f"premise:{name}", "held", MONITOR_LEMMAS[name], None,
                                    f"held at every one of {self.steps} steps ({n} cases examined)",
                                    applicable=applicable, detail={"checked": n})
            out.append((name, r))
        return out

    def result(self) -> InvariantResult:
        from .properties import combine_premises

        return combine_premises(self.monitors, self.results(), self.steps)
