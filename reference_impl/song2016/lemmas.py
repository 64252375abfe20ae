"""z3 encodings of Song & O'Kane's geometric safety lemmas (000 and 001; issue 5).

One small encoding per lemma, named after the mathematics, its variables indexed by time
step (``p_i_0`` is ``p_i(t)``, ``p_i_1`` is ``p_i(t+dt)``); the prover
(:mod:`swarmproof.checkers.proofs`) shows each valid by refuting its negation, with a
negative control and vacuity controls.  Every lemma is stated normalised (a point at the
origin, ``phi = 1``, ``s = v*dt/phi``: the normalisation lemmas of
:mod:`swarmproof.invariants.lemmas`).

* :data:`LEMMAS` -- the suite: ``bounded_range`` (000/001 Lemma 7), its strict form,
  ``nclb_link_kept`` (001 Sec. V-C, Def. 8), ``spanning_tree_kept`` (one link of Lemma 11's
  proof), ``relocate_stays_in_range``, ``safe_region_nonempty``, ``intermediate_goal_in_region``;
* :data:`EXTRA_LEMMAS` -- run only when named: known-false variants (findings) and a true
  lemma too hard for z3;
* :data:`CASE_FAMILIES` -- Lemma 11 stated directly on every small rooted tree
  (:func:`tree_case_encoding`, :func:`tree_cases`, :func:`rooted_shape`), confirmed by
  :func:`swarmproof.checkers.proofs.confirm_trees`.

Their runtime monitors (the premises on every step of a run) are in :mod:`.monitors`.

References
----------
000_3ad33c5b62f11d5f.txt Lemma 7, Sec. IV-C, Fig. 6;
001_7a4e517b856331bc.txt Lemma 7, Def. 8, Sec. V-C, Lemma 11.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable

import z3

from swarmproof.invariants.lemma_api import And, Eq, Ge, Gt, Le, LemmaSpec, Lt, Point, Real, constant
from swarmproof.invariants.lemmas import (ORIGIN as _ORIGIN, Encoding, Lemma, add as _add, dist2, eq as _eq,
                                          point as _pt, scale as _scale, sub as _sub, variables as _vars)

__all__ = ["LEMMAS", "EXTRA_LEMMAS", "CASE_FAMILIES", "TREE_SOLVER_PARAMS", "tree_case_encoding", "tree_case_spec",
           "tree_cases",
           "rooted_shape", "bounded_range", "nclb_link_kept", "tree_link_kept", "tree_link_kept_control",
           "relocate_stays_in_range", "safe_region_nonempty", "intermediate_goal_in_region",
           "intermediate_goal_partial_progress", "nclb_three_children_direct", "RELOCATE_STAYS_IN_RANGE"]


def _step_range(s) -> tuple:
    """``0 < s < 1``: ``s = v*dt/phi``; the papers assume ``v*dt < phi``."""
    return ("step_below_range", z3.And(s > 0, s < 1))


_S_NORM = "scale: phi = 1, s = v*dt/phi in (0, 1) (scale_invariance)"


def _t(what: str) -> str:
    return f"translation: {what} at the origin (translation_invariance)"


# ---------------------------------------------------- the safety lemmas

def _step(v):
    """``0 < s < 1``: ``s = v*dt/phi``; the papers assume ``v*dt < phi`` (a premise function)."""
    return And(Gt(v.s, 0), Lt(v.s, 1))


_STEP = ("step_below_range", _step)


def _bounded_radius2(v, radius: str):
    """The squared radius of Def. 8's bounded range, ``(phi - v dt)^2``, or ``phi^2`` (a control)."""
    return (1 - v.s) * (1 - v.s) if radius == "phi_minus_vdt" else constant(1, v.s)


def _bounded_range_premises(radius: str = "phi_minus_vdt", strict: bool = False, open_range: bool = False) -> tuple:
    near = Lt if strict else Le
    within = Lt if open_range else Le
    return (
        _STEP,
        ("neighbours_at_t", lambda v: near(dist2(v.p_i_0), 1)),
        ("child_moves_at_most_v_dt", lambda v: Le(dist2(v.p_i_1, v.p_i_0), v.s * v.s)),
        ("parent_moves_at_most_v_dt", lambda v: Le(dist2(v.p_p_1), v.s * v.s)),
        ("child_in_parent_bounded_range", lambda v: within(dist2(v.p_i_1), _bounded_radius2(v, radius))),
    )


