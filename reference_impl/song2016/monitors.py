"""Runtime monitors of the premises of Song & O'Kane 2016's lemmas (001 Lemma 7, Def. 8, Sec. V-C).

The z3 lemmas (:mod:`.lemmas`, docs/proofs.md) are about mathematics; these pure checks over a
trace (or one step of a streaming run) say whether a run met their premises.  Importing this
module registers them with :mod:`swarmproof.invariants.premises` (the shared mechanism):

* ``nclb`` -- :func:`parents_in_bounded_ranges`: every robot that moves in a step ends inside
  the bounded range (001 Def. 8: disc of radius ``phi - v*dt``) of each child it declared for
  that step (``nclb_link_kept``).  Children are read from the controller state key
  ``"children"`` of the state recorded after the step decided (song2016's documented state).
* ``relocate`` -- :func:`relocate_path_in_range`: while the relocate robot's parent is the
  root, the root does not move and both ends of the relocate robot's step are strictly within
  ``phi`` of it (the premises of ``relocate_stays_in_range``, so the whole straight path is).
* ``child_toward_parent`` -- :func:`children_toward_still_parents`: a robot whose parent stays
  still in a step does not end farther from it (``spanning_tree_kept``, case
  ``child_toward_still_parent``; the relocate robot excepted).
* ``tree_link_cases`` -- :func:`tree_links_in_proved_cases` / :class:`TreeLinkCases`: every
  link of the tree is in a case the per-link lemma proves (``spanning_tree_kept``).

Measured findings (docs/proofs.md, "Premise monitors"): song2016 met every premise on all 240
acceptance runs.  Blind spots: those of :mod:`swarmproof.invariants.premises` (step ends only,
straight motion assumed in between; a state without the keys ``children``, ``relocate``,
``parent``, ``root_id`` makes the monitor ``inconclusive``).

References
----------
001_7a4e517b856331bc.txt Lemma 7, Def. 8, Sec. V-C (NCLB, relocate robot), Lemma 11.
"""

from __future__ import annotations

import math

import numpy as np

from swarmproof.invariants.premises import (MISSING, examined_steps, movers_in_bounded_ranges,
                                            present_robot_steps, register_monitor, slot_of)
from swarmproof.invariants.result import InvariantResult, state_value

__all__ = ["parents_in_bounded_ranges", "relocate_path_in_range", "children_toward_still_parents",
           "tree_links_in_proved_cases", "TREE_LINK_CASES", "TreeLinkCases"]


def parents_in_bounded_ranges(trace, phi: float, v: float, dt: float, *,
                              tol: float = 1e-9) -> InvariantResult:
    """Every robot that moves in step ``t`` ends within ``phi - v*dt`` of the
    position at ``t`` of each child it declared for step ``t`` (001 Def. 8, NCLB).

    Lemma: ``nclb_link_kept``."""
    radius = phi - v * dt
    status, hit, checked = movers_in_bounded_ranges(
        trace, phi, v, dt, lambda st: state_value(st, "children", MISSING), tol)
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

def _parent_list(parent):
    if parent is MISSING:
        return MISSING
    return () if parent is None else (parent,)

def relocate_path_in_range(trace, phi: float, *, tol: float = 1e-9) -> InvariantResult:
    """While the relocate robot's parent is the root: the root stays still and
    both ends of the relocate robot's step are strictly within ``phi`` of it.

    Lemma: ``relocate_stays_in_range`` (then the straight path between them is
    within ``phi`` too)."""
    slot = slot_of(trace)
    checked = 0
    for t in examined_steps(trace):
        after = trace.states[t + 1]
        pres1 = trace.present_at(t + 1)
        for k in range(trace.n):
            if not pres1[k]:
                continue  # crashed or not yet added: no state to read
            relocate = state_value(after[k], "relocate", MISSING)
            if relocate is MISSING:
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
    slot = slot_of(trace)
    eps = tol * phi
    checked = 0
    for t, k, before, after, p0, p1, pres0, pres1 in present_robot_steps(trace):
        par = state_value(before[k], "parent", MISSING)
        if par is MISSING:
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
        slot = slot_of(trace)
        for t, k, before, after, p0, p1, pres0, pres1 in present_robot_steps(trace):
            par = state_value(after[k], "parent", MISSING)
            if par is MISSING:
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
                kids = state_value(after[q], "children", MISSING)
                if kids is MISSING:
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


register_monitor("nclb", lambda trace, phi, v, dt: parents_in_bounded_ranges(trace, phi, v, dt), "nclb_link_kept")
register_monitor("relocate", lambda trace, phi, v, dt: relocate_path_in_range(trace, phi), "relocate_stays_in_range")
register_monitor("child_toward_parent", lambda trace, phi, v, dt: children_toward_still_parents(trace, phi, v, dt),
                 "spanning_tree_kept")
register_monitor("tree_link_cases", lambda trace, phi, v, dt: tree_links_in_proved_cases(trace, phi, v, dt),
                 "spanning_tree_kept", accumulating=lambda phi, v, dt, meta: TreeLinkCases(phi, v, dt))
