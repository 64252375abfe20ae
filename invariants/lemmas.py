"""Lemmas as data: the types of a z3 lemma and the vector helpers its encodings use (issue 5;
DESIGN.md sections 1, 3, 4).

A lemma is a :class:`Lemma` (statement, citation, kind, what it does not prove, its encoding
and a negative control); :meth:`Lemma.build` returns an :class:`Encoding` (named premises, a
conclusion, the free variables).  The prover that decides them is
:mod:`swarmproof.checkers.proofs`; the lemmas of each paper live in its package
(``swarmproof.reference_impl.song2016.lemmas``, ``...wang2020.lemmas``) and reach the prover
through the algorithm registry (:func:`swarmproof.reference_impl.registry.lemma_sets`).

Points are pairs of z3 arithmetic terms; distances are compared through their squares
(:func:`dist2`: no distance variables, no quantifiers, DESIGN.md section 4).  The normalisation
lemmas (translation, rotation and scale invariance), which justify stating every geometric lemma
with one point at the origin, ``phi = 1`` and ``s = v dt / phi``, are declared once in
:mod:`swarmproof.invariants.normalisation` (docs/proofs.md).

Examples
--------
>>> import z3
>>> a, b = point("a"), point("b")
>>> z3.simplify(dist2((z3.RealVal(3), z3.RealVal(4))))
25
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import z3

__all__ = ["Encoding", "Lemma", "Point", "point", "ORIGIN", "sub", "add", "scale", "eq", "dist2", "variables"]

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