def _bounded_range_spec(lemma_id: str, statement: str, cites: tuple, strict: bool, open_range: bool,
                        control: tuple, control_note: str, kind: str = "auxiliary") -> LemmaSpec:
    """000 Lemma 7 / 001 Lemma 7, normalised: ``p_p(t) = 0``, ``phi = 1``, ``s = v dt/phi``.

    Premises: ``||p_i(t)|| <= 1`` (neighbours; ``< 1`` if ``strict``),
    ``||p_i(t+dt) - p_i(t)|| <= s``, ``||p_p(t+dt)|| <= s``,
    ``||p_i(t+dt)|| <= 1 - s`` (``< 1 - s`` if ``open_range``).
    Conclusion: ``||p_i(t+dt) - p_p(t+dt)|| <= 1`` (``< 1`` if ``strict``).
    ``control``: the arguments of :func:`_bounded_range_premises` for the negative control."""
    near = Lt if strict else Le
    return LemmaSpec(
        id=lemma_id, statement=statement, kind=kind, cites=cites,
        variables=(Real("s", 0.0, 1.0), Point("p_i_0"), Point("p_i_1"), Point("p_p_1")),
        premises=_bounded_range_premises("phi_minus_vdt", strict, open_range),
        conclusion=lambda v: near(dist2(v.p_i_1, v.p_p_1), 1),
        control_premises=_bounded_range_premises(*control),
        normalisations=(_t("p_p(t)"), _S_NORM), control_note=control_note)


def _nclb_premises(radius: str) -> tuple:
    return (
        _STEP,
        ("link_at_t", lambda v: Le(dist2(v.p_p_0), 1)),
        ("parent_moves_at_most_v_dt", lambda v: Le(dist2(v.p_p_1, v.p_p_0), v.s * v.s)),
        ("parent_in_child_bounded_range", lambda v: Le(dist2(v.p_p_1), _bounded_radius2(v, radius))),
        ("child_moves_at_most_v_dt", lambda v: Le(dist2(v.p_c_1), v.s * v.s)),
    )


_LINK_VARIABLES = (Real("s", 0.0, 1.0), Point("p_p_0"), Point("p_p_1"), Point("p_c_1"))


def _link_kept(v):
    return Le(dist2(v.p_p_1, v.p_c_1), 1)


def _nclb_spec() -> LemmaSpec:
    """001 Sec. V-C (NCLB) for one parent-child link, normalised: ``p_c(t) = 0``.

    Premises: the link holds at ``t`` (``||p_p(t)|| <= 1``), the parent moves at
    most ``s`` and ends in the child's bounded range (Def. 8:
    ``||p_p(t+dt)|| <= 1 - s``), the child moves at most ``s``.
    Conclusion: ``||p_p(t+dt) - p_c(t+dt)|| <= 1``.  The control: radius ``phi``."""
    return LemmaSpec(
        id="nclb_link_kept",
        statement="A parent that moves at most v dt into the bounded range (Def. 8: disc of "
                  "radius phi - v dt around p_c(t)) of a child that moves at most v dt stays "
                  "within phi of that child: ||p_p(t+dt) - p_c(t+dt)|| <= phi.",
        cites=("001_7a4e517b856331bc.txt Sec. V-C (NCLB), Def. 8, Lemma 7",),
        normalisations=(_t("p_c(t)"), _S_NORM),
        variables=_LINK_VARIABLES, premises=_nclb_premises("phi_minus_vdt"), conclusion=_link_kept,
        control_premises=_nclb_premises("phi"),
        control_note="parent anywhere within phi of the child's old position")


