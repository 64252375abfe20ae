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

Every one is derived from its lemma's one definition (a binding, issue 32).  The check of which
case of Lemma 11's argument covers each tree link, :func:`tree_links_in_proved_cases` /
:class:`TreeLinkCases`, is here too (it reads the same states) but is no premise monitor: no
lemma states the case coverage by the algorithm's own reasons, so it is the property
``tree_link_cases`` of song2016 (:mod:`.properties`; docs/proofs.md, "Premise monitors").

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

from swarmproof.invariants.lemma_monitor import Batch, Binding, Instance
from swarmproof.invariants.premises import MISSING, present_robot_steps, register_binding, slot_of
from swarmproof.invariants.result import InvariantResult, state_value

from .lemmas import BOUNDED_RANGE, NCLB_LINK_KEPT, RELOCATE_STAYS_IN_RANGE, SPANNING_TREE_KEPT

__all__ = ["STEP_BOUNDED", "NCLB", "RELOCATE", "CHILD_TOWARD_PARENT", "step_bounded", "parents_in_bounded_ranges",
           "relocate_path_in_range", "children_toward_still_parents", "tree_links_in_proved_cases",
           "TREE_LINK_CASES", "TreeLinkCases"]


# ------------------------------------------------------------------ bindings (issue 32)
# Each monitor below is derived from its lemma's one definition (.lemmas): the binding only says
# which robots of a step are an instance and reads their positions, normalised as the lemma is.

def _every_robot_step(view):
    """Every robot present at both ends of the step, its own start at the origin."""
    ks = view.robot_array()
    yield Batch({"robot": view.ids_of(ks)},
                {"s": view.s, "p_i_0_x": 0.0, "p_i_0_y": 0.0, **view.points("p_i_1", ks, 1)},
                facts={"moved": np.round(view.distances(ks, 1, ks, 0), 12), "limit": view.v * view.dt})


#: ``step_bounded``: no robot moves more than ``v dt`` in a step -- the premise
#: ``child_moves_at_most_v_dt`` of ``bounded_range`` (000/001 Lemma 7), for every robot.
STEP_BOUNDED = Binding("step_bounded", BOUNDED_RANGE, _every_robot_step, what="robot steps",
                       only=("child_moves_at_most_v_dt",), cites="bounded_range (000/001 Lemma 7)")


def _moving_parents_and_children(view):
    """Every robot that moved, with each child it decided the step with (state key
    ``"children"`` after the step), the child's start at the origin."""
    parents, children = [], []
    for k in view.robots():
        kids = view.state(k, "children")
        if not kids or not view.moved(k):
            continue                        # did not move: nothing to check (the link case "still")
        for c in kids:
            j = view.slot(c)
            if j is not None:
                parents.append(k)
                children.append(j)
    yield _link_batch(view, parents, children, ("parent", "child"),
                      facts={"distance": np.round(view.distances(parents, 1, children, 0), 12),
                             "bounded_range": view.phi - view.v * view.dt})


def _link_batch(view, parents, children, names, facts, child_first: bool = False) -> Batch:
    """Parent-child pairs as a batch of ``(s, p_p_0, p_p_1, p_c_1)`` with the child's start at
    the origin (the variables of ``nclb_link_kept`` and ``spanning_tree_kept``); the key names
    the parent first (``child_first``: the child)."""
    key = [(names[0], view.ids_of(parents)), (names[1], view.ids_of(children))]
    return Batch(dict(key[::-1] if child_first else key),
                 {"s": view.s, **view.points("p_p_0", parents, 0, children), **view.points("p_p_1", parents, 1, children),
                  **view.points("p_c_1", children, 1, children)}, facts=facts)


#: ``nclb``: every robot that moves ends inside the bounded range (001 Def. 8: disc of radius
#: ``phi - v dt``) of each child it decided the step with -- ``nclb_link_kept``, on the links of
#: the communication graph at ``t`` (premise ``link_at_t`` selects them).
NCLB = Binding("nclb", NCLB_LINK_KEPT, _moving_parents_and_children, what="moving-parent/child pairs",
               given=("step_below_range", "link_at_t"), cites="nclb_link_kept (001 Sec. V-C, Def. 8)")


def _relocate_under_root(view):
    """The relocate robot while its parent is the root (state keys ``relocate``, ``parent``,
    ``root_id`` after the step), the root's start at the origin; ``l = 1/2``: the path's midpoint
    (the lemma covers every point of it; the two ends are its premises)."""
    for k in view.robots():
        if not view.state(k, "relocate"):
            continue
        parent, root = view.state(k, "parent"), view.state(k, "root_id")
        if parent is None or parent != root:
            continue
        q = view.slot(root)
        if q is None:
            continue
        o = (q, 0)
        yield Instance({"relocate": view.id(k), "root": int(root)},
                       {**view.point("a", k, 0, o), **view.point("b", k, 1, o), "l": 0.5,
                        **view.point("r", q, 1, o)},
                       facts={"root_moved": round(view.distance(q, 1, q, 0), 12),
                              "start": round(view.distance(k, 0, q, 0), 12),
                              "end": round(view.distance(k, 1, q, 0), 12), "range": view.phi})


