"""The z3 proof suite for the safety lemmas (issue 5; DESIGN.md sections 3 and 4).

One small encoding per lemma, named after the mathematics, its variables
indexed by time step (``p_i_0`` is ``p_i(t)``, ``p_i_1`` is ``p_i(t+dt)``).
Validity is shown by asserting the negation of the conclusion and getting
``unsat``.  Every lemma is checked in three steps (:func:`prove`):

1. its premises are satisfiable (else the proof would be vacuous: reported
   ``inconclusive``);
2. premises and ``Not(conclusion)`` are ``unsat`` (``proved``); ``sat`` gives a
   concrete counterexample as numbers; ``unknown`` or a timeout is
   ``inconclusive``, never proved;
3. a negative control, the same lemma with one premise weakened, must be
   refuted with a concrete counterexample; a control that also "proves"
   suggests an encoding that cannot fail, and the lemma is then reported
   ``inconclusive`` ("negative control not refuted");
4. vacuity controls (:func:`vacuity_controls`): each premise dropped in turn
   must give a counterexample for at least one of them, and the conclusion
   must not survive dropping them all (else: tautological, ``inconclusive``).

Each lemma has a ``kind``: ``"paper lemma"`` when it encodes a paper's
numbered result with its premises, else ``"auxiliary"``; ``not_proved``
lists what it does not cover that a reader could take it to.

Normalisation (DESIGN.md section 4, measured): every geometric lemma is
stated with the centre of the disc it reasons about at the origin
(translation invariance), with ``phi = 1`` and ``s = v*dt/phi`` as one
variable (scale invariance).  The invariances are lemmas of their own
(``translation_invariance``, ``rotation_invariance``, ``scale_invariance``),
proved by the same procedure; docs/proofs.md says why they make the
normalised statements equivalent to the general ones.  Distances are
compared through their squares (no distance variables, no quantifiers).

Examples
--------
>>> r = prove(LEMMAS["relocate_stays_in_range"], timeout_s=10)
>>> r.status, r.premises_satisfiable, r.negative_control["status"]
('proved', True, 'counterexample')
>>> sorted(LEMMAS)[:3]
['bounded_range', 'bounded_range_strict', 'intermediate_goal_in_region']

References
----------
000_3ad33c5b62f11d5f.txt Lemma 7, Sec. IV-C, Fig. 6;
001_7a4e517b856331bc.txt Lemma 7, Def. 8, Sec. V-C, Lemma 11.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Callable, Iterable, Sequence

import numpy as np
import z3

from swarmproof.models.errors import UsageError, check_positive

__all__ = [
    "Encoding",
    "Lemma",
    "LemmaResult",
    "LEMMAS",
    "EXTRA_LEMMAS",
    "prove",
    "run_suite",
    "lookup",
    "model_to_numbers",
    "confirm_trees",
    "rooted_shape",
    "tree_cases",
    "TREE_SOLVER_PARAMS",
    "kernel_oracle_check",
    "vacuity_controls",
    "premise_names",
]

DEFAULT_TIMEOUT_S = 10.0

Point = tuple  # (x, y) of z3 arithmetic terms


# ---------------------------------------------------------------- records

@dataclass(frozen=True)
class Encoding:
    """A lemma as z3 terms.

    ``premises`` are named (the names go to ``assert_and_track``);
    ``cases`` optionally splits the lemma into cases, each a list of extra
    named premises: the lemma holds iff it holds in every case (a premise
    ``A or B`` proved as ``A => C`` and ``B => C``).  ``parts`` optionally
    splits a conjunctive conclusion into named conjuncts, each proved on its
    own with all the premises (``P => (A and B)`` holds iff ``P => A`` and
    ``P => B``); ``conclusion`` must then be their conjunction.
    ``variables`` are the free variables, in the order a counterexample
    lists them.
    """

    premises: list
    conclusion: z3.BoolRef
    variables: list
    cases: list = field(default_factory=list)
    parts: list = field(default_factory=list)


@dataclass(frozen=True)
class Lemma:
    """A lemma: statement, citation, normalisations, encoding, negative control."""

    id: str
    statement: str
    cites: tuple
    normalisations: tuple
    build: Callable[[], Encoding]
    control: Callable[[], Encoding]
    control_note: str
    solver_params: tuple = ()  # extra (name, value) pairs for every solver
    #: "paper lemma" (a paper's numbered result, its statement and premises) or "auxiliary"
    #: (a fact swarmproof proves on the way: a normalisation, one case, one moment, a variant)
    kind: str = "auxiliary"
    #: what the lemma does *not* cover that a reader could take it to (issue 19)
    not_proved: tuple = ()


@dataclass
class LemmaResult:
    """The outcome of :func:`prove` (DESIGN.md section 2, ``prove`` JSON)."""

    id: str
    statement: str
    cites: list
    status: str  # proved | counterexample | inconclusive
    seconds: float
    premises_satisfiable: bool | None
    negative_control: dict
    counterexample: dict | None = None
    reason: str = ""
    normalisations: list = field(default_factory=list)
    kind: str = "auxiliary"
    vacuity: dict = field(default_factory=dict)
    not_proved: list = field(default_factory=list)

    def to_dict(self) -> dict:
        return {
            "id": self.id,
            "kind": self.kind,
            "statement": self.statement,
            "cites": list(self.cites),
            "not_proved": list(self.not_proved),
            "status": self.status,
            "seconds": round(self.seconds, 4),
            "premises_satisfiable": self.premises_satisfiable,
            "negative_control": dict(self.negative_control),
            "vacuity": dict(self.vacuity),
            "counterexample": self.counterexample,
            "reason": self.reason,
            "normalisations": list(self.normalisations),
        }


# ------------------------------------------------------- vector helpers

def _pt(name: str) -> Point:
    return (z3.Real(f"{name}_x"), z3.Real(f"{name}_y"))


_ORIGIN: Point = (z3.RealVal(0), z3.RealVal(0))


def _sub(a: Point, b: Point) -> Point:
    return (a[0] - b[0], a[1] - b[1])


def _add(a: Point, b: Point) -> Point:
    return (a[0] + b[0], a[1] + b[1])


def _scale(k, a: Point) -> Point:
    return (k * a[0], k * a[1])


def _eq(a: Point, b: Point) -> z3.BoolRef:
    return z3.And(a[0] == b[0], a[1] == b[1])


def dist2(a: Point, b: Point = _ORIGIN):
    """Squared Euclidean distance ``||a - b||^2`` (no distance variables)."""
    d = _sub(a, b)
    return d[0] * d[0] + d[1] * d[1]


def _vars(*points_or_reals) -> list:
    out = []
    for p in points_or_reals:
        if isinstance(p, tuple):
            out.extend(p)
        else:
            out.append(p)
    return out


def _step_range(s) -> tuple:
    """``0 < s < 1``: ``s = v*dt/phi``; the papers assume ``v*dt < phi``."""
    return ("step_below_range", z3.And(s > 0, s < 1))


# ---------------------------------------------------- normalisation lemmas

def translation_invariance(shift_both: bool = True) -> Encoding:
    """``||(a - c) - (b - c)||^2 = ||a - b||^2`` for all points ``a, b, c``.

    Moving the origin to any point ``c`` changes no distance; with
    ``shift_both=False`` (the control) only ``a`` is moved."""
    a, b, c = _pt("a"), _pt("b"), _pt("c")
    b2 = _sub(b, c) if shift_both else b
    return Encoding(premises=[], conclusion=dist2(_sub(a, c), b2) == dist2(a, b),
                    variables=_vars(a, b, c))


def rotation_invariance(unit: bool = True) -> Encoding:
    """``||R a - R b||^2 = ||a - b||^2`` for ``R = [[c, -n], [n, c]]``, ``c^2 + n^2 = 1``.

    The control drops ``c^2 + n^2 = 1`` (any rotation-scaling matrix)."""
    a, b = _pt("a"), _pt("b")
    c, n = z3.Reals("cos sin")

    def rot(p):
        return (c * p[0] - n * p[1], n * p[0] + c * p[1])

    prem = [("rotation_is_orthonormal", c * c + n * n == 1)] if unit else \
        [("rotation_bounded", c * c + n * n <= 4)]
    return Encoding(premises=prem, conclusion=dist2(rot(a), rot(b)) == dist2(a, b),
                    variables=_vars(a, b, c, n))


def scale_invariance(scale_radius: bool = True) -> Encoding:
    """For ``k > 0``: ``||a-b||^2 <= r^2  <=>  ||k a - k b||^2 <= (k r)^2``, the same
    with ``<``, and the map keeps segment points: ``k (a + l (b - a)) = k a + l (k b - k a)``.

    So dividing every position and radius by ``phi`` turns ``phi`` into 1 and
    ``v*dt`` into ``s = v*dt/phi`` without changing any premise or conclusion.
    The control does not scale the radius."""
    a, b = _pt("a"), _pt("b")
    k, r, lam = z3.Reals("k r l")
    kr = k * r if scale_radius else r
    ka, kb = _scale(k, a), _scale(k, b)
    seg = _eq(_scale(k, _add(a, _scale(lam, _sub(b, a)))), _add(ka, _scale(lam, _sub(kb, ka))))
    concl = z3.And((dist2(a, b) <= r * r) == (dist2(ka, kb) <= kr * kr),
                   (dist2(a, b) < r * r) == (dist2(ka, kb) < kr * kr),
                   seg)
    return Encoding(premises=[("scale_positive", k > 0)], conclusion=concl,
                    variables=_vars(a, b, k, r, lam))


# ---------------------------------------------------- the safety lemmas

def bounded_range(range_radius_factor: str = "phi_minus_vdt", strict: bool = False,
                  open_range: bool = False) -> Encoding:
    """000 Lemma 7 / 001 Lemma 7, normalised: ``p_p(t) = 0``, ``phi = 1``, ``s = v dt/phi``.

    Premises: ``||p_i(t)|| <= 1`` (neighbours; ``< 1`` if ``strict``),
    ``||p_i(t+dt) - p_i(t)|| <= s``, ``||p_p(t+dt)|| <= s``,
    ``||p_i(t+dt)|| <= 1 - s`` (``< 1 - s`` if ``open_range``).
    Conclusion: ``||p_i(t+dt) - p_p(t+dt)|| <= 1`` (``< 1`` if ``strict``).
    The control uses the radius ``phi`` (1) instead of ``phi - v dt``."""
    s = z3.Real("s")
    pi0, pi1, pp1 = _pt("p_i_0"), _pt("p_i_1"), _pt("p_p_1")
    rad2 = (1 - s) * (1 - s) if range_radius_factor == "phi_minus_vdt" else z3.RealVal(1)
    near = (lambda d: d < 1) if strict else (lambda d: d <= 1)
    in_range = dist2(pi1) < rad2 if open_range else dist2(pi1) <= rad2
    prem = [
        _step_range(s),
        ("neighbours_at_t", near(dist2(pi0))),
        ("child_moves_at_most_v_dt", dist2(pi1, pi0) <= s * s),
        ("parent_moves_at_most_v_dt", dist2(pp1) <= s * s),
        ("child_in_parent_bounded_range", in_range),
    ]
    return Encoding(premises=prem, conclusion=near(dist2(pi1, pp1)),
                    variables=_vars(s, pi0, pi1, pp1))


def nclb_link_kept(radius: str = "phi_minus_vdt") -> Encoding:
    """001 Sec. V-C (NCLB) for one parent-child link, normalised: ``p_c(t) = 0``.

    Premises: the link holds at ``t`` (``||p_p(t)|| <= 1``), the parent moves at
    most ``s`` and ends in the child's bounded range (Def. 8:
    ``||p_p(t+dt)|| <= 1 - s``), the child moves at most ``s``.
    Conclusion: ``||p_p(t+dt) - p_c(t+dt)|| <= 1``."""
    s = z3.Real("s")
    pp0, pp1, pc1 = _pt("p_p_0"), _pt("p_p_1"), _pt("p_c_1")
    rad2 = (1 - s) * (1 - s) if radius == "phi_minus_vdt" else z3.RealVal(1)
    prem = [
        _step_range(s),
        ("link_at_t", dist2(pp0) <= 1),
        ("parent_moves_at_most_v_dt", dist2(pp1, pp0) <= s * s),
        ("parent_in_child_bounded_range", dist2(pp1) <= rad2),
        ("child_moves_at_most_v_dt", dist2(pc1) <= s * s),
    ]
    return Encoding(premises=prem, conclusion=dist2(pp1, pc1) <= 1,
                    variables=_vars(s, pp0, pp1, pc1))


def tree_link_kept() -> Encoding:
    """One link of the spanning tree in the cases of 001 Sec. V-C's motion strategy that
    :func:`swarmproof.invariants.premises.tree_links_in_proved_cases` checks at run time;
    normalised: ``p_c(t) = 0``.

    * ``nclb``: the parent moves inside the child's bounded range, the child
      moves at most ``s`` (the premises of ``nclb_link_kept``);
    * ``child_not_farther_from_still_parent``: the parent does not move and the child
      ends no farther from it than it started (case 3 of Sec. V-C, and "children ...
      will only move toward the robot" when a safe region is empty).

    In each case the link is kept: ``||p_p(t+dt) - p_c(t+dt)|| <= 1``.  Not covered
    (``Lemma.not_proved``): links a child chose in the step, the relocate robot heading for
    its vacancy, the relocate robot's nearest-safe-point move toward a non-root parent."""
    s = z3.Real("s")
    pp0, pp1, pc1 = _pt("p_p_0"), _pt("p_p_1"), _pt("p_c_1")
    common = [_step_range(s), ("link_at_t", dist2(pp0) <= 1)]
    cases = [
        ("nclb", [
            ("parent_moves_at_most_v_dt", dist2(pp1, pp0) <= s * s),
            ("parent_in_child_bounded_range", dist2(pp1) <= (1 - s) * (1 - s)),
            ("child_moves_at_most_v_dt", dist2(pc1) <= s * s),
        ]),
        ("child_not_farther_from_still_parent", [
            ("parent_still", _eq(pp1, pp0)),
            ("child_not_farther", dist2(pc1, pp0) <= dist2(pp0)),
        ]),
    ]
    return Encoding(premises=common, conclusion=dist2(pp1, pc1) <= 1,
                    variables=_vars(s, pp0, pp1, pc1), cases=cases)


def tree_link_kept_control() -> Encoding:
    """Control of ``spanning_tree_kept``: the ``nclb`` case with radius ``phi``."""
    return nclb_link_kept(radius="phi")


def relocate_stays_in_range(endpoint_radius2: int = 1) -> Encoding:
    """A point on a segment between two points within ``phi`` of a stationary
    robot is within ``phi`` of it.  Normalised: the stationary robot (the root)
    at the origin, ``phi = 1``.  The control lets one endpoint be ``2 phi`` away."""
    a, b = _pt("a"), _pt("b")
    lam = z3.Real("l")
    q = _add(a, _scale(lam, _sub(b, a)))
    prem = [
        ("start_within_range", dist2(a) <= 1),
        ("end_within_range", dist2(b) <= endpoint_radius2),
        ("on_segment", z3.And(lam >= 0, lam <= 1)),
    ]
    return Encoding(premises=prem, conclusion=dist2(q) <= 1, variables=_vars(a, b, lam))


def safe_region_nonempty(children: int = 3, ds_bound: str = "phi_minus_vdt") -> Encoding:
    """001 Sec. V-C: every child within ``d_s < phi - v dt`` of its parent puts the
    parent's own position in every child's bounded range.  Normalised: the
    parent at the origin.  Stated for ``children`` children at once (each
    conjunct uses only its own child's premise).  The control allows
    ``d_s < phi``."""
    s, ds = z3.Reals("s d_s")
    cs = [_pt(f"c{k}_0") for k in range(children)]
    bound = 1 - s if ds_bound == "phi_minus_vdt" else z3.RealVal(1)
    prem = [_step_range(s), ("safe_distance", z3.And(ds > 0, ds < bound))]
    prem += [(f"child_{k}_within_d_s", dist2(c) <= ds * ds) for k, c in enumerate(cs)]
    concl = z3.And([dist2(_ORIGIN, c) <= (1 - s) * (1 - s) for c in cs])
    return Encoding(premises=prem, conclusion=concl, variables=_vars(s, ds, *cs))


def intermediate_goal_in_region(neighbour_radius2: int = 1) -> Encoding:
    """000 Sec. IV-C, Fig. 6: ``P_i & P_p`` (discs of radius ``v dt`` around ``p_i(t)`` and
    ``phi - v dt`` around ``p_p(t)``) is not empty when the robots are neighbours: the point
    ``(1 - s) p_i(t)`` lies in both.  Normalised: ``p_p(t) = 0``.

    (That a goal chosen in ``P_i & P_p`` and reached at ``t+dt`` meets the premises of
    ``bounded_range`` is the definition of the two discs, not a fact for z3: the two
    conclusion parts that said so repeated the premises and were removed, issue 19.)
    The control lets the robots be up to ``2 phi`` apart."""
    s = z3.Real("s")
    pi0 = _pt("p_i_0")
    w = _scale(1 - s, pi0)
    prem = [
        _step_range(s),
        ("neighbours_at_t", dist2(pi0) <= neighbour_radius2),
    ]
    parts = [("witness_in_P_i", dist2(w, pi0) <= s * s),
             ("witness_in_P_p", dist2(w) <= (1 - s) * (1 - s))]
    return Encoding(premises=prem, conclusion=z3.And([t for _, t in parts]), variables=_vars(s, pi0),
                    parts=parts)


# -------------------------------------------- findings and hard lemmas

def intermediate_goal_partial_progress() -> Encoding:
    """A robot that drives only part of the way to its intermediate goal ``g``
    (``p_i(t+dt) = p_i(t) + l (g - p_i(t))``, ``0 <= l <= 1``, e.g. because part of
    the step was spent turning) is NOT always in the parent's bounded range:
    z3 finds a counterexample.  000 Sec. IV-C assumes the goal is reached."""
    s, lam = z3.Reals("s l")
    pi0, g = _pt("p_i_0"), _pt("g")
    pi1 = _add(pi0, _scale(lam, _sub(g, pi0)))
    prem = [
        _step_range(s),
        ("neighbours_at_t", dist2(pi0) <= 1),
        ("goal_in_P_i", dist2(g, pi0) <= s * s),
        ("goal_in_P_p", dist2(g) <= (1 - s) * (1 - s)),
        ("partial_progress", z3.And(lam >= 0, lam <= 1)),
    ]
    return Encoding(premises=prem, conclusion=dist2(pi1) <= (1 - s) * (1 - s),
                    variables=_vars(s, lam, pi0, g))


def nclb_three_children_direct() -> Encoding:
    """NCLB for a parent with three children at once, not normalised per child
    (DESIGN.md section 4: did not finish in 300 s).  True, but too hard for
    z3 in any short timeout: the honest source of a timeout in the tests."""
    s = z3.Real("s")
    pp1 = _pt("p_p_1")
    c0 = [_pt(f"c{k}_0") for k in range(3)]
    c1 = [_pt(f"c{k}_1") for k in range(3)]
    prem = [_step_range(s), ("parent_moves_at_most_v_dt", dist2(pp1) <= s * s)]
    for k in range(3):
        prem += [
            (f"link_{k}_at_t", dist2(c0[k]) <= 1),
            (f"child_{k}_moves_at_most_v_dt", dist2(c1[k], c0[k]) <= s * s),
            (f"parent_in_bounded_range_of_{k}", dist2(pp1, c0[k]) <= (1 - s) * (1 - s)),
        ]
    concl = z3.And([dist2(pp1, c) <= 1 for c in c1])
    return Encoding(premises=prem, conclusion=concl, variables=_vars(s, pp1, *c0, *c1))


# ------------------------------------------------------------- registry

_S_NORM = "scale: phi = 1, s = v*dt/phi in (0, 1) (scale_invariance)"


def _t(what: str) -> str:
    return f"translation: {what} at the origin (translation_invariance)"


_LEMMA_LIST = [
    Lemma(
        id="translation_invariance",
        statement="Distances do not change when every point is shifted by the same vector: "
                  "||(a - c) - (b - c)|| = ||a - b||.",
        cites=("normalisation lemma (docs/proofs.md)",),
        normalisations=(),
        build=translation_invariance,
        control=lambda: translation_invariance(shift_both=False),
        control_note="only a is shifted",
    ),
    Lemma(
        id="rotation_invariance",
        statement="Distances do not change under a rotation R (c^2 + n^2 = 1): "
                  "||R a - R b|| = ||a - b||.",
        cites=("normalisation lemma (docs/proofs.md)",),
        normalisations=(),
        build=rotation_invariance,
        control=lambda: rotation_invariance(unit=False),
        control_note="c^2 + n^2 = 1 dropped (any rotation-scaling)",
    ),
    Lemma(
        id="scale_invariance",
        statement="For k > 0, ||a - b|| <= r iff ||k a - k b|| <= k r (also with <), and "
                  "scaling maps segment points to segment points; so phi can be set to 1 "
                  "and v*dt replaced by s = v*dt/phi.",
        cites=("normalisation lemma (docs/proofs.md)",),
        normalisations=(),
        build=scale_invariance,
        control=lambda: scale_invariance(scale_radius=False),
        control_note="the radius r is not scaled",
    ),
    Lemma(
        id="bounded_range",
        statement="If r_i and r_p are neighbours at t (||p_i(t) - p_p(t)|| <= phi), each moves "
                  "at most v dt, and ||p_i(t+dt) - p_p(t)|| <= phi - v dt, then "
                  "||p_i(t+dt) - p_p(t+dt)|| <= phi.",
        cites=("000_3ad33c5b62f11d5f.txt Lemma 7, Eqs. 5-7",
               "001_7a4e517b856331bc.txt Lemma 7"),
        normalisations=(_t("p_p(t)"), _S_NORM),
        build=bounded_range,
        control=lambda: bounded_range(range_radius_factor="phi"),
        control_note="bounded range of radius phi instead of phi - v dt",
        kind="paper lemma",
    ),
    Lemma(
        id="bounded_range_strict",
        statement="With neighbours strictly closer than phi (docs/decisions.md, Model and "
                  "geometry) Lemma 7 needs the open bounded range: if ||p_i(t) - p_p(t)|| < phi, "
                  "each moves at most v dt and ||p_i(t+dt) - p_p(t)|| < phi - v dt, then "
                  "||p_i(t+dt) - p_p(t+dt)|| < phi.",
        cites=("000_3ad33c5b62f11d5f.txt Lemma 7", "001_7a4e517b856331bc.txt Lemma 7, Def. 4"),
        normalisations=(_t("p_p(t)"), _S_NORM),
        build=lambda: bounded_range(strict=True, open_range=True),
        control=lambda: bounded_range(strict=True, open_range=False),
        control_note="closed bounded range (<= phi - v dt) with strict neighbours: "
                     "a pair can end exactly phi apart",
    ),
    Lemma(
        id="nclb_link_kept",
        statement="A parent that moves at most v dt into the bounded range (Def. 8: disc of "
                  "radius phi - v dt around p_c(t)) of a child that moves at most v dt stays "
                  "within phi of that child: ||p_p(t+dt) - p_c(t+dt)|| <= phi.",
        cites=("001_7a4e517b856331bc.txt Sec. V-C (NCLB), Def. 8, Lemma 7",),
        normalisations=(_t("p_c(t)"), _S_NORM),
        build=nclb_link_kept,
        control=lambda: nclb_link_kept(radius="phi"),
        control_note="parent anywhere within phi of the child's old position",
    ),
    Lemma(
        id="spanning_tree_kept",
        statement="One link of the spanning tree, in the two cases of the motion strategy the "
                  "run-time monitor tree_link_cases checks (the parent moves inside the child's "
                  "bounded range and the child moves at most v dt; the parent stays still and the "
                  "child ends no farther from it): the link is kept, ||p_p(t+dt) - p_c(t+dt)|| <= phi. "
                  "One link only, not Lemma 11: the composition over the tree's links is argued on "
                  "paper (docs/proofs.md), and the cases listed as not proved are not covered.",
        cites=("001_7a4e517b856331bc.txt Lemma 11's proof, Sec. V-C (one link; Lemma 11 itself is not proved)",),
        normalisations=(_t("p_c(t)"), _S_NORM),
        build=tree_link_kept,
        control=tree_link_kept_control,
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
        ),
    ),
    Lemma(
        id="relocate_stays_in_range",
        statement="A robot moving along the straight segment between two points within phi of "
                  "a stationary robot stays within phi of it.",
        cites=("001_7a4e517b856331bc.txt Sec. V-C case 2 (relocate robot toward the vacancy)",),
        normalisations=(_t("the stationary robot"), "scale: phi = 1 (scale_invariance)"),
        build=relocate_stays_in_range,
        control=lambda: relocate_stays_in_range(endpoint_radius2=4),
        control_note="the segment's end may be 2 phi away",
        not_proved=("that the relocate robot's step ends within phi of the root: the run-time "
                    "monitor checks that end directly (a disc is convex; this lemma only extends "
                    "the two ends to the path between them)",),
    ),
    Lemma(
        id="safe_region_nonempty",
        statement="If every child is within d_s < phi - v dt of its parent, the parent's own "
                  "position lies in every child's bounded range, so the safe region (their "
                  "intersection) is not empty (stated for 3 children).",
        cites=("001_7a4e517b856331bc.txt Sec. V-C (safe distance d_s), Def. 8",),
        normalisations=(_t("p_p(t)"), _S_NORM),
        build=safe_region_nonempty,
        control=lambda: safe_region_nonempty(ds_bound="phi"),
        control_note="d_s < phi instead of d_s < phi - v dt",
        not_proved=("that the children do come within d_s (Sec. V-C's 'the safe region will "
                    "eventually be non-empty' is a liveness claim; this is one moment of it)",),
    ),
    Lemma(
        id="intermediate_goal_in_region",
        statement="P_i & P_p (discs of radius v dt around p_i(t) and phi - v dt around p_p(t)) is "
                  "not empty when the robots are neighbours: (1 - s) p_i(t) lies in both. (A goal "
                  "chosen there and reached at t+dt meets bounded_range's premises by definition.)",
        cites=("000_3ad33c5b62f11d5f.txt Sec. IV-C steps 1-3, Fig. 6, Lemma 7",),
        normalisations=(_t("p_p(t)"), _S_NORM),
        build=intermediate_goal_in_region,
        control=lambda: intermediate_goal_in_region(neighbour_radius2=4),
        control_note="the robots up to 2 phi apart instead of phi",
        not_proved=("that the robot reaches its goal within the step: it may not "
                    "(intermediate_goal_partial_progress, a counterexample)",),
    ),
]

