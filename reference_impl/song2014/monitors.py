"""Runtime monitor of the premise of Song & O'Kane 2014's Lemma 7 as this paper states it.

``parent_bounded_range`` -- :func:`descendants_in_parent_bounded_ranges`: every robot that
moves in a step ends within ``phi - v*dt`` of the old position of the parent it chose (000
Lemma 7, Eqs. 5-7; the lemma ``bounded_range``, :mod:`swarmproof.reference_impl.song2016.lemmas`).
Importing this module registers it with :mod:`swarmproof.invariants.premises`.

Measured finding (docs/proofs.md, "Premise monitors"): song2014 breaks Lemma 7's premise under
its own assumptions, because the engine's differential drive (turn, then drive for the time
left) stops a robot short of its chosen point; with (nearly) instantaneous turns it holds.

References
----------
000_3ad33c5b62f11d5f.txt Lemma 7, Eqs. 5-7, Sec. IV-C.
"""

from __future__ import annotations

from swarmproof.invariants.premises import MISSING, movers_in_bounded_ranges, register_monitor
from swarmproof.invariants.result import InvariantResult, state_value

__all__ = ["descendants_in_parent_bounded_ranges"]


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
    status, hit, checked = movers_in_bounded_ranges(
        trace, phi, v, dt, lambda st: _parent_list(state_value(st, "parent", MISSING)), tol,
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
    if parent is MISSING:
        return MISSING
    return () if parent is None else (parent,)


register_monitor("parent_bounded_range",
                 lambda trace, phi, v, dt: descendants_in_parent_bounded_ranges(trace, phi, v, dt), "bounded_range")