def _tree_link_spec() -> LemmaSpec:
    """One link of the spanning tree in the cases of 001 Sec. V-C's motion strategy that the
    run-time monitor ``tree_link_cases`` checks; normalised: ``p_c(t) = 0``.

    * ``nclb``: the parent moves inside the child's bounded range, the child
      moves at most ``s`` (the premises of ``nclb_link_kept``);
    * ``child_not_farther_from_still_parent``: the parent does not move and the child
      ends no farther from it than it started (case 3 of Sec. V-C, and "children ...
      will only move toward the robot" when a safe region is empty).

    In each case the link is kept: ``||p_p(t+dt) - p_c(t+dt)|| <= 1``.  Not covered
    (``not_proved``): links a child chose in the step, the relocate robot heading for
    its vacancy, the relocate robot's nearest-safe-point move toward a non-root parent.
    The control: the ``nclb`` case with radius ``phi``, no other case."""
    nclb = _nclb_premises("phi_minus_vdt")
    return LemmaSpec(
        id="spanning_tree_kept",
        statement="One link of the spanning tree, in the two cases of the motion strategy the "
                  "run-time monitor tree_link_cases checks (the parent moves inside the child's "
                  "bounded range and the child moves at most v dt; the parent stays still and the "
                  "child ends no farther from it): the link is kept, ||p_p(t+dt) - p_c(t+dt)|| <= phi. "
                  "One link only, not Lemma 11: the composition over the tree's links is argued on "
                  "paper (docs/proofs.md), and the cases listed as not proved are not covered.",
        cites=("001_7a4e517b856331bc.txt Lemma 11's proof, Sec. V-C (one link; Lemma 11 itself is not proved)",),
        normalisations=(_t("p_c(t)"), _S_NORM),
        variables=_LINK_VARIABLES, premises=nclb[:2], conclusion=_link_kept,
        cases=(("nclb", nclb[2:]),
               ("child_not_farther_from_still_parent", (
                   ("parent_still", lambda v: And(Eq(v.p_p_1[0], v.p_p_0[0]), Eq(v.p_p_1[1], v.p_p_0[1]))),
                   ("child_not_farther", lambda v: Le(dist2(v.p_c_1, v.p_p_0), dist2(v.p_p_0))),
               ))),
        control_premises=_nclb_premises("phi"), control_cases=(),
        control_note="nclb case with the parent anywhere within phi of the child",
        not_proved=(
            "links a child chose in the step: the parent moves without counting it among its "
            "children (messages take one step), so no NCLB premise holds for them -- swarmproof "
            "finds them breaking (song2016, square n=20 seed 1, step 344)",
            "the relocate robot heading for its vacancy while its parent is the root: its link "
            "is checked at run time only (monitor tree_link_cases, case relocate_in_root_range_monitored)",
            "the relocate robot moving toward a parent that is not the root by the nearest safe "
            "point (Fig. 11's intermediate goal): it can move away from that parent, and a "
            "crafted state breaks the link",
            "the composition of the per-link cases into Lemma 11 (the tree at t+dt spans the "
            "communication graph): argued on paper in docs/proofs.md, not by z3",
        ))


def bounded_range(range_radius_factor: str = "phi_minus_vdt", strict: bool = False,
                  open_range: bool = False) -> Encoding:
    """000 Lemma 7 / 001 Lemma 7 as z3 terms (:data:`BOUNDED_RANGE`'s variables); the arguments
    pick the radius (``"phi"``: the control's), strict neighbours and the open bounded range."""
    near = Lt if strict else Le
    return dataclasses.replace(BOUNDED_RANGE, premises=_bounded_range_premises(range_radius_factor, strict, open_range),
                               conclusion=lambda v: near(dist2(v.p_i_1, v.p_p_1), 1)).build()


def nclb_link_kept(radius: str = "phi_minus_vdt") -> Encoding:
    """:data:`NCLB_LINK_KEPT` as z3 terms (``radius="phi"``: its negative control)."""
    return NCLB_LINK_KEPT.build() if radius == "phi_minus_vdt" else NCLB_LINK_KEPT.control()


def tree_link_kept() -> Encoding:
    """:data:`SPANNING_TREE_KEPT` as z3 terms."""
    return SPANNING_TREE_KEPT.build()


def tree_link_kept_control() -> Encoding:
    """Control of ``spanning_tree_kept``: the ``nclb`` case with radius ``phi``."""
    return SPANNING_TREE_KEPT.control()


def _relocate_spec(endpoint_radius2: int) -> LemmaSpec:
    """``relocate_stays_in_range`` declared once (issue 32: one definition for the proof and
    for float judgments, swarmproof.invariants.lemma_api): a point on a segment between two
    points within ``phi`` of a stationary robot is within ``phi`` of it.  Normalised: the
    stationary robot (the root) at the origin, ``phi = 1``.  The control lets one endpoint be
    ``2 phi`` away (``endpoint_radius2 = 4``)."""
    def end(radius2):
        return ("end_within_range", lambda v: Le(dist2(v.b), radius2))

    start = ("start_within_range", lambda v: Le(dist2(v.a), 1))
    on_segment = ("on_segment", lambda v: And(Ge(v.l, 0), Le(v.l, 1)))
    # the stationary robot's position after the step (before it: the origin); stated since issue 32
    # so that the runtime monitor derived from this definition checks it (it was implicit before)
    still = ("root_still", lambda v: And(Eq(v.r[0], 0), Eq(v.r[1], 0)))
    return LemmaSpec(
        id="relocate_stays_in_range",
        statement="A robot moving along the straight segment between two points within phi of "
                  "a stationary robot stays within phi of it.",
        variables=(Point("a"), Point("b"), Real("l", 0.0, 1.0), Point("r")),
        premises=(start, end(endpoint_radius2), on_segment, still),
        conclusion=lambda v: Le(dist2(_add(v.a, _scale(v.l, _sub(v.b, v.a))), v.r), 1),
        control_premises=(start, end(4), on_segment, still),
        cites=("001_7a4e517b856331bc.txt Sec. V-C case 2 (relocate robot toward the vacancy)",),
        normalisations=(_t("the stationary robot"), "scale: phi = 1 (scale_invariance)"),
        control_note="the segment's end may be 2 phi away",
        not_proved=("that the relocate robot's step ends within phi of the root: the run-time "
                    "monitor checks that end directly (a disc is convex; this lemma only extends "
                    "the two ends to the path between them)",),
    )


