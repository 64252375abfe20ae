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


# -- oscillation: no progress over a window (randomized algorithms) --------------------

def _moving(T):
    states = [(("tick", i),) for i in range(T + 1)]
    return make([[[0.01 * i, 0]] for i in range(T + 1)], states=states)


def test_no_progress_held_when_the_measure_improves_within_every_window():
    t = _moving(10)
    r = oscillation(t, 1e-6, randomized=True, progress=[0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4], window=3)
    assert r.held and "progress within every 3 steps" in r.message


def test_no_progress_violated_names_the_stall():
    t = _moving(10)
    r = oscillation(t, 1e-6, randomized=True, progress=[0, 1, 1, 1, 2, 1.5, 1.9, 2, 2, 3, 4], window=4)
    assert r.violated
    assert r.witness == {"kind": "no_progress", "step": 8, "since": 4, "window": 4, "best": 2.0}
    assert r.message.startswith("no progress for 4 steps: the goal measure stayed at most 2 ")
    # the same stall with the goal reached at its end is not reported
    assert oscillation(t, 1e-6, randomized=True, progress=[0, 1, 1, 1, 2, 1.5, 1.9, 2, 2, 3, 4], window=4,
                       goal_reached=lambda s: s >= 8).held


def test_no_progress_window_longer_than_the_trace_is_not_judged():
    t = _moving(5)
    assert oscillation(t, 1e-6, randomized=True, progress=[0] * 6, window=6).held


def test_randomized_without_measure_inconclusive_and_cycle_rule_off():
    # a revisited global state: a cycle for a deterministic algorithm, not for a randomized one
    t = make([[[0, 0]], [[1, 0]], [[0, 0]]])
    assert oscillation(t, 1e-3).violated
    r = oscillation(t, 1e-3, randomized=True)
    assert r.status == "inconclusive" and "without a progress measure" in r.message
    assert oscillation(t, 1e-3, randomized=True, progress=[0, 1, 2], window=2).held


def test_no_progress_bad_arguments():
    t = _moving(3)
    with pytest.raises(ValueError, match="window=None"):
        oscillation(t, 1e-6, progress=[0, 1, 2, 3])
    with pytest.raises(ValueError, match=r"shape=\(2,\)"):
        oscillation(t, 1e-6, progress=[0, 1], window=2)


# -- premises ---------------------------------------------------------------------------

def _follower(end_xy):
    poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [end_xy[0], end_xy[1], 0]]], float)
    return Trace(ids=[4, 7], poses=poses, states=[((("parent", None),), (("parent", 4),))] * 2)


def test_premises_held_violated_and_inconclusive():
    import swarmproof.reference_impl.song2014  # noqa: F401  (registers its monitors)
    from swarmproof.invariants.properties import premises

    ok = premises(_follower((0.95, 0)), ("step_bounded", "parent_bounded_range"), 1.2, 0.2, 1.0)
    assert ok.held and ok.message == ("premises held at all 1 steps: step_bounded (2 checked), "
                                      "parent_bounded_range (1 checked)")
    assert ok.detail["monitors"]["parent_bounded_range"]["checked"] == 1
    # too far a step AND outside the parent's disc: the earliest step, first declared monitor
    bad = premises(_follower((1.25, 0)), ("step_bounded", "parent_bounded_range"), 1.2, 0.2, 1.0)
    assert bad.violated and (bad.witness["monitor"], bad.witness["lemma"]) == ("step_bounded", "bounded_range")
    assert bad.message.startswith("premise of lemma bounded_range failed: step 0, robot 7: premise "
                                  "child_moves_at_most_v_dt of lemma bounded_range failed, moved 0.25, limit 0.2")
    assert premises(_follower((0.95, 0)), (), 1.2, 0.2, 1.0).status == "inconclusive"
    # song2016's NCLB monitor on a state without "children": cannot judge
    r = premises(_follower((0.95, 0)), ("nclb",), 1.2, 0.2, 1.0)
    assert r.status == "inconclusive" and "has no 'children'" in r.message
