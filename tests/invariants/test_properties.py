"""Hand-made traces for the explorer's property predicates: held AND violated for each."""

import numpy as np
import pytest

from swarmproof.invariants.properties import collision, deadlock, oscillation, segment_min_distances
from swarmproof.models.trace import Trace


def make(xy_per_step, states=None, messages=None, ids=None):
    P = np.asarray(xy_per_step, float)
    poses = np.concatenate([P, np.zeros(P.shape[:2] + (1,))], axis=2)
    T1, n = poses.shape[:2]
    if states is None:
        states = [tuple(("s",) for _ in range(n))] * T1
    return Trace(ids=ids if ids is not None else list(range(n)), poses=poses, states=states, messages=messages)


# -- collision -------------------------------------------------------------------------

def test_collision_crossing_midway_is_seen_though_ends_are_far():
    # they swap places along the same line: at both ends 2 apart, midway they meet
    t = make([[[0, 0], [2, 0]], [[2, 0], [0, 0]]])
    r = collision(t, 0.1)
    assert r.violated and r.witness["step"] == 0 and r.witness["fraction"] == pytest.approx(0.5)
    assert r.witness["distance"] == pytest.approx(0.0)


def test_collision_parallel_motion_held_and_radius_threshold():
    t = make([[[0, 0], [0, 1]], [[1, 0], [1, 1]], [[2, 0], [2, 1]]])
    assert collision(t, 0.49).held
    r = collision(t, 0.51)
    assert r.violated and r.witness["robots"] == [0, 1] and r.witness["step"] == 0


def test_collision_reports_first_step_and_ids():
    t = make([[[0, 0], [5, 0], [9, 9]], [[0, 0], [5, 0], [9, 9]], [[0, 0], [0.3, 0], [9, 9]]], ids=[7, 3, 1])
    r = collision(t, 0.2)
    assert r.violated and r.witness["step"] == 1 and r.witness["robots"] == [3, 7]


def test_segment_min_distances_matches_dense_sampling():
    rng = np.random.default_rng(0)
    a0, a1, b0, b1 = (rng.normal(size=(50, 2)) for _ in range(4))
    d, _ = segment_min_distances(a0, a1, b0, b1)
    s = np.linspace(0, 1, 2001)[:, None, None]
    dense = np.linalg.norm((a0 + s * (a1 - a0)) - (b0 + s * (b1 - b0)), axis=2).min(axis=0)
    assert np.all(d <= dense + 1e-12) and np.allclose(d, dense, atol=1e-3)


def test_collision_bad_radius():
    with pytest.raises(ValueError, match="radius=0"):
        collision(make([[[0, 0]]]), 0)


# -- deadlock --------------------------------------------------------------------------

def test_deadlock_violated_after_k_quiet_steps():
    t = make([[[0, 0]], [[1, 0]]] + [[[1, 0]]] * 4)
    r = deadlock(t, 3)
    assert r.violated and r.witness == {"step": 1, "window": 3}


def test_deadlock_held_when_goal_reached_or_state_changes():
    t = make([[[0, 0]], [[1, 0]]] + [[[1, 0]]] * 4)
    assert deadlock(t, 3, goal_reached=True).held
    states = [(("s", i),) for i in range(6)]  # a controller whose state keeps changing is not quiet
    assert deadlock(make([[[0, 0]], [[1, 0]]] + [[[1, 0]]] * 4, states=states), 3).held


def test_deadlock_messages_break_quiet_and_short_trace_inconclusive():
    msgs = [{0: i} for i in range(5)]
    t = make([[[0, 0]]] * 6, messages=msgs)
    assert deadlock(t, 3).held
    assert deadlock(make([[[0, 0]]] * 2), 3).status == "inconclusive"


# -- oscillation -----------------------------------------------------------------------

def test_oscillation_cycle_violated_and_held_with_goal():
    t = make([[[0, 0]], [[1, 0]], [[0, 0]]])
    r = oscillation(t, 1e-3)
    assert r.violated and r.witness == {"kind": "cycle", "step": 2, "revisits": 0}
    assert oscillation(t, 1e-3, goal_reached=True).held


def test_oscillation_held_on_straight_motion_and_staying_put():
    t = make([[[x, 0]] for x in range(10)] + [[[9, 0]]] * 5)
    assert oscillation(t, 1e-3).held


def test_oscillation_back_and_forth_with_changing_states():
    xs = [0, 1, 0, 1, 0, 1, 0, 1]
    states = [(("tick", i),) for i in range(len(xs))]  # no global cycle: states keep changing
    t = make([[[x, 0]] for x in xs], states=states, ids=[4])
    r = oscillation(t, 1e-3, min_returns=3)
    assert r.violated and r.witness["kind"] == "back_and_forth" and r.witness["robot"] == 4
    assert r.witness["returns"] >= 3
    # two returns only: below the threshold
    assert oscillation(make([[[x, 0]] for x in xs[:4]], states=states[:4]), 1e-3, min_returns=3).held
    # excursion larger than the swing: not back and forth
    assert oscillation(t, 1e-3, excursion=2.0).held


def test_oscillation_one_slow_reversal_is_not_back_and_forth():
    xs = list(np.linspace(0, 1, 21)) + list(np.linspace(1, 0, 21)[1:])
    states = [(("tick", i),) for i in range(len(xs))]
    r = oscillation(make([[[x, 0]] for x in xs], states=states), 1e-3, min_returns=2)
    assert r.held
