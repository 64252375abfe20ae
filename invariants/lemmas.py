"""Lemmas as data: the types of a z3 lemma, the vector helpers its encodings use, and the
normalisation lemmas every geometric lemma relies on (issue 5; DESIGN.md sections 1, 3, 4).

A lemma is a :class:`Lemma` (statement, citation, kind, what it does not prove, its encoding
and a negative control); :meth:`Lemma.build` returns an :class:`Encoding` (named premises, a
conclusion, the free variables).  The prover that decides them is
:mod:`swarmproof.checkers.proofs`; the lemmas of each paper live in its package
(``swarmproof.reference_impl.song2016.lemmas``, ``...wang2020.lemmas``) and reach the prover
through the algorithm registry (:func:`swarmproof.reference_impl.registry.lemma_sets`).

Points are pairs of z3 arithmetic terms; distances are compared through their squares
(:func:`dist2`: no distance variables, no quantifiers, DESIGN.md section 4).  The normalisation
lemmas (:data:`NORMALISATION_LEMMAS`: translation, rotation and scale invariance) justify
stating every geometric lemma with one point at the origin, ``phi = 1`` and ``s = v dt / phi``
(docs/proofs.md).

Examples
--------
>>> import z3
>>> a, b = point("a"), point("b")
>>> z3.simplify(dist2((z3.RealVal(3), z3.RealVal(4))))
25
>>> [lem.id for lem in NORMALISATION_LEMMAS]
['translation_invariance', 'rotation_invariance', 'scale_invariance']
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import z3

__all__ = ["Encoding", "Lemma", "Point", "point", "ORIGIN", "sub", "add", "scale", "eq", "dist2", "variables",
           "translation_invariance", "rotation_invariance", "scale_invariance", "NORMALISATION_LEMMAS"]

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
    #: z3's work budget for the whole proof (the lemma, its negative control and its vacuity
    #: controls share it), in z3's deterministic resource units (``rlimit``); None: the prover's
    #: default.  A budget, unlike a wall-clock timeout, gives the same verdict on a loaded machine.
    rlimit: int | None = None


def lemma_solver(ctx: z3.Context | None = None, params=()) -> z3.Solver:
    """A solver for a lemma's terms: z3's nlsat procedure (nonlinear real arithmetic), or its
    default SMT solver when ``params`` hold the pseudo-parameter ``("solver", "smt")`` (linear
    arithmetic with Boolean structure).  Measured: the default combined solver answered
    ``unknown`` after 10 s on bounded_range, nlsat proves it in about 0.15 s; on 004's planner
    rule nlsat timed out at 30 s where the SMT solver's simplex decides in 0.06 s
    (docs/proofs.md).  The prover and :func:`swarmproof.invariants.lemma_api.cross_check` use it."""
    if ("solver", "smt") in tuple(params):
        return z3.Solver(ctx=ctx)
    return z3.Tactic("qfnra-nlsat", ctx=ctx).solver()


# ------------------------------------------------------- vector helpers

def point(name: str) -> Point:
    """The z3 point ``(name_x, name_y)``."""
    return (z3.Real(f"{name}_x"), z3.Real(f"{name}_y"))


ORIGIN: Point = (z3.RealVal(0), z3.RealVal(0))


def sub(a: Point, b: Point) -> Point:
    """``a - b``."""
    return (a[0] - b[0], a[1] - b[1])


def add(a: Point, b: Point) -> Point:
    """``a + b``."""
    return (a[0] + b[0], a[1] + b[1])


def scale(k, a: Point) -> Point:
    """``k a``."""
    return (k * a[0], k * a[1])


def eq(a: Point, b: Point) -> z3.BoolRef:
    """``a == b`` componentwise."""
    return z3.And(a[0] == b[0], a[1] == b[1])


def dist2(a: Point, b: Point = (0, 0)):
    """Squared Euclidean distance ``||a - b||^2`` (no distance variables).  Like :func:`sub`,
    :func:`add` and :func:`scale` it works on z3 terms and on floats alike (z3 reads the default
    origin's ``0`` as ``RealVal(0)``), so :mod:`swarmproof.invariants.lemma_api` uses these."""
    d = sub(a, b)
    return d[0] * d[0] + d[1] * d[1]


def variables(*points_or_reals) -> list:
    """The z3 variables of points and reals, flattened in order (a counterexample lists them so)."""
    out = []
    for p in points_or_reals:
        if isinstance(p, tuple):
            out.extend(p)
        else:
            out.append(p)
    return out


# ---------------------------------------------------- normalisation lemmas

def translation_invariance(shift_both: bool = True) -> Encoding:
    """``||(a - c) - (b - c)||^2 = ||a - b||^2`` for all points ``a, b, c``.

    Moving the origin to any point ``c`` changes no distance; with
    ``shift_both=False`` (the control) only ``a`` is moved."""
    a, b, c = point("a"), point("b"), point("c")
    b2 = sub(b, c) if shift_both else b
    return Encoding(premises=[], conclusion=dist2(sub(a, c), b2) == dist2(a, b),
                    variables=variables(a, b, c))


def rotation_invariance(unit: bool = True) -> Encoding:
    """``||R a - R b||^2 = ||a - b||^2`` for ``R = [[c, -n], [n, c]]``, ``c^2 + n^2 = 1``.

    The control drops ``c^2 + n^2 = 1`` (any rotation-scaling matrix)."""
    a, b = point("a"), point("b")
    c, n = z3.Reals("cos sin")

    def rot(p):
        return (c * p[0] - n * p[1], n * p[0] + c * p[1])

    prem = [("rotation_is_orthonormal", c * c + n * n == 1)] if unit else \
        [("rotation_bounded", c * c + n * n <= 4)]
    return Encoding(premises=prem, conclusion=dist2(rot(a), rot(b)) == dist2(a, b),
                    variables=variables(a, b, c, n))


def scale_invariance(scale_radius: bool = True) -> Encoding:
    """For ``k > 0``: ``||a-b||^2 <= r^2  <=>  ||k a - k b||^2 <= (k r)^2``, the same
    with ``<``, and the map keeps segment points: ``k (a + l (b - a)) = k a + l (k b - k a)``.

    So dividing every position and radius by ``phi`` turns ``phi`` into 1 and
    ``v*dt`` into ``s = v*dt/phi`` without changing any premise or conclusion.
    The control does not scale the radius."""
    a, b = point("a"), point("b")
    k, r, lam = z3.Reals("k r l")
    kr = k * r if scale_radius else r
    ka, kb = scale(k, a), scale(k, b)
    seg = eq(scale(k, add(a, scale(lam, sub(b, a)))), add(ka, scale(lam, sub(kb, ka))))
    concl = z3.And((dist2(a, b) <= r * r) == (dist2(ka, kb) <= kr * kr),
                   (dist2(a, b) < r * r) == (dist2(ka, kb) < kr * kr),
                   seg)
    return Encoding(premises=[("scale_positive", k > 0)], conclusion=concl,
                    variables=variables(a, b, k, r, lam))


#: The normalisation lemmas, first in ``swarmproof prove``'s suite.
NORMALISATION_LEMMAS = [
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
]