#: The suite, by id (``swarmproof prove`` with no ids runs all of these).
LEMMAS: dict = {lem.id: lem for lem in _LEMMA_LIST}

#: Lemmas run only when named: known-false variants (findings) and a true
#: lemma too hard for z3 (the honest timeout).
EXTRA_LEMMAS: dict = {
    "bounded_range_strict_closed": Lemma(
        id="bounded_range_strict_closed",
        statement="FINDING (expected counterexample): with neighbours strictly closer than phi "
                  "and the closed bounded range of Def. 8, a pair can end exactly phi apart.",
        cites=("001_7a4e517b856331bc.txt Lemma 7, Def. 8",),
        normalisations=(_t("p_p(t)"), _S_NORM),
        build=lambda: bounded_range(strict=True, open_range=False),
        control=lambda: bounded_range(strict=True, range_radius_factor="phi"),
        control_note="bounded range of radius phi",
    ),
    "intermediate_goal_partial_progress": Lemma(
        id="intermediate_goal_partial_progress",
        statement="FINDING (expected counterexample): a robot that covers only part of the way "
                  "to its intermediate goal may end outside the parent's bounded range.",
        cites=("000_3ad33c5b62f11d5f.txt Sec. IV-C, Lemma 7",),
        normalisations=(_t("p_p(t)"), _S_NORM),
        build=intermediate_goal_partial_progress,
        control=lambda: intermediate_goal_in_region(neighbour_radius2=4),
        control_note="the robots up to 2 phi apart",
    ),
    "nclb_three_children_direct": Lemma(
        id="nclb_three_children_direct",
        statement="NCLB for three children at once, un-normalised (true; too hard for z3 in a "
                  "short timeout, DESIGN.md section 4).",
        cites=("001_7a4e517b856331bc.txt Sec. V-C",),
        normalisations=(_S_NORM,),
        build=nclb_three_children_direct,
        control=lambda: nclb_link_kept(radius="phi"),
        control_note="one child, radius phi",
    ),
}


