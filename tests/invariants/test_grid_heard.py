"""wang2020's property ``grid_heard`` (a premise monitor until issue 32; reference_impl/wang2020/
properties.py, :class:`GridHeard`): which robots a departing robot must have heard, over which
frames, for 004 Lemma IV-A.1's premise ``lossless_delivery_within_R`` to hold (docs/decisions.md,
"Wang & Rubenstein 2020: grid_heard (issue 15)")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarmproof.invariants.registry import get_property
from swarmproof.reference_impl.wang2020.monitors import GridHeard, grid_heard_neighbours
from swarmproof.models.trace import InitialConfiguration, Trace

L = 0.2


def _trace(far_until, *, heard=(), window=2.0, depart=4, frames=6, extra=None):
    """Robot 1 waits at the origin and sets off in step ``depart``; robot 2 stands 0.8 m away up to
    frame ``far_until - 1`` and 0.2 m away from frame ``far_until`` on (R = 0.6)."""
    poses = np.zeros((frames, 2, 3))
    poses[:, 1, 0] = [0.8 if f < far_until else L for f in range(frames)]
    st = lambda moving, h: (("moving", moving), ("heard", h), ("window", window))  # noqa: E731
    states = [(st(f > depart, heard), st(False, (1,))) for f in range(frames)]
    meta = {} if extra is None else {"params": {"extra": extra}}
    return Trace(ids=[1, 2], poses=poses, states=states, meta=meta)


def _old_monitor_flags(trace, phi):
    """The monitor before issue 15's analysis: every robot within R at the departure frame unheard."""
    for t in range(trace.frames - 1):
        for k in range(trace.n):
            if dict(trace.states[t][k])["moving"] or not dict(trace.states[t + 1][k])["moving"]:
                continue
            heard = set(dict(trace.states[t + 1][k])["heard"])
            p = trace.poses[t]
            if any(j != k and math.hypot(*(p[j, :2] - p[k, :2])) <= phi and int(trace.ids[j]) not in heard
                   for j in range(trace.n)):
                return True
    return False


# (frame robot 2 comes within R, expected verdict): the window of robot 1's departure in step 4 is
# 2 steps, its receipts those of steps 2..4 (the broadcasts of steps 1..3, delivered to the robots
# within R at frames 2..4)
@pytest.mark.parametrize("far_until, status", [
    (0, "violated"),      # within R all along
    (2, "violated"),      # within R from the window's first frame on: every receipt owed
    (3, "held"),          # came within R one frame into the window: its first broadcast went nowhere
    (4, "held"),          # came within R in the very step robot 1 set off
], ids=["all-along", "from-first-frame", "one-frame-late", "this-step"])
def test_only_robots_within_R_throughout_the_window_are_owed(far_until, status):
    r = grid_heard_neighbours(_trace(far_until), 0.6)
    assert r.status == status
    if status == "violated":
        assert r.witness == {"step": 4, "robot": 1, "unheard": [2], "frames": [2, 4], "window_steps": 2,
                             "lemma": "wang2020_lemma_iv_a_1"}
        assert r.message == "robot 1 set off in step 4 without having heard [2], within R throughout its window (steps 2..4)"
    else:
        assert r.detail["arrived_unheard"] == 1 and r.detail["owed"] == 0


def test_a_robot_heard_is_no_violation_and_the_old_monitor_flagged_a_late_arrival():
    assert grid_heard_neighbours(_trace(0, heard=(2,)), 0.6).status == "held"
    late = _trace(4)
    assert _old_monitor_flags(late, 0.6)                       # the defect: it was flagged
    assert grid_heard_neighbours(late, 0.6).status == "held"


def test_a_window_shorter_than_a_broadcast_period_owes_nothing():
    # a broadcast every 4 steps and a window of 2: robot 2 need not have broadcast in it
    assert grid_heard_neighbours(_trace(0, extra={"broadcast_every": 4.0}), 0.6).status == "held"
    # a broadcast every 2 steps: the 2 steps surely read (3 less the boundary step) hold one
    assert grid_heard_neighbours(_trace(0, extra={"broadcast_every": 2.0}), 0.6).status == "violated"


def test_the_window_span_follows_the_clock_rate():
    # rate 2 (clock units per step): a window of 4 units spans 2 steps -> frames 2..4
    slow = _trace(3, window=4.0, extra={"clock_rate_min": 2.0, "clock_rate_max": 2.0})
    assert grid_heard_neighbours(slow, 0.6).status == "held"
    # rate 1: 4 steps -> frames 1..4 (robot 2 came within R at frame 3: not owed either)
    assert grid_heard_neighbours(_trace(3, window=4.0), 0.6).status == "held"
    r = grid_heard_neighbours(_trace(1, window=4.0), 0.6)
    assert r.status == "violated" and r.witness["frames"] == [1, 4]