def relocate_stays_in_range(endpoint_radius2: int = 1) -> Encoding:
    """The z3 encoding of :data:`RELOCATE_STAYS_IN_RANGE` (``endpoint_radius2 = 4``: its
    negative control)."""
    return _relocate_spec(endpoint_radius2).build()


def _safe_region_premises(children: int, ds_bound: str) -> tuple:
    def within(k):
        return (f"child_{k}_within_d_s", lambda v: Le(dist2(getattr(v, f"c{k}_0")), v.d_s * v.d_s))

    bound = (lambda v: 1 - v.s) if ds_bound == "phi_minus_vdt" else (lambda v: constant(1, v.s))
    return (_STEP, ("safe_distance", lambda v: And(Gt(v.d_s, 0), Lt(v.d_s, bound(v))))) + tuple(
        within(k) for k in range(children))


def _safe_region_spec(children: int = 3) -> LemmaSpec:
    """001 Sec. V-C: every child within ``d_s < phi - v dt`` of its parent puts the
    parent's own position in every child's bounded range.  Normalised: the
    parent at the origin.  Stated for ``children`` children at once (each
    conjunct uses only its own child's premise).  The control allows
    ``d_s < phi``."""
    return LemmaSpec(
        id="safe_region_nonempty",
        statement="If every child is within d_s < phi - v dt of its parent, the parent's own "
                  "position lies in every child's bounded range, so the safe region (their "
                  "intersection) is not empty (stated for 3 children).",
        cites=("001_7a4e517b856331bc.txt Sec. V-C (safe distance d_s), Def. 8",),
        normalisations=(_t("p_p(t)"), _S_NORM),
        variables=(Real("s", 0.0, 1.0), Real("d_s", 0.0, 1.0)) + tuple(Point(f"c{k}_0") for k in range(children)),
        premises=_safe_region_premises(children, "phi_minus_vdt"),
        conclusion=lambda v: And(*[Le(dist2((0, 0), getattr(v, f"c{k}_0")), (1 - v.s) * (1 - v.s))
                                   for k in range(children)]),
        control_premises=_safe_region_premises(children, "phi"),
        control_note="d_s < phi instead of d_s < phi - v dt",
        not_proved=("that the children do come within d_s (Sec. V-C's 'the safe region will "
                    "eventually be non-empty' is a liveness claim; this is one moment of it)",))


def safe_region_nonempty(children: int = 3, ds_bound: str = "phi_minus_vdt") -> Encoding:
    """:func:`_safe_region_spec` as z3 terms (``ds_bound="phi"``: its negative control)."""
    spec = _safe_region_spec(children)
    return spec.build() if ds_bound == "phi_minus_vdt" else spec.control()


def _intermediate_goal_premises(neighbour_radius2: int) -> tuple:
    return (_STEP, ("neighbours_at_t", lambda v: Le(dist2(v.p_i_0), neighbour_radius2)))


def _witness(v):
    """``(1 - s) p_i(t)``: a point of ``P_i & P_p``."""
    return _scale(1 - v.s, v.p_i_0)