def lookup(ids: Iterable[str] | None = None) -> list:
    """The lemmas named by ``ids`` (all of :data:`LEMMAS` when None), in order.

    Raises
    ------
    UsageError
        For an unknown id, listing the valid ones.

    Examples
    --------
    >>> [lem.id for lem in lookup(["bounded_range"])]
    ['bounded_range']
    >>> lookup(["lemma7"])
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: lemma='lemma7' is not a known lemma id; fix: use one of: translation_invariance, rotation_invariance, scale_invariance, bounded_range, bounded_range_strict, nclb_link_kept, spanning_tree_kept, relocate_stays_in_range, safe_region_nonempty, intermediate_goal_in_region, wang2020_time_normalisation, wang2020_planner_vertex_one_moment, wang2020_planner_edge_one_moment, wang2020_lemma_iv_a_1, wang2020_theorem_iv_a_2, wang2020_separation_equal_speeds, wang2020_speed_buffer_v_b3_cases, wang2020_separation_speeds (run only when named: bounded_range_strict_closed, intermediate_goal_partial_progress, nclb_three_children_direct)
    """
    if ids is None:
        return list(LEMMAS.values())
    out = []
    for i in ids:
        lem = LEMMAS.get(i) or EXTRA_LEMMAS.get(i)
        if lem is None:
            raise UsageError(
                f"lemma={i!r} is not a known lemma id",
                fix="use one of: " + ", ".join(LEMMAS)
                    + " (run only when named: " + ", ".join(EXTRA_LEMMAS) + ")")
        out.append(lem)
    return out


