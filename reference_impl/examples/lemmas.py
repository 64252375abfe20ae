"""A lemma about ``example-gather``, declared once and bound to its runs (issue 32; docs/lemmas.md).

``example-gather`` (:class:`~.algorithms.GatherToLowestId`) is not from a paper; this lemma is
the worked example of stating one's own: true of the algorithm as written, with every premise it
needs, proved by z3 (``swarmproof prove gather_follower_link_kept``) and monitored on every step
of every run (``premise_monitors = ("gather_link",)``: :data:`GATHER_LINK`).

What is true, and what is not.  A follower steers to the point ``gap`` short of where it saw its
leader (the lowest-ID neighbour) and stops there; ``steer_toward`` turns before it drives, so in
a step it may not move at all; its leader follows a leader of its own and may pull away by up to
``v dt``.  So "the follower gets closer to its leader" is false (a follower closer than
``gap + v dt`` stops at ``gap`` while its leader leaves), and so is "the link is kept" without a
margin (a follower turning in place ``phi - epsilon`` from a leader driving away loses it).  What
holds is: **a follower that does not end farther from its leader's old position, within
``phi - v dt`` of it, stays within ``phi`` of the leader, which moves at most ``v dt``.**  The
follower's premise is what its code guarantees (a straight drive toward a point on the segment to
its leader, or no drive); the margin selects the pairs the lemma speaks of (``given``); the
leader's premise is the engine's speed limit.

Normalised as the song2016 lemmas are: the leader's position at ``t`` at the origin, ``phi = 1``,
``s = v dt / phi``; ``f0``/``f1`` the follower before/after the step, ``l1`` the leader after.
"""

from __future__ import annotations

import numpy as np

from swarmproof.invariants.lemma_api import And, Gt, Le, LemmaSpec, Lt, Point, Real, dist2
from swarmproof.invariants.lemma_monitor import Batch, Binding
from swarmproof.invariants.premises import register_binding

__all__ = ["GATHER_FOLLOWER_LINK_KEPT", "GATHER_LINK", "SPECS", "LEMMAS"]


def _premises(margin: str) -> tuple:
    """The lemma's premises; ``margin="phi"`` drops the ``v dt`` margin (the negative control)."""
    def near(v):
        r = 1 - v.s
        return Lt(dist2(v.f0), r * r) if margin == "phi_minus_vdt" else Lt(dist2(v.f0), 1)

    return (
        ("step_below_range", lambda v: And(Gt(v.s, 0), Lt(v.s, 1))),
        ("near_leader", near),
        ("follower_not_farther", lambda v: Le(dist2(v.f1), dist2(v.f0))),
        ("leader_moves_at_most_v_dt", lambda v: Le(dist2(v.l1), v.s * v.s)),
    )


GATHER_FOLLOWER_LINK_KEPT = LemmaSpec(
    id="gather_follower_link_kept",
    statement="A follower within phi - v dt of its leader's position at t that does not end the step "
              "farther from that position stays strictly within phi of its leader, which moves at "
              "most v dt: ||p_f(t+dt) - p_l(t+dt)|| < phi.",
    kind="auxiliary",
    cites=("example-gather (reference_impl/examples/algorithms.py, GatherController.step; docs/lemmas.md)",),
    variables=(Real("s", 0.0, 1.0), Point("f0", -1.0, 1.0), Point("f1", -1.0, 1.0), Point("l1", -1.0, 1.0)),
    premises=_premises("phi_minus_vdt"),
    conclusion=lambda v: Lt(dist2(v.f1, v.l1), 1),
    control_premises=_premises("phi"),
    control_note="the follower anywhere within phi of its leader (no v dt margin)",
    normalisations=("translation: the leader's position at t at the origin (translation_invariance)",
                    "scale: phi = 1, s = v*dt/phi in (0, 1) (scale_invariance)"),
    not_proved=("that the follower gets closer to its leader: false (a follower closer than gap + v dt "
                "stops at gap while its leader may pull away)",
                "the link of a pair farther apart than phi - v dt at t: the lemma does not speak of it "
                "(the monitor counts such pairs as outside)",
                "that the swarm gathers or stays connected: example-gather claims neither"),
)

#: The lemma by id (:func:`swarmproof.reference_impl.registry.lemma_sets` adds them to the suite).
SPECS: dict = {GATHER_FOLLOWER_LINK_KEPT.id: GATHER_FOLLOWER_LINK_KEPT}
LEMMAS: dict = {i: spec.lemma() for i, spec in SPECS.items()}


# ------------------------------------------------------------------ the binding (its runtime monitor)

def _followers_and_leaders(view):
    """Every robot that followed a leader in the step (state key ``"target"`` after it: the
    leader's ID) with that leader, both present at both ends; the leader's start at the origin."""
    followers, leaders = [], []
    for k in view.robots():
        leader = view.state(k, "target")
        q = None if leader is None else view.slot(leader)
        if q is not None:
            followers.append(k)
            leaders.append(q)
    yield Batch({"follower": view.ids_of(followers), "leader": view.ids_of(leaders)},
                {"s": view.s, **view.points("f0", followers, 0, leaders), **view.points("f1", followers, 1, leaders),
                 **view.points("l1", leaders, 1, leaders)},
                facts={"before": np.round(view.distances(followers, 0, leaders, 0), 12),
                       "after": np.round(view.distances(followers, 1, leaders, 0), 12)})


#: ``gather_link``: the monitor of :data:`GATHER_FOLLOWER_LINK_KEPT` on every step of an
#: ``example-gather`` run (premise ``near_leader`` selects the pairs it speaks of).
GATHER_LINK = Binding("gather_link", GATHER_FOLLOWER_LINK_KEPT, _followers_and_leaders,
                      what="follower/leader steps", given=("step_below_range", "near_leader"))

register_binding(GATHER_LINK)