#: 000 Sec. IV-C, Fig. 6: ``P_i & P_p`` (discs of radius ``v dt`` around ``p_i(t)`` and
#: ``phi - v dt`` around ``p_p(t)``) is not empty when the robots are neighbours: the point
#: ``(1 - s) p_i(t)`` lies in both.  Normalised: ``p_p(t) = 0``.  (That a goal chosen in
#: ``P_i & P_p`` and reached at ``t+dt`` meets the premises of ``bounded_range`` is the
#: definition of the two discs, not a fact for z3: the two conclusion parts that said so
#: repeated the premises and were removed, issue 19.)  The control lets the robots be up to
#: ``2 phi`` apart.
INTERMEDIATE_GOAL_IN_REGION = LemmaSpec(
    id="intermediate_goal_in_region",
    statement="P_i & P_p (discs of radius v dt around p_i(t) and phi - v dt around p_p(t)) is "
              "not empty when the robots are neighbours: (1 - s) p_i(t) lies in both. (A goal "
              "chosen there and reached at t+dt meets bounded_range's premises by definition.)",
    cites=("000_3ad33c5b62f11d5f.txt Sec. IV-C steps 1-3, Fig. 6, Lemma 7",),
    normalisations=(_t("p_p(t)"), _S_NORM),
    variables=(Real("s", 0.0, 1.0), Point("p_i_0")),
    premises=_intermediate_goal_premises(1), conclusion=None,
    parts=(("witness_in_P_i", lambda v: Le(dist2(_witness(v), v.p_i_0), v.s * v.s)),
           ("witness_in_P_p", lambda v: Le(dist2(_witness(v)), (1 - v.s) * (1 - v.s)))),
    control_premises=_intermediate_goal_premises(4),
    control_note="the robots up to 2 phi apart instead of phi",
    not_proved=("that the robot reaches its goal within the step: it may not "
                "(intermediate_goal_partial_progress, a counterexample)",))


def intermediate_goal_in_region(neighbour_radius2: int = 1) -> Encoding:
    """:data:`INTERMEDIATE_GOAL_IN_REGION` as z3 terms (``neighbour_radius2=4``: its negative
    control)."""
    spec = INTERMEDIATE_GOAL_IN_REGION
    return spec.build() if neighbour_radius2 == 1 else spec.control()


# -------------------------------------------- findings and hard lemmas

def intermediate_goal_partial_progress() -> Encoding:
    """:data:`INTERMEDIATE_GOAL_PARTIAL_PROGRESS` as z3 terms."""
    return INTERMEDIATE_GOAL_PARTIAL_PROGRESS.build()


def nclb_three_children_direct() -> Encoding:
    """:data:`NCLB_THREE_CHILDREN_DIRECT` as z3 terms."""
    return NCLB_THREE_CHILDREN_DIRECT.build()


# ------------------------------------------------------------- the suite



#: ``relocate_stays_in_range`` declared once (the proof and float judgments read it).
RELOCATE_STAYS_IN_RANGE = _relocate_spec(1)

#: 000 Lemma 7 / 001 Lemma 7 declared once (the proof and float judgments read it).
BOUNDED_RANGE = _bounded_range_spec(
    "bounded_range",
    "If r_i and r_p are neighbours at t (||p_i(t) - p_p(t)|| <= phi), each moves "
    "at most v dt, and ||p_i(t+dt) - p_p(t)|| <= phi - v dt, then "
    "||p_i(t+dt) - p_p(t+dt)|| <= phi.",
    ("000_3ad33c5b62f11d5f.txt Lemma 7, Eqs. 5-7", "001_7a4e517b856331bc.txt Lemma 7"),
    strict=False, open_range=False, control=("phi", False, False),
    control_note="bounded range of radius phi instead of phi - v dt", kind="paper lemma")

BOUNDED_RANGE_STRICT = _bounded_range_spec(
    "bounded_range_strict",
    "With neighbours strictly closer than phi (docs/decisions.md, Model and "
    "geometry) Lemma 7 needs the open bounded range: if ||p_i(t) - p_p(t)|| < phi, "
    "each moves at most v dt and ||p_i(t+dt) - p_p(t)|| < phi - v dt, then "
    "||p_i(t+dt) - p_p(t+dt)|| < phi.",
    ("000_3ad33c5b62f11d5f.txt Lemma 7", "001_7a4e517b856331bc.txt Lemma 7, Def. 4"),
    strict=True, open_range=True, control=("phi_minus_vdt", True, False),
    control_note="closed bounded range (<= phi - v dt) with strict neighbours: "
                 "a pair can end exactly phi apart")

BOUNDED_RANGE_STRICT_CLOSED = _bounded_range_spec(
    "bounded_range_strict_closed",
    "FINDING (expected counterexample): with neighbours strictly closer than phi "
    "and the closed bounded range of Def. 8, a pair can end exactly phi apart.",
    ("001_7a4e517b856331bc.txt Lemma 7, Def. 8",),
    strict=True, open_range=False, control=("phi", True, False),
    control_note="bounded range of radius phi")

NCLB_LINK_KEPT = _nclb_spec()
SPANNING_TREE_KEPT = _tree_link_spec()
SAFE_REGION_NONEMPTY = _safe_region_spec(3)

#: The song2016 lemmas declared as :class:`LemmaSpec` (issue 32), by id.
SPECS: dict = {spec.id: spec for spec in (BOUNDED_RANGE, BOUNDED_RANGE_STRICT, NCLB_LINK_KEPT, SPANNING_TREE_KEPT,
                                          RELOCATE_STAYS_IN_RANGE, SAFE_REGION_NONEMPTY,
                                          INTERMEDIATE_GOAL_IN_REGION, BOUNDED_RANGE_STRICT_CLOSED)}