# ------------------------------------------------------------- solving

def _configure() -> None:
    """Fix z3's random seeds: the same lemma gives the same answer and model."""
    z3.set_param("smt.random_seed", 0)
    z3.set_param("sat.random_seed", 0)
    z3.set_param("nlsat.seed", 0)


def _solver(timeout_ms: int, params: Sequence = ()) -> z3.Solver:
    # Nonlinear real arithmetic: the nlsat procedure directly (measured: the
    # default combined solver answered `unknown` after 10 s on bounded_range,
    # nlsat proves it in about 0.15 s).  A lemma in linear real arithmetic with
    # Boolean structure asks for z3's default SMT solver with the pseudo-parameter
    # ("solver", "smt") (measured on 004's planner rule: nlsat timed out at 30 s
    # where the SMT solver's simplex decides in 0.06 s; docs/proofs.md).
    params = tuple(params)
    smt = ("solver", "smt") in params
    s = z3.Solver() if smt else z3.Tactic("qfnra-nlsat").solver()
    s.set("timeout", max(1, int(timeout_ms)))
    for k, v in params:
        if k != "solver":
            s.set(k, v)
    return s


def _number(val) -> float:
    if z3.is_rational_value(val):
        return float(Fraction(val.numerator_as_long(), val.denominator_as_long()))
    if z3.is_algebraic_value(val):
        r = val.approx(20)
        return float(Fraction(r.numerator_as_long(), r.denominator_as_long()))
    if z3.is_int_value(val):
        return float(val.as_long())
    raise TypeError(f"value={val!r} is not a number")  # pragma: no cover


