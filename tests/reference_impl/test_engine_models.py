"""Engine models (issue 12): anonymous sensing without IDs, the neighbor rule a model declares,
communication to all in O(n), and delayed, duplicated and reordered messages that replay exactly."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarmproof.models.errors import UsageError
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import FaultModel, simulate
from swarmproof.reference_impl.protocol import Command, Params, RobotModel

P = Params(range=1.0, v=0.1, omega=math.pi / 4, dt=1.0)


def _observations(ids, model, faults=None, steps=6):
    from testkit import Recorder

    poses = [[0, 0, 0.3], [0.6, 0, 1.0], [0.3, 0.5, -2.0], [1.2, 0.2, 0.0]]
    algo = Recorder(model)
    r = simulate(algo, None, InitialConfiguration(ids, poses), P, seed=5, max_steps=steps,
                 stop_when_static=False, faults=faults)
    return [obs for _, obs in algo.seen], r


@pytest.mark.parametrize("communication", ["neighbors", "all", "none"])
def test_an_anonymous_controller_cannot_learn_any_robot_id(communication):
    """Relabel the robots: every observation stays bit-identical, so nothing in it depends on IDs."""
    model = RobotModel(sensing="anonymous", communication=communication, motion="holonomic")
    first, r1 = _observations([0, 1, 2, 3], model)
    second, r2 = _observations([907, 13, 4, 250], model)
    assert len(first) == len(second) == 24
    for a, b in zip(first, second):
        assert a.robot_id is None and a.neighbor_ids is None and a.own_pose is None
        assert a.neighbor_poses.shape == (3, 2)                  # positions only: no headings
        assert a.neighbor_poses.tobytes() == b.neighbor_poses.tobytes()
        assert dict(a.messages) == dict(b.messages) and a.inbox == b.inbox
        assert all(sender is None for sender, _ in a.inbox)
        assert set(a.messages) <= set(range(3))                  # keyed by sensed row, not by ID
    assert np.array_equal(r1.trace.poses, r2.trace.poses)
    if communication != "none":
        assert any(o.messages for o in first)


def test_anonymous_robots_hear_only_the_robots_in_range():
    model = RobotModel(sensing="anonymous", communication="neighbors", motion="holonomic")
    seen, _ = _observations([0, 1, 2, 3], model, steps=2)
    obs = [o for o in seen if o.step == 1]
    for o in obs:
        near = {r for r, (x, y) in enumerate(o.neighbor_poses.tolist()) if math.hypot(x, y) < 1.0}
        assert set(o.messages) == near


def test_the_neighbor_rule_is_the_models_strict_or_inclusive(recorder):
    init = InitialConfiguration([0, 1], [[0, 0, 0], [1.0, 0, 0]])          # exactly phi apart
    got = {}
    for rule in ("strict", "inclusive"):
        algo = recorder(RobotModel(neighbor_rule=rule), command=lambda rid, k, obs, rng: Command(message="x"))
        r = simulate(algo, None, init, P, seed=0, max_steps=2, stop_when_static=False)
        got[rule] = [o.neighbor_ids for _, o in algo.seen]
        assert r.trace.meta["model"]["neighbor_rule"] == rule
    assert got == {"strict": [(), (), (), ()], "inclusive": [(1,), (0,), (1,), (0,)]}
    with pytest.raises(UsageError, match=r"RobotModel neighbor_rule='closest' is not one of \['strict', 'inclusive'\]"):
        RobotModel(neighbor_rule="closest")


def test_the_connectivity_property_follows_the_models_neighbor_rule(recorder):
    from swarmproof.invariants.connectivity import connected_throughout

    init = InitialConfiguration([0, 1], [[0, 0, 0], [1.0, 0, 0]])
    algo = recorder(RobotModel(neighbor_rule="inclusive"), command=lambda rid, k, obs, rng: Command())
    r = simulate(algo, None, init, P, seed=0, max_steps=1, stop_when_static=False)
    assert connected_throughout(r.trace, 1.0).status == "held"
    assert connected_throughout(r.trace, 1.0, inclusive=False).status == "inconclusive"  # vacuous start


def test_communication_to_all_delivers_every_other_robots_message():
    model = RobotModel(communication="all")
    seen, _ = _observations([0, 1, 2, 3], model, steps=3)
    for o in seen:
        if o.step == 0:
            assert dict(o.messages) == {}
            continue
        assert sorted(o.messages) == sorted({0, 1, 2, 3} - {o.robot_id})
        assert o.robot_id not in o.messages and len(o.messages) == 3
        assert o.inbox == tuple(o.messages.items())


def _late_faults():
    return FaultModel(message_delay=2, message_duplication=0.4, message_reorder=True, message_loss=0.1)


def test_delayed_duplicated_reordered_messages_are_recorded_and_replay_bit_identically():
    model = RobotModel(communication="all")
    seen, r = _observations([0, 1, 2, 3], model, faults=_late_faults(), steps=12)
    assert {"timely_messages", "messages_delivered_once", "ordered_messages", "reliable_messages"} <= \
        set(r.broken_assumptions)
    late = [e for e in r.trace.events if e.kind == "late_delivery"]
    assert late, "no delivery was late or duplicated in 12 steps"
    # a duplicated delivery shows in the inbox twice; a delayed one arrives after newer ones
    assert any(len(o.inbox) > len({s for s, _ in o.inbox}) for o in seen)
    assert any(any(m[2] < o.step - 1 for _, m in o.inbox) for o in seen)
    # the replay: the same fault model rebuilt from its description, the same seed
    again = FaultModel.from_dict(r.trace.meta["faults"])
    assert again.describe() == _late_faults().describe()
    seen2, r2 = _observations([0, 1, 2, 3], model, faults=again, steps=12)
    assert r2.trace.poses.tobytes() == r.trace.poses.tobytes()
    assert r2.trace.events == r.trace.events and r2.trace.states == r.trace.states
    assert [o.inbox for o in seen2] == [o.inbox for o in seen]


def test_late_messages_of_anonymous_robots_keep_no_sender():
    model = RobotModel(sensing="anonymous", communication="all", motion="holonomic")
    first, _ = _observations([0, 1, 2, 3], model, faults=_late_faults(), steps=8)
    second, _ = _observations([40, 2, 77, 9], model, faults=_late_faults(), steps=8)
    assert [o.inbox for o in first] == [o.inbox for o in second]
    assert all(s is None for o in first for s, _ in o.inbox)


@pytest.mark.parametrize("kwargs, match", [
    (dict(message_delay=-1), r"message_delay=-1 must be an integer >= 0"),
    (dict(message_delay=1.5), r"message_delay=1.5 must be an integer >= 0"),
    (dict(message_duplication=2.0), r"message_duplication=2.0 must be a number in \[0, 1\]"),
])
def test_bad_message_faults_are_named(kwargs, match):
    with pytest.raises(UsageError, match=match):
        FaultModel(**kwargs)


def test_fault_descriptions_without_the_new_faults_are_unchanged():
    d = FaultModel(message_loss=0.2).describe()
    assert "message_delay" not in d and "message_reorder" not in d