#: The suite's lemmas of these papers, in order (``swarmproof prove`` runs them after the
#: normalisation lemmas).
_LEMMA_LIST = [spec.lemma() for spec in (BOUNDED_RANGE, BOUNDED_RANGE_STRICT, NCLB_LINK_KEPT, SPANNING_TREE_KEPT,
                                         RELOCATE_STAYS_IN_RANGE, SAFE_REGION_NONEMPTY, INTERMEDIATE_GOAL_IN_REGION)]

#: These papers' lemmas by id, in order (:mod:`swarmproof.checkers.proofs` puts them in its suite).
LEMMAS: dict = {lem.id: lem for lem in _LEMMA_LIST}

#: Lemmas run only when named: known-false variants (findings) and a true
#: lemma too hard for z3 (the honest timeout).
def _partial_end(v):
    """``p_i(t+dt) = p_i(t) + l (g - p_i(t))``: part of the way to the goal ``g``."""
    return _add(v.p_i_0, _scale(v.l, _sub(v.g, v.p_i_0)))


#: A robot that drives only part of the way to its intermediate goal ``g`` (``0 <= l <= 1``, e.g.
#: because part of the step was spent turning) is NOT always in the parent's bounded range: z3
#: finds a counterexample.  000 Sec. IV-C assumes the goal is reached.  A finding (expected
#: counterexample); its control is ``intermediate_goal_in_region``'s.
INTERMEDIATE_GOAL_PARTIAL_PROGRESS = LemmaSpec(
    id="intermediate_goal_partial_progress",
    statement="FINDING (expected counterexample): a robot that covers only part of the way "
              "to its intermediate goal may end outside the parent's bounded range.",
    cites=("000_3ad33c5b62f11d5f.txt Sec. IV-C, Lemma 7",),
    normalisations=(_t("p_p(t)"), _S_NORM),
    variables=(Real("s", 0.0, 1.0), Real("l", 0.0, 1.0), Point("p_i_0"), Point("g")),
    premises=(_STEP,
              ("neighbours_at_t", lambda v: Le(dist2(v.p_i_0), 1)),
              ("goal_in_P_i", lambda v: Le(dist2(v.g, v.p_i_0), v.s * v.s)),
              ("goal_in_P_p", lambda v: Le(dist2(v.g), (1 - v.s) * (1 - v.s))),
              ("partial_progress", lambda v: And(Ge(v.l, 0), Le(v.l, 1)))),
    conclusion=lambda v: Le(dist2(_partial_end(v)), (1 - v.s) * (1 - v.s)),
    control_of=INTERMEDIATE_GOAL_IN_REGION, control_note="the robots up to 2 phi apart",
)


def _three_children_premises() -> tuple:
    prem = [_STEP, ("parent_moves_at_most_v_dt", lambda v: Le(dist2(v.p_p_1), v.s * v.s))]
    for k in range(3):
        c0, c1 = f"c{k}_0", f"c{k}_1"
        prem += [
            (f"link_{k}_at_t", lambda v, c0=c0: Le(dist2(getattr(v, c0)), 1)),
            (f"child_{k}_moves_at_most_v_dt",
             lambda v, c0=c0, c1=c1: Le(dist2(getattr(v, c1), getattr(v, c0)), v.s * v.s)),
            (f"parent_in_bounded_range_of_{k}",
             lambda v, c0=c0: Le(dist2(v.p_p_1, getattr(v, c0)), (1 - v.s) * (1 - v.s))),
        ]
    return tuple(prem)


#: NCLB for a parent with three children at once, not normalised per child (DESIGN.md section 4:
#: did not finish in 300 s).  True, but too hard for z3 in any short budget: the honest source of
#: an inconclusive in the tests.  Its control is ``nclb_link_kept``'s (one child, radius phi).
NCLB_THREE_CHILDREN_DIRECT = LemmaSpec(
    id="nclb_three_children_direct",
    statement="NCLB for three children at once, un-normalised: true, but too hard for z3 "
              "within its budget (DESIGN.md section 4).",
    cites=("001_7a4e517b856331bc.txt Sec. V-C",),
    normalisations=(_S_NORM,),
    variables=(Real("s", 0.0, 1.0), Point("p_p_1"), *(Point(f"c{k}_0") for k in range(3)),
               *(Point(f"c{k}_1") for k in range(3))),
    premises=_three_children_premises(),
    conclusion=lambda v: And(*[Le(dist2(v.p_p_1, getattr(v, f"c{k}_1")), 1) for k in range(3)]),
    control_of=NCLB_LINK_KEPT, control_note="one child, radius phi",
    # z3 did not finish it in 300 s; a budget of about 5 s of work shows the honest
    # inconclusive without the prover's default of about a minute (docs/proofs.md "Budgets")
    rlimit=20_000_000,
)