#: ``relocate``: while the relocate robot's parent is the root, the root stays still and both
#: ends of the relocate robot's step are within ``phi`` of it -- ``relocate_stays_in_range``.
RELOCATE = Binding("relocate", RELOCATE_STAYS_IN_RANGE, _relocate_under_root, what="relocate steps under the root",
                   cites="relocate_stays_in_range (001 Sec. V-C)")


def _children_of_still_parents(view):
    """Every robot that moved, not the relocate robot, whose parent (the same before and after
    the step) is present; its start at the origin."""
    parents, children = [], []
    for k in view.robots():
        par = view.state(k, "parent", when=0)
        if par is None or not view.moved(k) or view.state(k, "parent", default=None) != par:
            continue
        if view.state(k, "relocate", when=0, default=False) or view.state(k, "relocate", default=False):
            continue
        q = view.slot(par)
        if q is None:
            continue
        parents.append(q)
        children.append(k)
    yield _link_batch(view, parents, children, ("parent", "child"), child_first=True,
                      facts={"before": np.round(view.distances(children, 0, parents, 0), 12),
                             "after": np.round(view.distances(children, 1, parents, 0), 12)})


#: ``child_toward_parent``: a robot whose parent stays still does not end farther from it (001
#: Sec. V-C: "the children ... will only move toward the robot") -- the premise
#: ``child_not_farther`` of ``spanning_tree_kept``'s case ``child_not_farther_from_still_parent``,
#: where its premise ``parent_still`` holds (the relocate robot is left to ``relocate``).
CHILD_TOWARD_PARENT = Binding("child_toward_parent", SPANNING_TREE_KEPT, _children_of_still_parents,
                              what="child moves toward a still parent", given=("parent_still",),
                              only=("parent_still", "child_not_farther"),
                              cites="spanning_tree_kept, case child_not_farther_from_still_parent "
                                    "(001 Sec. V-C, Lemma 11)")


def step_bounded(trace, v: float, dt: float, phi: float = 1.0) -> InvariantResult:
    """:data:`STEP_BOUNDED` over ``trace``: no robot moves more than ``v*dt`` in a step.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.2, 0, 0]]], dtype=float)
    >>> r = step_bounded(Trace(ids=[1, 2], poses=poses, states=[((), ())] * 2), v=0.1, dt=1.0)
    >>> r.status, r.witness["robot"], r.witness["moved"], r.witness["premise"]
    ('violated', 2, 0.2, 'child_moves_at_most_v_dt')
    """
    return STEP_BOUNDED.check(trace, phi, v, dt)


def parents_in_bounded_ranges(trace, phi: float, v: float, dt: float) -> InvariantResult:
    """:data:`NCLB` over ``trace`` (lemma ``nclb_link_kept``)."""
    return NCLB.check(trace, phi, v, dt)


def relocate_path_in_range(trace, phi: float, v: float = 0.0, dt: float = 1.0) -> InvariantResult:
    """:data:`RELOCATE` over ``trace`` (lemma ``relocate_stays_in_range``)."""
    return RELOCATE.check(trace, phi, v, dt)


def children_toward_still_parents(trace, phi: float, v: float, dt: float) -> InvariantResult:
    """:data:`CHILD_TOWARD_PARENT` over ``trace``.  Added 2026-11-24: a subtree robot that drove
    away from its still parent broke links with every other premise met (docs/song2016.md, "Case 3
    steered to the nearest safe point").

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.1, 0, 0]]], dtype=float)
    >>> st = ((("parent", None), ("relocate", False)), (("parent", 1), ("relocate", False)))
    >>> r = children_toward_still_parents(Trace(ids=[1, 2], poses=poses, states=[st] * 2), 1.2, 0.1, 1.0)
    >>> r.status, r.witness["child"], r.witness["parent"], r.witness["after"], r.witness["premise"]
    ('violated', 2, 1, 1.1, 'child_not_farther')
    """
    return CHILD_TOWARD_PARENT.check(trace, phi, v, dt)


#: The cases of ``spanning_tree_kept`` a link can be in (:func:`tree_links_in_proved_cases`);
#: the last is checked at run time only: no lemma with premises covers it (docs/proofs.md).
TREE_LINK_CASES = ("nclb", "child_not_farther_from_still_parent", "relocate_in_root_range_monitored")


def tree_links_in_proved_cases(trace, phi: float, v: float, dt: float, *,
                               tol: float = 1e-9) -> InvariantResult:
    """Every link of the tree a step decided falls in a case whose link-keeping is proved (the
    property ``tree_link_cases``, :mod:`.properties`).

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
    or, step by step, the one-step windows of
    :class:`~swarmproof.invariants.premises.StepFeed` (the property's streaming monitor, fed by
    the engine); :meth:`result` judges
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
        name, cites = "tree_link_cases", self.cites
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


for _binding in (STEP_BOUNDED, NCLB, RELOCATE, CHILD_TOWARD_PARENT):
    register_binding(_binding)