def model_to_numbers(model: z3.ModelRef, variables: Sequence) -> dict:
    """The model's value of each variable as a float (algebraic numbers to 20
    decimals first), keyed by variable name; unconstrained ones are 0.

    Examples
    --------
    >>> x, y = z3.Reals("x y")
    >>> s = z3.Solver(); s.add(x * x == 2, x > 0, y == 1 / 4); _ = s.check()
    >>> model_to_numbers(s.model(), [x, y])
    {'x': 1.4142135623730951, 'y': 0.25}
    """
    return {str(v): _number(model.eval(v, model_completion=True)) for v in variables}


def _check(premises: list, negate: z3.BoolRef | None, deadline: float, params) -> tuple:
    """One fresh solver: premises (tracked by name) and optionally ``Not(negate)``,
    with the time left until ``deadline`` (``time.perf_counter()`` seconds).

    Returns (z3 result, model or None, reason_unknown); the result is None
    when the deadline has already passed (nothing was checked)."""
    left_ms = (deadline - time.perf_counter()) * 1000
    if left_ms <= 0:
        return None, None, "timeout"
    s = _solver(left_ms, params)
    for k, (name, term) in enumerate(premises):
        s.assert_and_track(term, f"{k}:{name}")
    if negate is not None:
        s.add(z3.Not(negate))
    res = s.check()
    if res == z3.sat:
        return res, s.model(), ""
    if res == z3.unknown:
        return res, None, s.reason_unknown()
    return res, None, ""