SPECS.update({s.id: s for s in (INTERMEDIATE_GOAL_PARTIAL_PROGRESS, NCLB_THREE_CHILDREN_DIRECT)})

EXTRA_LEMMAS: dict = {
    "bounded_range_strict_closed": BOUNDED_RANGE_STRICT_CLOSED.lemma(),
    "intermediate_goal_partial_progress": INTERMEDIATE_GOAL_PARTIAL_PROGRESS.lemma(),
    "nclb_three_children_direct": NCLB_THREE_CHILDREN_DIRECT.lemma(),
}


# ------------------------------------- direct confirmation on small trees

#: nlsat option for the direct tree confirmation: keep the variables in the order
#: they first appear (``s``, the moves ``m_k``, then each link's vector) instead
#: of nlsat's reordering heuristic.  Measured (docs/performance.md, "Proof
#: suite"): with the heuristic 222 of the 640 cases up to 5 robots timed out at
#: 2 s; with this order and the conclusion proved link by link, none.
TREE_SOLVER_PARAMS = (("variable_ordering_strategy", 3),)


def tree_case_spec(tree, root, moving) -> LemmaSpec:
    """001 Lemma 11 stated directly for one rooted tree and one set of moving robots (no per-link
    lemma used), declared once (issue 32): all links' premises at once, conclusion "every link
    kept", one ``part`` per link.  Its negative control is NCLB with radius ``phi`` instead of
    ``phi - v dt``.

    Normalisations (docs/proofs.md): the root's old position at the origin, ``phi = 1``,
    ``s = v dt / phi``; a robot that does not move has the constant move ``(0, 0)``.  Variables
    are per link (a linear change of coordinates, one-to-one for a tree): for a moving parent
    ``u_c = p_p(t+dt) - p_c(t)``, for a still parent ``d_c = p_c(t) - p_p(t)``;
    ``m_k = p_k(t+dt) - p_k(t)`` for a moving robot.  The case of each link follows the motion
    strategy (001 Sec. V-C): a moving parent obeys NCLB, a child of a still parent moves straight
    toward it (``m_c = -l_c d_c``, ``0 <= l_c <= 1``)."""
    import networkx as nx

    parent = {v: u for u, v in nx.bfs_edges(tree, root)}

    def m(v, k):
        return getattr(v, f"m{k}") if k in moving else (constant(0, v.s), constant(0, v.s))

    def premises(control: bool) -> tuple:
        def rad2(v):
            return constant(1, v.s) if control else (1 - v.s) * (1 - v.s)

        prem = [_STEP] + [(f"robot_{k}_moves_at_most_v_dt", lambda v, k=k: Le(dist2(m(v, k)), v.s * v.s))
                          for k in sorted(moving)]
        for c, p in sorted(parent.items()):
            if p in moving:
                prem += [(f"link_{p}_{c}_at_t", lambda v, c=c, p=p: Le(dist2(getattr(v, f"u{c}"), m(v, p)), 1)),
                         (f"nclb_{p}_in_bounded_range_of_{c}",
                          lambda v, c=c: Le(dist2(getattr(v, f"u{c}")), rad2(v)))]
            else:
                prem.append((f"link_{p}_{c}_at_t", lambda v, c=c: Le(dist2(getattr(v, f"d{c}")), 1)))
                if c in moving:
                    def toward(v, c=c):
                        lam, d, mc = getattr(v, f"l{c}"), getattr(v, f"d{c}"), m(v, c)
                        step = _scale(-lam, d)
                        return And(Ge(lam, 0), Le(lam, 1), And(Eq(mc[0], step[0]), Eq(mc[1], step[1])))
                    prem.append((f"child_{c}_toward_still_parent_{p}", toward))
        return tuple(prem)

    parts, variables = [], [Real("s", 0.0, 1.0)] + [Point(f"m{k}", -1.0, 1.0) for k in sorted(moving)]
    for c, p in sorted(parent.items()):
        if p in moving:
            parts.append((f"link_{p}_{c}_kept", lambda v, c=c: Le(dist2(m(v, c), getattr(v, f"u{c}")), 1)))
            variables.append(Point(f"u{c}"))
        else:
            parts.append((f"link_{p}_{c}_kept", lambda v, c=c: Le(dist2(_add(getattr(v, f"d{c}"), m(v, c))), 1)))
            if c in moving:
                variables.append(Real(f"l{c}", 0.0, 1.0))
            variables.append(Point(f"d{c}"))
    return LemmaSpec(
        id=f"spanning_tree_case_{rooted_shape(tree, root, moving)}",
        statement="001 Lemma 11 for one rooted tree and one set of moving robots: every link kept.",
        cites=("001_7a4e517b856331bc.txt Lemma 11, Sec. V-C",),
        normalisations=(_t("the root's old position"), _S_NORM),
        variables=tuple(variables), premises=premises(False), conclusion=None, parts=tuple(parts),
        control_premises=premises(True), control_note="NCLB with radius phi instead of phi - v dt",
        solver_params=TREE_SOLVER_PARAMS)


