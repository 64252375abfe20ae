"""The simulation engine: determinism, sensing, motion limits, assumptions, protocol, faults."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarmproof.models.errors import AssumptionError, ProtocolError, UsageError
from swarmproof.models.se2 import relative_many
from swarmproof.models.trace import InitialConfiguration, Trace
from swarmproof.reference_impl.engine import FaultModel, TableSchedule, default_static_window, simulate
from swarmproof.reference_impl.examples.algorithms import GatherToLowestId
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import (Assumption, Command, Params, RobotModel,
                                                connected_start)


class Scripted:
    """An algorithm whose controllers record observations and replay a command function."""

    name = "scripted"

    def __init__(self, fn, model=RobotModel(), assumptions=(), finished=lambda s: False):
        self.fn = fn
        self.model = model
        self.assumptions = assumptions
        self._finished = finished
        self.seen: dict = {}

    def controller(self, robot_id, params, lattice, rng):
        algo = self

        class C:
            def __init__(self):
                self.k = 0

            def step(self, obs):
                algo.seen.setdefault(robot_id, []).append(obs)
                self.k += 1
                return algo.fn(robot_id, obs, rng)

            def state(self):
                return (("k", self.k),)

        return C()

    def finished(self, states):
        return self._finished(states)


def random_walk(rid, obs, rng):
    return Command(message=("hi", rid, obs.step), turn=float(rng.uniform(-1, 1)),
                   forward=float(rng.uniform(0, 0.2)))


P = Params(range=1.0, v=0.1, omega=math.pi / 4, dt=1.0)


def test_same_seed_gives_bit_identical_trace_json():
    init = random_connected(8, 3, range=1.0, min_separation=0.3)
    a = simulate(Scripted(random_walk), None, init, P, seed=5, max_steps=40, record_messages=True)
    b = simulate(Scripted(random_walk), None, init, P, seed=5, max_steps=40, record_messages=True)
    c = simulate(Scripted(random_walk), None, init, P, seed=6, max_steps=40, record_messages=True)
    assert a.trace.to_json().encode() == b.trace.to_json().encode()
    assert np.array_equal(a.trace.poses, b.trace.poses)
    assert not np.array_equal(a.trace.poses, c.trace.poses)


def test_trace_round_trips_through_json_and_npz(tmp_path):
    init = random_connected(5, 1, range=1.0, min_separation=0.3)
    r = simulate(Scripted(random_walk), None, init, P, seed=2, max_steps=10, record_messages=True)
    for name in ("t.json", "t.npz"):
        path = r.trace.save(tmp_path / name)
        back = Trace.load(path)
        assert np.array_equal(back.poses, r.trace.poses)
        assert back.to_json() == r.trace.to_json()
    assert back.states[3] == r.trace.states[3]
    assert back.messages[2] == r.trace.messages[2]


def test_sensing_strict_range_sorted_ids_body_frame():
    # robot 5 at origin facing +y; robot 2 at (0, 0.5) facing +y; robot 9 at exactly range.
    init = InitialConfiguration([5, 9, 2], [[0, 0, math.pi / 2], [1.0, 0, 0], [0, 0.5, math.pi / 2]])
    algo = Scripted(lambda rid, obs, rng: Command())
    simulate(algo, None, init, P, seed=0, max_steps=1, stop_when_static=False)
    obs = algo.seen[5][0]
    assert obs.neighbor_ids == (2,)                        # 9 is at exactly phi: not a neighbor
    assert np.allclose(obs.neighbor_poses, [[0.5, 0.0, 0.0]])
    assert obs.own_pose is None
    assert not obs.neighbor_poses.flags.writeable
    with pytest.raises(ValueError):
        obs.neighbor_poses[0, 0] = 1.0


def test_neighbor_order_is_by_id_and_messages_come_from_last_step():
    init = InitialConfiguration([7, 3, 5], [[0, 0, 0], [0.3, 0, 0], [-0.3, 0, 0]])
    algo = Scripted(lambda rid, obs, rng: Command(message=("m", rid, obs.step)))
    simulate(algo, None, init, P, seed=0, max_steps=2, stop_when_static=False)
    first, second = algo.seen[7]
    assert first.neighbor_ids == (3, 5)
    assert first.messages == {}
    assert second.messages == {3: ("m", 3, 0), 5: ("m", 5, 0)}


def test_motion_is_clamped_turn_then_drive_and_recorded():
    init = InitialConfiguration([0], [[0, 0, 0]])
    algo = Scripted(lambda rid, obs, rng: Command(turn=math.pi / 2, forward=5.0))
    r = simulate(algo, None, init, P, seed=0, max_steps=1)
    x, y, th = r.trace.poses[1, 0]
    # turn clamped to omega*dt = pi/4, taking the whole step: nothing left to drive
    assert th == pytest.approx(math.pi / 4) and (x, y) == (0.0, 0.0)
    assert [e.kind for e in r.trace.events] == ["clamp"]
    algo2 = Scripted(lambda rid, obs, rng: Command(turn=math.pi / 8, forward=5.0))
    r2 = simulate(algo2, None, init, P, seed=0, max_steps=1)
    d = math.hypot(*r2.trace.poses[1, 0, :2])
    assert d == pytest.approx(0.1 * 0.5)                  # half the step turning, half driving
    assert r2.trace.poses[1, 0, 2] == pytest.approx(math.pi / 8)


@pytest.mark.parametrize("cmd", [None, Command(forward=-0.1), Command(turn=float("nan")),
                                 Command(forward="far")],
                         ids=["not-a-command", "negative-forward", "nan-turn", "string-forward"])
def test_malformed_command_raises_protocol_error(cmd):
    init = InitialConfiguration([0], [[0, 0, 0]])
    with pytest.raises(ProtocolError, match="robot 0"):
        simulate(Scripted(lambda rid, obs, rng: cmd), None, init, P, seed=0, max_steps=1)


def _too_fast(params, n, ids):
    return None if params.v * params.dt < params.range else f"v*dt={params.v * params.dt!r} >= range"


BAD = [
    ("duplicate-ids", InitialConfiguration([1, 1], [[0, 0, 0], [0.5, 0, 0]]), P, "unique_ids"),
    ("disconnected", InitialConfiguration([1, 2], [[0, 0, 0], [5, 0, 0]]), P, "connected_start"),
    ("v-dt-too-big", InitialConfiguration([1, 2], [[0, 0, 0], [0.5, 0, 0]]),
     Params(range=1.0, v=2.0), "v_dt_below_range"),
]


@pytest.mark.parametrize("init,params,name", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_broken_assumptions_refused_or_recorded(init, params, name):
    algo = Scripted(lambda rid, obs, rng: Command(),
                    assumptions=(Assumption("v_dt_below_range", "v*dt < phi", "001 Lemma 7", _too_fast),
                                 connected_start()))
    with pytest.raises(AssumptionError, match=f"assumption '{name}' broken"):
        simulate(algo, None, init, params, seed=0, max_steps=1)
    r = simulate(algo, None, init, params, seed=0, max_steps=1, allow_violations=True)
    assert name in r.broken_assumptions
    assert r.trace.meta["broken_assumptions"] == list(r.broken_assumptions)


BAD_ARGS = [
    ("negative-seed", dict(seed=-1), "seed=-1"),
    ("float-seed", dict(seed=1.5), "seed=1.5"),
    ("bad-params", dict(params=Params(range=0.0)), "params.range=0.0"),
    ("negative-cap", dict(max_steps=-3), "max_steps=-3"),
    ("bad-static", dict(stop_when_static=0), "stop_when_static=0"),
]


@pytest.mark.parametrize("kw,match", [b[1:] for b in BAD_ARGS], ids=[b[0] for b in BAD_ARGS])
def test_bad_arguments(kw, match):
    args = dict(seed=0, params=P)
    args.update(kw)
    params = args.pop("params")
    with pytest.raises(UsageError, match=match):
        simulate(Scripted(lambda rid, obs, rng: Command()), None,
                 InitialConfiguration([0], [[0, 0, 0]]), params, **args)


def test_stops_static_after_window_and_on_finished():
    init = InitialConfiguration([0, 1], [[0, 0, 0], [0.5, 0, 0]])

    class Still(Scripted):
        def controller(self, robot_id, params, lattice, rng):
            class C:
                def step(self, obs):
                    return Command()

                def state(self):
                    return "idle"
            return C()

    r = simulate(Still(None), None, init, P, seed=0, max_steps=1000)
    assert r.status == "static" and r.steps == default_static_window(2) and r.static
    r = simulate(Still(None), None, init, P, seed=0, max_steps=1000, stop_when_static=3)
    assert r.steps == 3
    r = simulate(Still(None), None, init, P, seed=0, max_steps=5, stop_when_static=False)
    assert r.status == "step_cap" and r.steps == 5 and not r.static
    r = simulate(GatherToLowestId(), None, init, P, seed=0)
    assert r.status == "finished"


def test_global_sensing_gets_own_pose_read_only():
    init = InitialConfiguration([0], [[1.0, 2.0, 0.5]])
    algo = Scripted(lambda rid, obs, rng: Command(), model=RobotModel(sensing="global"))
    simulate(algo, None, init, P, seed=0, max_steps=1)
    own = algo.seen[0][0].own_pose
    assert own.tolist() == [1.0, 2.0, 0.5] and not own.flags.writeable


def test_anonymous_sensing_sees_everyone_without_ids():
    init = InitialConfiguration([0, 1, 2], [[0, 0, 0], [5, 0, 0], [0, 9, 0]])
    algo = Scripted(lambda rid, obs, rng: Command(), model=RobotModel(sensing="anonymous",
                                                                       communication="none"))
    simulate(algo, None, init, P, seed=0, max_steps=1)
    obs = algo.seen[None][0]
    assert obs.neighbor_ids is None and obs.robot_id is None
    assert obs.neighbor_poses[:, :2].tolist() == [[0.0, 9.0], [5.0, 0.0]]


def test_fault_hooks_schedule_crash_add_drop_noise():
    init = InitialConfiguration([0, 1, 2], [[0, 0, 0], [0.5, 0, 0], [0.9, 0, 0]])
    algo = Scripted(lambda rid, obs, rng: Command(message=("m", rid)))
    faults = FaultModel(schedule=lambda step, ids, rng: ids != 1,
                        crashes={2: [2]}, additions={1: [(7, [0.0, 0.5, 0.0])]},
                        drop_message=lambda step, s, r, rng: s == 0 and r == 7,
                        noise_std=(0.01, 0.0))
    r = simulate(algo, None, init, P, seed=0, max_steps=4, faults=faults, stop_when_static=False)
    assert 1 not in algo.seen                              # never scheduled
    assert len(algo.seen[2]) == 2                          # crashed at the start of step 2
    assert len(algo.seen[7]) == 3                          # joined at step 1
    assert all(0 not in o.messages for o in algo.seen[7])  # every delivery 0 -> 7 dropped
    assert algo.seen[0][1].messages == {2: ("m", 2)}      # 1 never acts, so never broadcasts
    assert algo.seen[0][2].messages == {7: ("m", 7)}      # 2 crashed: not heard any more
    assert r.trace.present[-1].tolist() == [True, True, False, True]
    kinds = {e.kind for e in r.trace.events}
    assert {"crash", "add", "drop"} <= kinds
    assert set(r.broken_assumptions) == {"synchronous_clocks", "no_crashes", "fixed_robot_set",
                                         "reliable_messages", "exact_sensing"}
    # noise: robot 0 sees robot 2 not exactly at (0.9, 0)
    assert algo.seen[0][0].neighbor_poses[1, 0] != 0.9
    again = simulate(algo, None, init, P, seed=0, max_steps=4, faults=faults, stop_when_static=False)
    assert again.trace.to_json() == r.trace.to_json()


def test_data_driven_faults_replay_identically_from_their_json():
    from swarmproof.reference_impl.engine import DropSet, TableSchedule

    init = random_connected(6, 2, range=1.0, min_separation=0.3)
    faults = FaultModel(schedule=TableSchedule({1: (0, 1, 2), 3: ()}),
                        drop_message=DropSet({(2, 0, 1), (2, 1, 0)}), crashes={4: [5]},
                        noise_std=(0.005, 0.001))
    a = simulate(Scripted(random_walk), None, init, P, seed=9, max_steps=8, faults=faults,
                 record_messages=True)
    rebuilt = FaultModel.from_dict(a.trace.meta["faults"])
    b = simulate(Scripted(random_walk), None, init, P, seed=9, max_steps=8, faults=rebuilt,
                 record_messages=True)
    assert a.trace.to_json() == b.trace.to_json()
    # step 3: nobody acts, so nobody moves
    assert np.array_equal(a.trace.poses[4], a.trace.poses[3])


def test_callable_faults_are_not_rebuildable():
    f = FaultModel(schedule=lambda step, ids, rng: ids >= 0)
    with pytest.raises(UsageError, match="cannot be rebuilt from data"):
        FaultModel.from_dict(f.describe())


def test_unhashable_state_is_a_protocol_error():
    class Bad(Scripted):
        def controller(self, robot_id, params, lattice, rng):
            class C:
                def step(self, obs):
                    return Command()

                def state(self):
                    return {"parent": None}
            return C()

    with pytest.raises(ProtocolError, match="unhashable dict"):
        simulate(Bad(None), None, InitialConfiguration([0], [[0, 0, 0]]), P, seed=0, max_steps=1)


def test_progress_is_reported_and_messages_recorded():
    calls = []
    init = InitialConfiguration([0, 1], [[0, 0, 0], [0.5, 0, 0]])
    r = simulate(Scripted(lambda rid, obs, rng: Command(message=("m", rid))), None, init, P, seed=0,
                 max_steps=120, stop_when_static=False, record_messages=True,
                 progress=lambda step, cap: calls.append((step, cap)))
    assert calls == [(50, 120), (100, 120), (120, 120)]
    assert r.trace.messages[0] == {0: ("m", 0), 1: ("m", 1)} and len(r.trace.messages) == 120


class Repeating:
    """Controllers that log whether the engine called ``step`` or ``repeat_step``.

    Robot 0 drives in steps 0 and 4, robot 1 changes its broadcast in step 2 (their
    ``repeat_step`` declines then); every other decision repeats the last command.
    """

    name = "repeating"
    model = RobotModel()
    assumptions = ()

    def __init__(self, with_repeat=True):
        self.calls = []
        self.seen = {}
        self.with_repeat = with_repeat

    def controller(self, rid, params, lattice, rng):
        calls, seen = self.calls, self.seen

        class C:
            msg = ("m", rid)
            last = None

            def step(self, obs):
                calls.append((obs.step, rid, "step"))
                seen[(obs.step, rid)] = obs
                if rid == 1 and obs.step == 2:
                    self.msg = ("changed", rid)
                drive = (rid, obs.step) in ((0, 0), (0, 4))
                self.last = Command(message=self.msg, forward=0.05 if drive else 0.0)
                return self.last

            def state(self):
                return (("msg", self.msg),)

        class R(C):
            def repeat_step(self, t):
                calls.append((t, rid, "repeat"))
                return None if (rid, t) in ((1, 2), (0, 4)) else self.last

        return R() if self.with_repeat else C()

    def finished(self, states):
        return False


def test_repeat_step_only_when_the_whole_observation_is_unchanged():
    """Sensing reused when nothing moved, and repeat_step called instead of step exactly
    for the robots whose neighbor IDs, pose bits and message objects are last step's."""
    init = InitialConfiguration([0, 1, 2, 3], [[0, 0, 0], [0.6, 0, 0], [1.2, 0, 0], [5, 0, 0]])
    alg = Repeating()
    kw = dict(max_steps=6, stop_when_static=False, record_messages=True)
    r = simulate(alg, None, init, P, seed=0, **kw)
    by_step = {}
    for t, rid, how in alg.calls:
        by_step.setdefault(t, []).append(f"{rid}{how[0]}")
    assert by_step == {
        0: ["0s", "1s", "2s", "3s"],              # no previous observation
        1: ["0s", "1s", "2s", "3r"],              # 0 moved (0, 1 resense); first messages heard
        2: ["0r", "1r", "1s", "2r", "3r"],        # nothing moved or changed; 1 declines
        3: ["0s", "1r", "2s", "3r"],              # 1's new message reaches 0 and 2
        4: ["0r", "0s", "1r", "2r", "3r"],        # 0 declines and drives
        5: ["0s", "1s", "2r", "3r"],              # 0 moved, no message changed
    }
    # step 3 reused step 1's sensing (nobody moved in steps 1 and 2): still exact
    obs = alg.seen[(3, 0)]
    assert obs.neighbor_ids == (1,)
    expect = relative_many(r.trace.poses[3][0], r.trace.poses[3][1:2])
    assert np.abs(obs.neighbor_poses - expect).max() < 1e-12
    assert abs(obs.neighbor_poses[0, 0] - 0.55) < 1e-12   # after robot 0 drove 0.05
    plain = Repeating(with_repeat=False)
    q = simulate(plain, None, init, P, seed=0, **kw)
    assert q.trace.to_json() == r.trace.to_json()
    assert {how for _, _, how in plain.calls} == {"step"}