def _cases(enc: Encoding) -> list:
    if not enc.cases:
        return [("", list(enc.premises))]
    return [(name, list(enc.premises) + list(extra)) for name, extra in enc.cases]


def _outcome(status: str, premises_satisfiable, reason: str = "", counterexample=None) -> dict:
    return dict(status=status, premises_satisfiable=premises_satisfiable,
                counterexample=counterexample, reason=reason)


def _solve_encoding(enc: Encoding, deadline: float, params) -> dict:
    """Premises satisfiable, then validity, case by case (and part by part).
    Returns a dict with ``status``, ``premises_satisfiable``, ``counterexample``,
    ``reason``."""
    for case, prem in _cases(enc):
        where = f" (case {case})" if case else ""
        r, _, why = _check(prem, None, deadline, params)
        if r is None:
            return _outcome("inconclusive", None, f"timeout before checking the premises{where}")
        if r == z3.unsat:
            return _outcome("inconclusive", False,
                            f"premises unsatisfiable{where}: the lemma would hold vacuously")
        if r == z3.unknown:
            return _outcome("inconclusive", None, f"z3 unknown on the premises{where}: {why}")
        for part, concl in (enc.parts or [("", enc.conclusion)]):
            what = f"the conclusion part {part}" if part else "the conclusion"
            r, model, why = _check(prem, concl, deadline, params)
            if r is None:
                return _outcome("inconclusive", True, f"timeout before checking {what}{where}")
            if r == z3.sat:
                return _outcome("counterexample", True,
                                f"z3 found premises true and {what} false{where}",
                                model_to_numbers(model, enc.variables))
            if r == z3.unknown:
                return _outcome("inconclusive", True,
                                f"z3 unknown on the negated {what[4:]}{where}: {why}")
    return _outcome("proved", True)


def _without(enc: Encoding, names) -> Encoding:
    """``enc`` with the premises called ``names`` removed (from the common list and every case)."""
    def keep(lst):
        return [(n, t) for n, t in lst if n not in names]

    return Encoding(premises=keep(enc.premises), conclusion=enc.conclusion, variables=enc.variables,
                    cases=[(c, keep(extra)) for c, extra in enc.cases], parts=enc.parts)


def premise_names(enc: Encoding) -> list:
    """Every named premise of ``enc`` (common ones, then each case's), each once, in order."""
    out: list = []
    for name, _ in list(enc.premises) + [p for _, extra in enc.cases for p in extra]:
        if name not in out:
            out.append(name)
    return out


def vacuity_controls(lemma: Lemma, timeout_s: float = DEFAULT_TIMEOUT_S) -> dict:
    """Drop each premise of ``lemma`` in turn, then all of them, and solve again (issue 19).

    A premise the conclusion needs gives a counterexample when dropped; a lemma whose
    conclusion survives dropping every premise is *tautological* (it says nothing about the
    premises it lists).  ``verdict``: ``"ok"`` (some premise is needed and the lemma is not
    tautological), ``"tautological"``, ``"no_single_premise_needed"`` (every single drop still
    proves: the premises are redundant), ``"identity"`` (no premises at all: a normalisation
    identity, nothing to drop) or ``"inconclusive"`` (a solver timeout or ``unknown`` left it
    open).  ``dropped`` maps each premise to the status with it removed.  The whole check
    shares one budget of ``timeout_s`` seconds.

    >>> v = vacuity_controls(LEMMAS["relocate_stays_in_range"])
    >>> v["verdict"], v["dropped"]["on_segment"], v["all_dropped"]
    ('ok', 'counterexample', 'counterexample')
    """
    _configure()
    enc = lemma.build()
    names = premise_names(enc)
    if not names:
        return {"verdict": "identity", "dropped": {}, "all_dropped": None,
                "note": "no premises: an identity, nothing to drop"}
    deadline = time.perf_counter() + timeout_s
    params = tuple(lemma.solver_params)
    dropped = {n: _solve_encoding(_without(enc, {n}), deadline, params)["status"] for n in names}
    every = _solve_encoding(_without(enc, set(names)), deadline, params)["status"]
    needed = sorted(n for n, st in dropped.items() if st == "counterexample")
    if every == "proved":
        verdict, note = "tautological", "the conclusion holds with every premise dropped"
    elif needed:
        verdict, note = "ok", "needed: " + ", ".join(needed)
    elif "inconclusive" in dropped.values() or every == "inconclusive":
        verdict, note = "inconclusive", "a solver timeout or unknown left a drop undecided"
    else:
        verdict, note = "no_single_premise_needed", "each premise alone can be dropped and the lemma still holds"
    return {"verdict": verdict, "dropped": dropped, "all_dropped": every, "note": note}