def tree_case_encoding(tree, root, moving, bounded_range: str = "phi_minus_vdt") -> Encoding:
    """:func:`tree_case_spec` as z3 terms (``bounded_range="phi"``: its negative control).

    Examples
    --------
    >>> import networkx as nx
    >>> enc = tree_case_encoding(nx.path_graph(3), 0, frozenset({1}))
    >>> [name for name, _ in enc.premises]
    ['step_below_range', 'robot_1_moves_at_most_v_dt', 'link_0_1_at_t', 'child_1_toward_still_parent_0', 'link_1_2_at_t', 'nclb_1_in_bounded_range_of_2']
    >>> [name for name, _ in enc.parts]
    ['link_0_1_kept', 'link_1_2_kept']
    """
    spec = tree_case_spec(tree, root, moving)
    return spec.build() if bounded_range == "phi_minus_vdt" else spec.control()


def rooted_shape(tree, root, moving) -> str:
    """Canonical form of a rooted tree whose vertices are marked moving (``m``)
    or still (``s``): nested brackets, children sorted (Aho, Hopcroft and
    Ullman's tree isomorphism code).  Two cases get the same string iff an
    isomorphism of rooted trees maps one onto the other and its moving robots
    onto the other's moving robots; their Lemma 11 statements are then the same
    formula up to renaming variables and reordering conjuncts, so one z3
    answer decides both (docs/proofs.md, "Symmetry reduction").

    Examples
    --------
    >>> import networkx as nx
    >>> rooted_shape(nx.path_graph(3), 0, {2})
    '(s(s(m)))'
    >>> rooted_shape(nx.path_graph(3), 2, {0}) == rooted_shape(nx.path_graph(3), 0, {2})
    True
    >>> rooted_shape(nx.path_graph(3), 1, {0})
    '(s(m)(s))'
    """
    def code(v, up):
        kids = sorted(code(w, v) for w in tree[v] if w != up)
        return "(" + ("m" if v in moving else "s") + "".join(kids) + ")"

    return code(root, None)


def tree_cases(max_robots: int):
    """Every case of the direct confirmation, in a fixed order: for ``n`` from 2
    to ``max_robots``, every tree shape (``networkx.nonisomorphic_trees``, nodes
    ``0..n-1``), every root, every subset of moving robots (by bit mask).

    Yields ``(n, tree, root, moving)``.

    Examples
    --------
    >>> sum(1 for _ in tree_cases(3))
    32
    """
    import networkx as nx

    for n in range(2, max_robots + 1):
        for tree in nx.nonisomorphic_trees(n):
            tree = nx.convert_node_labels_to_integers(tree)
            for root in range(n):
                for mask in range(2 ** n):
                    yield n, tree, root, frozenset(k for k in range(n) if mask >> k & 1)


@dataclass(frozen=True)
class CaseFamily:
    """A lemma stated directly on every small case (each case one z3 problem) with a symmetry
    key: what :func:`swarmproof.checkers.proofs.confirm_trees` solves."""

    lemma: str
    cases: Callable
    encode: Callable
    key: Callable
    solver_params: tuple
    variants: tuple


#: Lemma 11 on every rooted tree and set of moving robots (001 Sec. V-C; docs/proofs.md):
#: ``variants`` are the bounded ranges, the lemma's first, the negative control's second.
CASE_FAMILIES = {
    "spanning_tree_kept": CaseFamily(
        lemma="spanning_tree_kept", cases=tree_cases,
        encode=lambda case, variant: tree_case_encoding(case[1], case[2], case[3], variant),
        key=lambda case: rooted_shape(case[1], case[2], case[3]),
        solver_params=TREE_SOLVER_PARAMS, variants=("phi_minus_vdt", "phi")),
}