def test_repeat_step_is_not_used_under_a_fault_model():
    init = InitialConfiguration([0, 1], [[0, 0, 0], [0.6, 0, 0]])
    alg = Repeating()
    simulate(alg, None, init, P, seed=0, max_steps=4, stop_when_static=False,
             faults=FaultModel(schedule=TableSchedule({})))
    assert [how for _, _, how in alg.calls] == ["step"] * 8


def test_stop_when_monitor_ends_the_run_with_status_stopped():
    init = InitialConfiguration([0, 1], [[0, 0, 0], [0.5, 0, 0]])
    seen = []

    def at_step_4(t, poses, states, present):
        seen.append((t, poses.shape, len(states), int(present.sum())))
        return t == 4

    r = simulate(Scripted(lambda rid, obs, rng: Command(forward=0.01)), None, init, P, seed=0,
                 max_steps=50, stop_when_static=False, stop_when=at_step_4)
    assert r.status == "stopped" and r.steps == 4 and len(r.trace.poses) == 5
    assert [s[0] for s in seen] == [0, 1, 2, 3, 4]   # the start, then after every step
    assert seen[0][1:] == ((2, 3), 2, 2)
    full = simulate(Scripted(lambda rid, obs, rng: Command(forward=0.01)), None, init, P, seed=0,
                    max_steps=50, stop_when_static=False)
    assert full.status == "step_cap" and np.array_equal(full.trace.poses[:5], r.trace.poses)