def prove(lemma: Lemma, timeout_s: float = DEFAULT_TIMEOUT_S) -> LemmaResult:
    """Prove one lemma and refute its negative control (module docstring, steps 1-3).

    Parameters
    ----------
    lemma : Lemma
        From :data:`LEMMAS` or :data:`EXTRA_LEMMAS`, or your own.
    timeout_s : float
        Wall-clock budget for the lemma, shared by its solver calls; the
        control gets its own budget of the same size.

    Returns
    -------
    LemmaResult
        ``status`` is ``proved`` only if z3 answered ``unsat`` for the negated
        conclusion, the premises are satisfiable and the control was refuted.

    Raises
    ------
    UsageError
        If ``timeout_s`` is not a positive number.
    """
    timeout_s = check_positive("timeout", timeout_s, fix="give a timeout in seconds > 0")
    if timeout_s > 86400:
        raise UsageError(f"timeout={timeout_s!r} seconds is over one day (z3 takes 32-bit milliseconds)",
                         fix="give a timeout of at most 86400 seconds")
    _configure()
    params = tuple(lemma.solver_params)
    t0 = time.perf_counter()
    main = _solve_encoding(lemma.build(), t0 + timeout_s, params)
    t1 = time.perf_counter()
    ctrl = _solve_encoding(lemma.control(), t1 + timeout_s, params)
    seconds = time.perf_counter() - t0
    control = {"status": ctrl["status"], "counterexample": ctrl["counterexample"],
               "weakened": lemma.control_note}
    if ctrl["status"] != "counterexample":
        control["reason"] = ctrl["reason"] or "the weakened lemma was proved"
    status, reason = main["status"], main["reason"]
    if status == "proved" and ctrl["status"] != "counterexample":
        status = "inconclusive"
        reason = (f"negative control not refuted ({control['reason']}): "
                  "the encoding may be unable to fail")
    vac = vacuity_controls(lemma, timeout_s) if status == "proved" else {
        "verdict": "not_run", "dropped": {}, "all_dropped": None, "note": f"the lemma is {status}"}
    if status == "proved" and vac["verdict"] not in ("ok", "identity"):
        status = "inconclusive"
        reason = f"vacuity control {vac['verdict']}: {vac['note']}"
    seconds = time.perf_counter() - t0
    return LemmaResult(
        id=lemma.id, statement=lemma.statement, cites=list(lemma.cites), status=status,
        seconds=seconds, premises_satisfiable=main["premises_satisfiable"],
        negative_control=control, counterexample=main["counterexample"], reason=reason,
        normalisations=list(lemma.normalisations), kind=lemma.kind, vacuity=vac,
        not_proved=list(lemma.not_proved))


def run_suite(ids: Iterable[str] | None = None,
              timeout_s: float = DEFAULT_TIMEOUT_S) -> list:
    """Prove the named lemmas (all of :data:`LEMMAS` when ``ids`` is None).

    This is what ``swarmproof prove`` and ``swarmproof verify`` call.

    Raises
    ------
    UsageError
        Unknown lemma id or a non-positive timeout.
    """
    check_positive("timeout", timeout_s, fix="give a timeout in seconds > 0")
    return [prove(lem, timeout_s) for lem in lookup(ids)]


# ------------------------------------- direct confirmation on small trees

#: nlsat option for the direct tree confirmation: keep the variables in the order
#: they first appear (``s``, the moves ``m_k``, then each link's vector) instead
#: of nlsat's reordering heuristic.  Measured (docs/performance.md, "Proof
#: suite"): with the heuristic 222 of the 640 cases up to 5 robots timed out at
#: 2 s; with this order and the conclusion proved link by link, none.
TREE_SOLVER_PARAMS = (("variable_ordering_strategy", 3),)


def _tree_case_encoding(tree, root, moving, bounded_range: str = "phi_minus_vdt") -> Encoding:
    """001 Lemma 11 stated directly for one rooted tree and one set of moving
    robots (no per-link lemma used): all links' premises at once, conclusion
    "every link kept", one ``part`` per link.

    Normalisations (docs/proofs.md): the root's old position at the origin,
    ``phi = 1``, ``s = v dt / phi``; a robot that does not move has the
    constant move ``(0, 0)``.  Variables are per link (a linear change of
    coordinates, one-to-one for a tree): for a moving parent
    ``u_c = p_p(t+dt) - p_c(t)``, for a still parent ``d_c = p_c(t) - p_p(t)``;
    ``m_k = p_k(t+dt) - p_k(t)`` for a moving robot.  The case of each link
    follows the motion strategy (001 Sec. V-C): a moving parent obeys NCLB,
    a child of a still parent moves straight toward it.  ``bounded_range="phi"``
    is the negative control (NCLB with radius ``phi`` instead of ``phi - v dt``).

    Examples
    --------
    >>> import networkx as nx
    >>> enc = _tree_case_encoding(nx.path_graph(3), 0, frozenset({1}))
    >>> [name for name, _ in enc.premises]
    ['step_below_range', 'robot_1_moves_at_most_v_dt', 'link_0_1_at_t', 'child_1_toward_still_parent_0', 'link_1_2_at_t', 'nclb_1_in_bounded_range_of_2']
    >>> [name for name, _ in enc.parts]
    ['link_0_1_kept', 'link_1_2_kept']
    """
    import networkx as nx

    s = z3.Real("s")
    parent = {v: u for u, v in nx.bfs_edges(tree, root)}
    rad2 = (1 - s) * (1 - s) if bounded_range == "phi_minus_vdt" else z3.RealVal(1)
    m = {k: (_pt(f"m{k}") if k in moving else _ORIGIN) for k in sorted(tree.nodes)}
    prem = [_step_range(s)] + [(f"robot_{k}_moves_at_most_v_dt", dist2(m[k]) <= s * s)
                               for k in sorted(moving)]
    parts, variables = [], [s] + _vars(*[m[k] for k in sorted(moving)])
    for c, p in sorted(parent.items()):
        if p in moving:
            u = _pt(f"u{c}")
            prem += [(f"link_{p}_{c}_at_t", dist2(u, m[p]) <= 1),
                     (f"nclb_{p}_in_bounded_range_of_{c}", dist2(u) <= rad2)]
            parts.append((f"link_{p}_{c}_kept", dist2(m[c], u) <= 1))
            variables += list(u)
        else:
            d = _pt(f"d{c}")
            prem.append((f"link_{p}_{c}_at_t", dist2(d) <= 1))
            if c in moving:
                lam = z3.Real(f"l{c}")
                prem.append((f"child_{c}_toward_still_parent_{p}",
                             z3.And(lam >= 0, lam <= 1, _eq(m[c], _scale(-lam, d)))))
                variables.append(lam)
            parts.append((f"link_{p}_{c}_kept", dist2(_add(d, m[c])) <= 1))
            variables += list(d)
    return Encoding(premises=prem, conclusion=z3.And([t for _, t in parts]),
                    variables=variables, parts=parts)


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


