"""The normalisation lemmas, each declared once (issue 32): what lets every other lemma be stated
with a point at the origin, ``phi = 1`` and ``s = v dt / phi``.

* ``translation_invariance``: ``||(a - c) - (b - c)||^2 = ||a - b||^2`` -- moving the origin to any
  point changes no distance (control: only ``a`` is moved);
* ``rotation_invariance``: ``||R a - R b||^2 = ||a - b||^2`` for ``R = [[c, -n], [n, c]]`` with
  ``c^2 + n^2 = 1`` (control: ``c^2 + n^2 <= 4``, any rotation-scaling);
* ``scale_invariance``: for ``k > 0``, ``||a - b|| <= r`` iff ``||k a - k b|| <= k r`` (and with
  ``<``), and scaling maps segment points to segment points (control: the radius not scaled).

They come first in ``swarmproof prove``'s suite (:data:`NORMALISATION_LEMMAS`).  Their negative
controls change the conclusion, not a premise (``control_conclusion``): translation has no
premise to weaken.

>>> [lem.id for lem in NORMALISATION_LEMMAS]
['translation_invariance', 'rotation_invariance', 'scale_invariance']
"""

from __future__ import annotations

from .lemma_api import And, Eq, Gt, Iff, Le, LemmaSpec, Lt, Point, Real, add, dist2, scale, sub

__all__ = ["TRANSLATION_INVARIANCE", "ROTATION_INVARIANCE", "SCALE_INVARIANCE", "SPECS", "NORMALISATION_LEMMAS"]

_CITES = ("normalisation lemma (docs/proofs.md)",)


def _translated(shift_both: bool):
    def concl(v):
        b = sub(v.b, v.c) if shift_both else v.b
        return Eq(dist2(sub(v.a, v.c), b), dist2(v.a, v.b))
    return concl


TRANSLATION_INVARIANCE = LemmaSpec(
    id="translation_invariance",
    statement="Distances do not change when every point is shifted by the same vector: "
              "||(a - c) - (b - c)|| = ||a - b||.",
    cites=_CITES,
    variables=(Point("a"), Point("b"), Point("c")),
    premises=(), conclusion=_translated(True),
    control_conclusion=_translated(False), control_note="only a is shifted",
)


def _rot(v, p):
    return (v.cos * p[0] - v.sin * p[1], v.sin * p[0] + v.cos * p[1])


ROTATION_INVARIANCE = LemmaSpec(
    id="rotation_invariance",
    statement="Distances do not change under a rotation R (c^2 + n^2 = 1): "
              "||R a - R b|| = ||a - b||.",
    cites=_CITES,
    variables=(Point("a"), Point("b"), Real("cos", -1.0, 1.0), Real("sin", -1.0, 1.0)),
    premises=(("rotation_is_orthonormal", lambda v: Eq(v.cos * v.cos + v.sin * v.sin, 1)),),
    conclusion=lambda v: Eq(dist2(_rot(v, v.a), _rot(v, v.b)), dist2(v.a, v.b)),
    control_premises=(("rotation_bounded", lambda v: Le(v.cos * v.cos + v.sin * v.sin, 4)),),
    control_note="c^2 + n^2 = 1 dropped (any rotation-scaling)",
)


def _scaled(scale_radius: bool):
    def concl(v):
        kr = v.k * v.r if scale_radius else v.r
        ka, kb = scale(v.k, v.a), scale(v.k, v.b)
        seg = scale(v.k, add(v.a, scale(v.l, sub(v.b, v.a))))
        img = add(ka, scale(v.l, sub(kb, ka)))
        return And(Iff(Le(dist2(v.a, v.b), v.r * v.r), Le(dist2(ka, kb), kr * kr)),
                   Iff(Lt(dist2(v.a, v.b), v.r * v.r), Lt(dist2(ka, kb), kr * kr)),
                   And(Eq(seg[0], img[0]), Eq(seg[1], img[1])))
    return concl


SCALE_INVARIANCE = LemmaSpec(
    id="scale_invariance",
    statement="For k > 0, ||a - b|| <= r iff ||k a - k b|| <= k r (also with <), and "
              "scaling maps segment points to segment points; so phi can be set to 1 "
              "and v*dt replaced by s = v*dt/phi.",
    cites=_CITES,
    variables=(Point("a"), Point("b"), Real("k", 0.0, 2.0), Real("r", 0.0, 2.0), Real("l", 0.0, 1.0)),
    premises=(("scale_positive", lambda v: Gt(v.k, 0)),),
    conclusion=_scaled(True),
    control_premises=(("scale_positive", lambda v: Gt(v.k, 0)),),
    control_conclusion=_scaled(False), control_note="the radius r is not scaled",
)

#: The normalisation lemmas by id.
SPECS: dict = {s.id: s for s in (TRANSLATION_INVARIANCE, ROTATION_INVARIANCE, SCALE_INVARIANCE)}

#: The normalisation lemmas, first in ``swarmproof prove``'s suite.
NORMALISATION_LEMMAS = [s.lemma() for s in SPECS.values()]
