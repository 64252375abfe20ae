"""Wang & Rubenstein 2020's own properties: checks of the paper that no lemma states as a run reads them.

Premise monitors until issue 32; properties since, because none can be derived from a lemma's
one definition without saying more than the lemma does (docs/proofs.md, "Premise monitors of
these lemmas"; docs/decisions.md).  A paper lemma's name is never put on them: each cites the
lemmas whose premises or conclusions it checks, and keeps its check unchanged
(:mod:`.monitors`):

* ``grid_claims`` -- cells distinct, claims distinct and no edge swap in every recorded state
  (:func:`~.monitors.grid_claims_distinct`): Thms. IV-A.1/IV-A.2's *conclusions* at one moment,
  which the lemmas that take them as premises state over claim intervals in continuous time (when
  each claim began, when its agent set off), which a state does not record.
* ``grid_heard`` -- a robot that sets off has heard every robot within ``R`` throughout its window
  that broadcast in it (:class:`~.monitors.GridHeard`, streamed): who is owed a message is read
  from the frames of the whole window, and the lemma's premise (``lossless_delivery_within_R``)
  is two Booleans, with no such selection.
* ``grid_spacing`` -- the run's grid length against ``2 sqrt(2) r <= l <= R/2`` (Sec. III-A) and
  Sec. V-B3's bound at the speeds drawn (:func:`~.monitors.grid_spacing_of_trace`): the run's
  parameters, once, not a step; the same as the assumptions ``grid_spacing_bounds`` and
  ``speed_buffer`` check before a run (on the speeds' range), judged on the run as recorded.

Importing this module registers them (``own=True``): wang2020 and its variant list them in
``properties``; ``explore``, ``verify`` and ``simulate`` judge them for those, ``grid_claims`` and
``grid_heard`` streamed in the engine on every step.

References
----------
004_004a3703645971e3.txt Sec. II-A, Sec. III-A (Constraints III-A.1/2), Sec. V-B3, Thms. IV-A.1/IV-A.2.
"""

from __future__ import annotations

from swarmproof.invariants.premises import StepFeed
from swarmproof.invariants.registry import Property, register_property
from swarmproof.invariants.result import InvariantResult

from .monitors import _GRID_CITES, GridHeard, grid_claims_distinct, grid_heard_neighbours, grid_spacing_of_trace

__all__ = ["GRID_CLAIMS", "GRID_HEARD", "GRID_SPACING"]


class _ClaimsEveryStep:
    """:func:`~.monitors.grid_claims_distinct` on every step the engine feeds (one-step windows),
    stopping at the first state that is not held; the same verdict as over a dense trace."""

    def __init__(self) -> None:
        self.final = None
        self.checked = 0

    def scan(self, window) -> None:
        if self.final is not None:
            return
        r = grid_claims_distinct(window)
        if r.status != "held":
            self.final = r
        else:
            self.checked += int(r.detail.get("checked", 0))

    def result(self) -> InvariantResult:
        if self.final is not None:
            return self.final
        return InvariantResult("grid_claims", "held", _GRID_CITES["claims"], None,
                               f"{self.checked} robot-states with distinct cells and claims",
                               applicable=self.checked > 0, detail={"checked": self.checked})


def _claims(trace, ctx):
    return grid_claims_distinct(trace)


def _claims_stream(algorithm, params, options):
    return StepFeed("grid_claims", _ClaimsEveryStep())


def _heard(trace, ctx):
    return grid_heard_neighbours(trace, ctx.phi)


def _heard_stream(algorithm, params, options):
    # the clock rates and broadcast period (params.extra) give the window's span
    meta = {"params": {"extra": dict(getattr(params, "extra", None) or {})}}
    return StepFeed("grid_heard", GridHeard(float(params.range), meta=meta))


def _spacing(trace, ctx):
    return grid_spacing_of_trace(trace, ctx.phi)


#: ``grid_claims``: Constraints III-A.1/2 from the controllers' own claims, at every recorded moment.
GRID_CLAIMS = register_property(Property(
    "grid_claims", "safety", _claims, ("states' cell, next, wp, moving",),
    "the controllers' own claims (state keys), not poses (the invariants constraint_vertex and constraint_edge "
    "read poses); one moment at a time: the lemmas' claim intervals in continuous time are not recorded",
    _GRID_CITES["claims"], stream=_claims_stream, every_step=True, own=True))

#: ``grid_heard``: every robot within R throughout a departing robot's window, that broadcast in it, was heard.
GRID_HEARD = register_property(Property(
    "grid_heard", "safety", _heard, ("poses", "states' heard, window, moving", "range", "clock rates"),
    "'heard' lists senders, not messages (at least one broadcast reached it); a robot that came within R during "
    "the window is not owed; streamed without per-robot clock rates, the window is taken at its longest for "
    "'within R throughout' and its shortest for 'broadcast in it'",
    _GRID_CITES["heard"], stream=_heard_stream, every_step=True, own=True))

#: ``grid_spacing``: the run's grid length against Sec. III-A's and Sec. V-B3's bounds.
GRID_SPACING = register_property(Property(
    "grid_spacing", "safety", _spacing, ("trace meta: grid_spacing, robot_radius, speeds drawn", "range"),
    "the run's parameters, once (not a step); inconclusive on a trace that does not record them",
    _GRID_CITES["spacing"], own=True))