def confirm_trees(max_robots: int = 5, timeout_s: float = 2.0, *, symmetry: bool = True,
                  bounded_range: str = "phi_minus_vdt") -> dict:
    """Confirm ``spanning_tree_kept`` with z3 directly on every tree shape of
    2..``max_robots`` robots, every root and every subset of moving robots.

    Each case is one whole-tree statement (:func:`_tree_case_encoding`),
    solved like a lemma (premises satisfiable, then validity), its
    conclusion proved link by link with all the tree's premises.

    Parameters
    ----------
    max_robots : int
        Largest tree (at least 2).
    timeout_s : float
        Wall-clock budget per case (per class with ``symmetry``); a case that
        runs out is ``inconclusive``, never counted as confirmed.
    symmetry : bool
        Solve one representative per isomorphism class (:func:`rooted_shape`)
        and give every case of the class its answer; ``False`` solves every case.
    bounded_range : {"phi_minus_vdt", "phi"}
        ``"phi"`` runs the negative control: NCLB with the bounded range of
        radius ``phi``; every case where a moving parent has a moving child
        must then be refuted.

    Returns
    -------
    dict
        ``counts``: cases by status (``proved``, ``counterexample``,
        ``inconclusive``); ``not_proved``: the cases that were not proved, as
        ``(n, edges, root, moving, status, reason)``; ``cases``: the number of
        cases; ``classes``: the number of z3 problems solved;
        ``class_counts``: those problems by status.  A counterexample would
        contradict the composition argument of docs/proofs.md.

    Raises
    ------
    UsageError
        If ``max_robots`` is not an integer >= 2, ``timeout_s`` is not positive or
        ``bounded_range`` is not one of the two radii.

    Examples
    --------
    >>> out = confirm_trees(2, timeout_s=5)
    >>> out["counts"], out["cases"], out["classes"]
    ({'proved': 8, 'counterexample': 0, 'inconclusive': 0}, 8, 4)
    >>> confirm_trees(2, timeout_s=5, bounded_range="phi")["counts"]
    {'proved': 6, 'counterexample': 2, 'inconclusive': 0}
    """
    if isinstance(max_robots, bool) or not isinstance(max_robots, int) or max_robots < 2:
        raise UsageError(f"max_robots={max_robots!r} must be an integer >= 2",
                         fix="give the largest tree size, for example 5")
    timeout_s = check_positive("timeout", timeout_s, fix="give a timeout in seconds > 0")
    if bounded_range not in ("phi_minus_vdt", "phi"):
        raise UsageError(f"bounded_range={bounded_range!r} is not a radius",
                         fix="use 'phi_minus_vdt' (the lemma) or 'phi' (the negative control)")
    _configure()
    counts = {"proved": 0, "counterexample": 0, "inconclusive": 0}
    class_counts = dict(counts)
    solved: dict = {}
    not_proved = []
    for n, tree, root, moving in tree_cases(max_robots):
        edges = sorted(tree.edges())
        key = rooted_shape(tree, root, moving) if symmetry else (n, tuple(edges), root, moving)
        if key not in solved:
            r = _solve_encoding(_tree_case_encoding(tree, root, moving, bounded_range),
                                time.perf_counter() + timeout_s, TREE_SOLVER_PARAMS)
            solved[key] = (r["status"], r["reason"])
            class_counts[r["status"]] += 1
        status, reason = solved[key]
        counts[status] += 1
        if status != "proved":
            not_proved.append((n, edges, root, sorted(moving), status, reason))
    return {"counts": counts, "not_proved": not_proved, "cases": sum(counts.values()),
            "classes": len(solved), "class_counts": class_counts}


# ------------------------------------------- the geometry kernel as oracle

def _q(x) -> z3.ArithRef:
    f = Fraction(float(x))
    return z3.RealVal(f.numerator) / f.denominator if f.denominator != 1 else z3.RealVal(f.numerator)


def kernel_oracle_check(kernel, c1, r1, c2, r2, target, *, tol: float = 1e-9,
                        timeout_s: float = 2.0) -> tuple:
    """Check one output of ``nearest_point_in_disc_intersection`` with z3.

    Exact rational arithmetic on the kernel's float inputs and output: the
    output must lie in both closed discs up to ``tol``, and z3 must find no
    point of the intersection nearer ``target`` by more than ``tol``
    (``unsat``).  ``None`` from the kernel must mean no point lies in both
    discs shrunk by ``tol``.

    Returns
    -------
    (status, reason): status ``'confirmed'``, ``'refuted'`` or ``'inconclusive'``.

    Examples
    --------
    >>> from swarmproof.models.geometry import nearest_point_in_disc_intersection as k
    >>> kernel_oracle_check(k, (0, 0), 0.25, (1, 0), 0.75, (0.3, 0.3))[0]
    'confirmed'
    >>> kernel_oracle_check(lambda *a: (0.0, 0.0), (0, 0), 0.25, (1, 0), 0.75, (0.3, 0.3))[0]
    'refuted'
    """
    _configure()
    q = kernel(c1, r1, c2, r2, target)
    x = _pt("x")
    C1, C2, T = (_q(c1[0]), _q(c1[1])), (_q(c2[0]), _q(c2[1])), (_q(target[0]), _q(target[1]))
    R1, R2 = _q(r1), _q(r2)
    ms = max(1, int(timeout_s * 1000))
    if q is None:
        if min(float(r1), float(r2)) < tol:
            return "inconclusive", "kernel returned None and a radius is below the tolerance"
        s = _solver(ms)
        s.add(dist2(x, C1) <= (R1 - tol) * (R1 - tol), dist2(x, C2) <= (R2 - tol) * (R2 - tol))
        res = s.check()
        if res == z3.unsat:
            return "confirmed", "empty intersection confirmed"
        if res == z3.sat:
            return "refuted", f"kernel returned None but {model_to_numbers(s.model(), x)} is in both discs"
        return "inconclusive", s.reason_unknown()
    Q = (_q(q[0]), _q(q[1]))
    for name, C, R in (("first", C1, R1), ("second", C2, R2)):
        if not z3.is_true(z3.simplify(dist2(Q, C) <= (R + tol) * (R + tol))):
            return "refuted", f"output {list(map(float, q))} outside the {name} disc"
    dq = float(np.hypot(float(q[0]) - float(target[0]), float(q[1]) - float(target[1])))
    if dq <= tol:
        return "confirmed", "output is the target"
    s = _solver(ms)
    s.add(dist2(x, C1) <= R1 * R1, dist2(x, C2) <= R2 * R2,
          dist2(x, T) < _q((dq - tol) ** 2))
    res = s.check()
    if res == z3.unsat:
        return "confirmed", "no point of the region nearer the target"
    if res == z3.sat:
        return "refuted", f"{model_to_numbers(s.model(), x)} is in the region and nearer the target"
    return "inconclusive", s.reason_unknown()


# Wang & Rubenstein 2020's collision theorems (issue 15): the module adds its lemmas to LEMMAS
# when it is imported, whichever of the two modules is imported first.
from . import proofs_wang2020 as _proofs_wang2020  # noqa: E402,F401
