"""benchmarks/wang2020/bench_wang2020_ratio.py: the decomposition of wang2020's travelled distance, the other
readings of ambiguous text (each differs from the reference exactly where intended) and the
idealised swap bounds (docs/wang2020.md, "Why the distance ratio grows with n")."""

from __future__ import annotations

from collections import deque

import numpy as np
import pytest

from swarmproof.reference_impl.wang2020 import algorithm as W
from swarmproof.reference_impl.wang2020.experiments import experiment_params


def _load():
    from testkit import load_benchmark

    return load_benchmark("wang2020/bench_wang2020_ratio")


B = _load()
Q = ((0, 0), (1, 0), (2, 0), (3, 0))


def _agent(reading: str, wp, T, *, rid=0, beta=0.5, seed=0):
    """A controller of ``reading`` started at rest on ``wp`` with goal ``T`` (shape Q)."""
    p = experiment_params(len(Q), beta=beta)
    a = B.controller_class(reading)(rid, p, (Q,), np.random.default_rng(seed))
    a.started = True
    a.cell = a.wp = a.next_step = wp
    a.p = (a.l * wp[0], a.l * wp[1])
    a.T, a.q_u, a.hop = T, T, float("inf")
    a.now = 10.0
    return a


def _msg(a, wp, T, **kw):
    return W.WangMsg((a.l * wp[0], a.l * wp[1]), wp, wp, T, T, None, **kw)


def test_the_decomposition_adds_up_exactly_on_a_small_trial():
    r = B.decompose(16, 0)
    assert r["status"] == "stopped" and r["formed_s"] is not None
    assert r["travelled"] == pytest.approx(r["initial"] + r["swaps"] + r["duplicates"] - r["residual"], abs=1e-6)
    assert r["optimum"] <= r["random_assignment"] and r["ratio"] == pytest.approx(r["travelled"] / r["optimum"], abs=1e-3)
    assert r["swaps_done"] > 0 and r["dup_changes"] > 0


def test_own_goal_counts_as_assigned_only_in_reading_own():
    # the agent at (0, 0) holds goal (1, 0); a neighbour at (0, 2) holds (3, 0): (1, 0) is in no message
    for reading, anchors in (("", True), ("own", False)):
        a = _agent(reading, (0, 0), (1, 0))
        a.buff = deque([(10.0, 1, _msg(a, (0, 2), (3, 0)), 0)])
        a.q_u = (2, 0)
        a._gradient()
        assert (a.q_u == (1, 0) and a.hop == 0) is anchors, reading


def test_an_agent_resting_on_its_goal_keeps_it_only_in_reading_rest():
    # both hold (1, 0); the other agent is lexically larger but not on the goal
    for reading, changes in (("", True), ("rest", False)):
        a = _agent(reading, (1, 0), (1, 0), seed=3)
        a.q_u = (3, 0)
        a._goal_manager(10.0, 1, _msg(a, (5, 0), (1, 0)))
        assert (a.T != (1, 0)) is changes, reading


def test_reading_pref_hands_the_tick_to_the_most_reducing_peer():
    # agent at (0, 0) with goal (3, 0); peer 1 (equal cost, first in the tick), peer 2 (reducing)
    for reading, peer in (("", 1), ("pref", 2)):
        a = _agent(reading, (0, 0), (3, 0), beta=0.999999)
        m_equal = _msg(a, (0, 1), (2, 0))           # 3 + 3 = 6 now, 2 + 4 = 6 swapped
        m_reduce = _msg(a, (3, 1), (0, 0))          # 3 + 4 = 7 now, 0 + 1 = 1 swapped
        if reading:
            a._cands, a._defer = [], True
        a._goal_manager(10.0, 1, m_equal)
        a._goal_manager(10.0, 2, m_reduce)
        if reading:
            a._main(10.0)
        assert a.hs is not None and a.hs.peer == peer, reading


def test_reading_srv_accepts_an_unexpected_reducing_request():
    # agent 5 at (3, 0) holds (0, 0); agent 1 at (0, 1) (lexically smaller: a client) holds (3, 0) and
    # requests a swap agent 5 never intended: 3 + 4 now, 0 + 1 swapped
    for reading, takes in (("", False), ("srv", True)):
        a = _agent(reading, (3, 0), (0, 0), rid=5)
        a._goal_manager(10.0, 1, _msg(a, (0, 1), (3, 0), request=(5, 1, (3, 0))))
        assert (a.T == (3, 0) and a.ack is not None and a.ack[:3] == (1, 1, (0, 0))) is takes, reading


def test_reading_req_stops_requesting_a_round_trip_before_the_timeout():
    for reading, late_request in (("", True), ("req", False)):
        a = _agent(reading, (0, 0), (3, 0))
        a.hs = W._Handshake("client", 1, 1, a.now + a.timeout, a.T)
        assert a.message().request == (1, 1, (3, 0))
        a.now = a.hs.deadline - 0.5 * a.delta_t
        assert (a.message().request is not None) is late_request, reading


def test_static_swaps_reach_only_neighbours_and_dynamic_swaps_meet_on_the_way():
    goals = [(1, 0), (19, 0)]
    near = [(0, 0), (2, 0)]
    far = [(0, 0), (20, 0)]
    crossed = [1, 0]
    rng = np.random.default_rng(0)
    assert B.static_swaps(near, goals, crossed, rng) == 18          # within R: the optimum (1 + 17)
    assert B.static_swaps(far, goals, crossed, rng) == 38           # 20 apart: no swap
    d = B.dynamic_swaps(far, goals, crossed, rng)                    # they swap once within R
    assert 2 < d < 38


def test_bounds_on_a_small_instance():
    r = B.bounds(16, 0, reps=1)
    assert 1.0 <= r["dynamic_over_opt"] and 1.0 <= r["static_over_opt"] <= r["random_over_opt"] * 1.2