def test_missing_keys_inconclusive_and_sparse_windows_not_a_pass():
    tr = _trace(0)
    bare = Trace(ids=[1, 2], poses=tr.poses, states=[((("moving", f > 4),), (("moving", False),))
                                                      for f in range(6)])
    r = grid_heard_neighbours(bare, 0.6)
    assert r.status == "inconclusive" and "without 'heard' and 'window'" in r.message
    # a sparse trace that kept frames 0, 4, 5 only: the window of step 4 (frames 2..4) is unknown
    sparse = Trace(ids=[1, 2], poses=tr.poses[[0, 4, 5]], states=[tr.states[i] for i in (0, 4, 5)],
                   times=[0, 4, 5])
    r = grid_heard_neighbours(sparse, 0.6)
    assert r.status == "inconclusive" and r.detail["unjudged"] == 1


def test_streaming_form_keeps_its_own_frames_and_agrees():
    tr = _trace(2)
    from swarmproof.reference_impl.protocol import Params

    mon = get_property("grid_heard").stream(None, Params(range=0.6, v=0.05), {})
    mon.start(tr.ids)
    for t in range(tr.frames):
        mon.observe(t, tr.poses[t], tr.states[t], np.ones(2, dtype=bool))
    r = mon.result()
    assert r.status == "violated" and r.witness == grid_heard_neighbours(tr, 0.6).witness


# -- the explorer's counterexample (issue 15) and a real loss ------------------------------------

def _column(loss=0.0, observers=()):
    """`swarmproof explore wang2020 --property premises --max-examples 100 --seed 0` (before the
    fix): 4 agents in a column at x = -0.2, letter-l scaled to 4 cells, seed 2.  Found on wang2020's
    reading "1", ``wang2020-broadcast-handshake`` since 0.3.0 (the same traces)."""
    from swarmproof.models.targets import resolve_target
    from swarmproof.reference_impl.engine import FaultModel, simulate
    from swarmproof.reference_impl.wang2020.algorithm import Wang2020, Wang2020BroadcastHandshake, default_params

    alg = Wang2020BroadcastHandshake()
    target = Wang2020.scale_target(resolve_target("shape:letter-l"), 4)
    init = InitialConfiguration([0, 1, 2, 3], [[-0.2, y, 0.0] for y in (0.4, 0.2, 0.0, -0.2)])
    params = default_params(0.6, 4)
    faults = FaultModel(message_loss=loss) if loss else None
    return alg, params, simulate(alg, target, init, params, seed=2, faults=faults, allow_violations=bool(loss),
                                 observers=observers, max_steps=400)


def test_the_explorer_counterexample_was_a_late_arrival_and_holds_now():
    _, _, r = _column()
    tr = r.trace
    st = lambda f, k: dict(tr.states[f][k])  # noqa: E731
    # robot 3 sets off in step 48 (from (2, -1) toward (2, 0)) without robot 1 in its msg_buff ...
    assert not st(48, 3)["moving"] and st(49, 3)["moving"] and st(49, 3)["wp"] == (2, 0)
    assert 1 not in st(49, 3)["heard"]
    # ... robot 1, travelling from (-1, 0) to (0, 0), came within R = 0.6 only at frame 48
    d = [math.hypot(*(tr.poses[f][1, :2] - tr.poses[f][3, :2])) for f in (44, 47, 48)]
    assert d[0] > 0.6 and d[1] == pytest.approx(0.6088, abs=1e-4) and d[2] == pytest.approx(0.5852, abs=1e-4)
    # its broadcasts of steps 44 and 46 were sent from beyond R; the next (step 48) is heard in step 49
    assert 1 in st(50, 3)["heard"]
    assert _old_monitor_flags(tr, 0.6)
    res = grid_heard_neighbours(tr, 0.6)
    assert res.status == "held" and res.detail["arrived_unheard"] == 1 and res.detail["checked"] == 10


def test_message_loss_is_found_streaming_and_on_the_trace():
    from swarmproof.invariants.registry import PropertyContext

    alg, params, _ = _column()
    prop = get_property("grid_heard")
    mon = prop.stream(alg, params, {})
    _, _, r = _column(loss=0.5, observers=[mon])
    streamed = mon.result()
    batch = prop.check(r.trace, PropertyContext(alg, None, params, r))
    assert streamed.status == batch.status == "violated"
    assert streamed.witness == batch.witness == {"step": 10, "robot": 0, "unheard": [1], "frames": [6, 10],
                                                 "window_steps": 4, "lemma": "wang2020_lemma_iv_a_1"}


def test_accumulator_stops_at_the_first_violation():
    acc = GridHeard(0.6)
    acc.scan(_trace(0))
    first = acc.result()
    acc.scan(_trace(0, heard=(2,)))
    assert acc.result().witness == first.witness
