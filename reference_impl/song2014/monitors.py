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

import numpy as np

from swarmproof.invariants.lemma_monitor import Batch, Binding
from swarmproof.invariants.premises import register_binding
from swarmproof.invariants.result import InvariantResult

from ..song2016.lemmas import BOUNDED_RANGE
from ..song2016.monitors import STEP_BOUNDED  # noqa: F401  (registers step_bounded, which song2014 lists)

__all__ = ["PARENT_BOUNDED_RANGE", "descendants_in_parent_bounded_ranges"]


def _children_and_parents(view):
    """Every robot with the parent it chose in the step (state key ``"parent"`` after it), unless
    neither moved; the parent's start at the origin (``bounded_range``'s normalisation)."""
    kids, parents = [], []
    for k in view.robots():
        par = view.state(k, "parent")
        if par is None:
            continue
        q = view.slot(par)
        if q is None or not (view.moved(k) or view.moved(q)):
            continue                        # neither moved: the link is as it was
        kids.append(k)
        parents.append(q)
    yield Batch({"child": view.ids_of(kids), "parent": view.ids_of(parents)},
                {"s": view.s, **view.points("p_i_0", kids, 0, parents), **view.points("p_i_1", kids, 1, parents),
                 **view.points("p_p_1", parents, 1, parents)},
                facts={"distance": np.round(view.distances(kids, 1, parents, 0), 12),
                       "bounded_range": view.phi - view.v * view.dt})


#: ``parent_bounded_range``: every robot ends the step within ``phi - v dt`` of the old position
#: of the parent it chose, unless neither moved (000 Lemma 7, Eqs. 5-7: the descendant's goal lies
#: in the disc ``P_p`` of radius ``phi - v dt`` around its parent, Sec. IV-C step 3) -- the lemma
#: ``bounded_range``, on the pairs that were neighbours at ``t`` (premise ``neighbours_at_t``).
PARENT_BOUNDED_RANGE = Binding("parent_bounded_range", BOUNDED_RANGE, _children_and_parents,
                               what="child/parent pairs", given=("step_below_range", "neighbours_at_t"),
                               cites="bounded_range (000 Lemma 7, Sec. IV-C)")


def descendants_in_parent_bounded_ranges(trace, phi: float, v: float, dt: float) -> InvariantResult:
    """:data:`PARENT_BOUNDED_RANGE` over ``trace``.  A robot that does not move is examined too
    when its parent moves (issue 19): a child that only turns in place while its parent drives
    away breaks the premise as surely as one that drives.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1.12, 0, 0]]], dtype=float)
    >>> st = ((("parent", None),), (("parent", 1),))
    >>> r = descendants_in_parent_bounded_ranges(Trace(ids=[1, 2], poses=poses, states=[st] * 2),
    ...                                          1.2, 0.15, 1.0)
    >>> r.status, r.witness["lemma"], r.witness["child"], r.witness["distance"], r.witness["premise"]
    ('violated', 'bounded_range', 2, 1.12, 'child_in_parent_bounded_range')
    """
    return PARENT_BOUNDED_RANGE.check(trace, phi, v, dt)


register_binding(PARENT_BOUNDED_RANGE)
