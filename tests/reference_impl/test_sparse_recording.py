"""Sparse recording and streaming monitors (issue 12; DESIGN.md section 5 "Monitors see every
step"): a sparse trace keeps every k-th step, every event and the last; properties still see
every step through monitors the engine feeds, so a violation at an unrecorded step is found."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarmproof.invariants.connectivity import ConnectivityMonitor, TreeLinkMonitor, connected_throughout
from swarmproof.invariants.properties import CollisionMonitor
from swarmproof.invariants.registry import PropertyContext, get_property
from swarmproof.models.errors import UsageError
from swarmproof.models.trace import InitialConfiguration, Trace
from swarmproof.reference_impl.engine import FaultModel, simulate
from swarmproof.reference_impl.protocol import Command, Params, RobotModel

P = Params(range=1.0, v=1.0, omega=math.pi, dt=1.0)
HOLO = RobotModel(motion="holonomic")


def _excursion(rid, k, obs, rng):
    """Robot 1 steps 0.6 away from robot 0 in step 7 and back in step 8; nothing else moves."""
    if rid != 1 or obs.step not in (7, 8):
        return Command()
    return Command(turn=0.0 if obs.step == 7 else math.pi, forward=0.6)


def _run(recorder, record_every, observers=(), steps=20, faults=None):
    init = InitialConfiguration([0, 1], [[0, 0, 0], [0.5, 0, 0]])
    algo = recorder(HOLO, _excursion)
    return simulate(algo, None, init, P, seed=0, max_steps=steps, stop_when_static=False,
                    record_every=record_every, observers=observers, faults=faults)


def test_a_sparse_trace_keeps_every_kth_step_the_events_and_the_last(recorder):
    faults = FaultModel(crashes={12: []}, additions={13: [(9, [0.0, 0.9, 0.0])]})
    r = _run(recorder, 5, steps=21, faults=faults)
    assert r.trace.times == [0, 5, 10, 14, 15, 20, 21]     # 14: the addition at step 13 is recorded after it
    assert len(r.trace.poses) == len(r.trace.states) == 7 and r.trace.sparse
    assert r.trace.meta["record_every"] == 5 and r.steps == 21
    dense = _run(recorder, 1, steps=21, faults=faults)
    assert dense.trace.times is None and not dense.trace.sparse
    for i, t in enumerate(r.trace.times):
        assert r.trace.poses[i].tobytes() == dense.trace.poses[t].tobytes()
        assert r.trace.states[i] == dense.trace.states[t]
    back = Trace.from_json(r.trace.to_json())
    assert back.times == r.trace.times


def test_a_violation_at_an_unrecorded_step_is_found_by_the_streaming_monitor(recorder):
    mons = (ConnectivityMonitor(1.0), CollisionMonitor(0.3))
    r = _run(recorder, 5, observers=mons)
    assert 8 not in r.trace.times
    # the sparse trace alone looks connected: the split after step 7 is not recorded
    assert connected_throughout(r.trace, 1.0).held
    seen = r.observed("connectivity")
    assert seen.violated and seen.witness == {"step": 8, "components": [[0], [1]]}
    # the same run recorded densely: the same verdict, from the trace
    dense = connected_throughout(_run(recorder, 1).trace, 1.0)
    assert (dense.status, dense.witness) == (seen.status, seen.witness)
    # robots of radius 0.3 overlap all along (0.5 apart): found at the first step
    assert r.observed("collision").violated and r.observed("collision").witness["step"] == 0


def test_the_registry_judges_a_sparse_trace_by_its_monitor_or_says_inconclusive(recorder):
    r = _run(recorder, 5, observers=(ConnectivityMonitor(1.0),))
    ctx = PropertyContext(None, None, P, r, {})
    assert get_property("connectivity").judge(r.trace, ctx).violated
    premises = get_property("premises").judge(r.trace, ctx)
    assert premises.status == "inconclusive" and "the trace is sparse (record_every=5)" in premises.message
    assert get_property("collision").judge(r.trace, ctx).status == "inconclusive"


def test_streaming_and_trace_judgments_agree_on_a_real_run():
    from swarmproof.invariants.connectivity import tree_links_survive
    from swarmproof.models.library import load
    from swarmproof.reference_impl.initial import random_connected
    from swarmproof.reference_impl.song2014.algorithm import Song2014

    start = random_connected(10, 2, range=1.2)
    p = Params(range=1.2, v=0.05)
    mons = (ConnectivityMonitor(1.2), TreeLinkMonitor(1.2))
    sparse = simulate(Song2014(), load("square"), start, p, seed=2, record_every=25, observers=mons)
    dense = simulate(Song2014(), load("square"), start, p, seed=2)
    for name, fn in (("connectivity", lambda t: connected_throughout(t, 1.2)),
                     ("tree_links", lambda t: tree_links_survive(t, 1.2))):
        a, b = sparse.observed(name), fn(dense.trace)
        assert (a.status, a.witness) == (b.status, b.witness), name
    assert sparse.trace.poses[-1].tobytes() == dense.trace.poses[-1].tobytes()


def test_simulate_command_line_record_every(cli):
    import json

    code, out, _ = cli("simulate", "song2016", "--lattice", "square", "--robots", "10", "--seed", "0",
                       "--record-every", "50", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["record_every"] == 50 and doc["recorded_steps"] < doc["steps"] / 10
    assert doc["connectivity"]["message"] == f"connected at all {doc['steps'] + 1} steps"
    code, _, err = cli("simulate", "song2016", "--lattice", "square", "--robots", "3", "--seed", "0",
                       "--record-every", "0")
    assert code == 2 and "--record-every 0 must be >= 1" in err


@pytest.mark.parametrize("kwargs, match", [
    (dict(record_every=0), r"record_every=0 must be an integer >= 1"),
    (dict(observers=[object()]), r"has no start\(ids\) and observe"),
])
def test_bad_recording_arguments_are_named(recorder, kwargs, match):
    init = InitialConfiguration([0], [[0, 0, 0]])
    with pytest.raises(UsageError, match=match):
        simulate(recorder(HOLO, _excursion), None, init, P, seed=0, max_steps=1, **kwargs)


def test_premise_monitors_stream_every_step_and_find_a_failure_a_sparse_trace_skips():
    """000 Lemma 7's premise fails for song2014 at step 2 of this start (test_premises.py);
    recorded every 5 steps, only the streaming monitor sees it -- at the same step."""
    from swarmproof.invariants.premises import PremisesMonitor, check_premises
    from swarmproof.invariants.properties import premises
    from swarmproof.models.library import load
    from swarmproof.reference_impl.initial import random_connected
    from swarmproof.reference_impl.song2014.algorithm import Song2014

    start = random_connected(10, 2, range=1.2)
    p = Params(range=1.2, v=0.05)
    names = Song2014.premise_monitors
    dense = simulate(Song2014(), load("square"), start, p, seed=2)
    want = premises(dense.trace, names, 1.2, 0.05, 1.0)
    mon = PremisesMonitor(names, 1.2, 0.05, 1.0)
    sparse = simulate(Song2014(), load("square"), start, p, seed=2, record_every=5, observers=(mon,))
    got = sparse.observed("premises")
    assert want.violated and (got.status, got.witness) == (want.status, want.witness)
    assert got.witness["step"] not in sparse.trace.times
    ctx = PropertyContext(Song2014(), load("square"), p, sparse, {})
    assert get_property("premises").judge(sparse.trace, ctx).witness == want.witness
    # on a run where every premise holds, the streamed verdict is held too
    from swarmproof.reference_impl.song2016.algorithm import Song2016

    s16 = Song2016(n_robots=8)
    start = random_connected(8, 0, range=1.2)
    p16 = Params(range=1.2, v=0.05)
    mon = PremisesMonitor(Song2016.premise_monitors, 1.2, 0.05, 1.0)
    r = simulate(s16, load("hexagon"), start, p16, seed=0, record_every=10, observers=(mon,))
    d = simulate(Song2016(n_robots=8), load("hexagon"), start, p16, seed=0)
    assert r.observed("premises").status == "held" == premises(d.trace, Song2016.premise_monitors, 1.2, 0.05,
                                                                1.0).status
    assert [x.status for x in check_premises(d.trace)] == [x.status for _, x in mon.results()]


def test_deadlock_is_judged_by_its_streaming_monitor_like_the_dense_trace():
    from swarmproof.invariants.properties import DeadlockMonitor, deadlock

    class Quiet:
        """Robot 1 steps away in step 7 and back in step 8; states never change: quiet after."""
        name, model, assumptions = "quiet", HOLO, ()

        def controller(self, rid, params, target, rng):
            class C:
                def step(self, obs):
                    return _excursion(rid, 0, obs, rng)

                def state(self):
                    return ()
            return C()

        def finished(self, states):
            return False

    init = InitialConfiguration([0, 1], [[0, 0, 0], [0.5, 0, 0]])
    dense = simulate(Quiet(), None, init, P, seed=0, max_steps=25, stop_when_static=False)
    for k, goal in ((5, False), (30, False), (5, True), (7, False)):
        mon = DeadlockMonitor()
        simulate(Quiet(), None, init, P, seed=0, max_steps=25, stop_when_static=False, record_every=5,
                 observers=(mon,))
        want = deadlock(dense.trace, k, goal_reached=goal)
        got = mon.result(k, goal)
        assert (got.status, got.witness) == (want.status, want.witness), (k, goal)
    assert mon.result(5).witness == {"step": 0, "window": 5}     # steps 0-6 are quiet already


class _Toggle:
    """Robot 0 steps +0.1 and back, over and over (state toggles): a cycle, and back and forth."""

    name, model, assumptions = "toggle", HOLO, ()

    def __init__(self, randomized=False, measure=None):
        self.randomized = randomized
        if measure is not None:
            self.progress_measure = measure

    def controller(self, rid, params, target, rng):
        class C:
            def __init__(self):
                self.out = False

            def step(self, obs):
                if rid != 0:
                    return Command()
                self.out = not self.out
                return Command(turn=0.0 if self.out else math.pi, forward=0.1)

            def state(self):
                return (("out", self.out),)
        return C()

    def finished(self, states):
        return False


@pytest.mark.parametrize("randomized, measure, window, kind", [
    (False, None, None, "cycle"),
    (True, None, None, "back_and_forth"),
    (True, lambda ids, poses, states: 0.0, 6, "back_and_forth"),
])
def test_oscillation_is_judged_by_its_streaming_monitor_like_the_dense_trace(randomized, measure, window, kind):
    from swarmproof.invariants.properties import OscillationMonitor, oscillation
    from swarmproof.invariants.registry import progress_values

    init = InitialConfiguration([0, 1], [[0, 0, 0], [0.5, 0.3, 0]])
    algo = _Toggle(randomized, measure)
    dense = simulate(algo, None, init, P, seed=0, max_steps=30, stop_when_static=False)
    progress = None if measure is None else progress_values(dense.trace, measure)
    for goal in (False, True):
        want = oscillation(dense.trace, goal_reached=lambda t, g=goal: g and t == 30, randomized=randomized,
                           progress=progress, window=window)
        mon = OscillationMonitor(randomized=randomized, measure=measure, window=window)
        simulate(_Toggle(randomized, measure), None, init, P, seed=0, max_steps=30, stop_when_static=False,
                 record_every=7, observers=(mon,))
        got = mon.result(goal)
        assert (got.status, got.witness, got.message) == (want.status, want.witness, want.message)
    assert got.status == "violated" and got.witness["kind"] == kind


def test_a_stall_is_found_by_the_streamed_progress_measure():
    from swarmproof.invariants.properties import OscillationMonitor, oscillation
    from swarmproof.invariants.registry import progress_values

    class Still(_Toggle):
        def controller(self, rid, params, target, rng):
            class C:
                def step(self, obs):
                    return Command()

                def state(self):
                    return ()
            return C()
    measure = lambda ids, poses, states: 0.0  # noqa: E731
    init = InitialConfiguration([0, 1], [[0, 0, 0], [0.5, 0.3, 0]])
    dense = simulate(Still(True, measure), None, init, P, seed=0, max_steps=12, stop_when_static=False)
    want = oscillation(dense.trace, randomized=True, progress=progress_values(dense.trace, measure), window=5)
    mon = OscillationMonitor(randomized=True, measure=measure, window=5)
    simulate(Still(True, measure), None, init, P, seed=0, max_steps=12, stop_when_static=False, record_every=4,
             observers=(mon,))
    got = mon.result(False)
    assert got.witness == want.witness == {"kind": "no_progress", "step": 5, "since": 0, "window": 5, "best": 0.0}


@pytest.mark.parametrize("algorithm_name, target, seed", [("song2014", "square", 2), ("song2016", "hexagon", 0),
                                                          ("example-gather", "square", 1)])
def test_every_property_judges_a_sparse_run_as_the_dense_one(algorithm_name, target, seed):
    """Sparse recording changes only what is stored (DESIGN.md section 5): each registered
    property with a streaming monitor gives the dense run's status and witness."""
    from swarmproof.checkers.runs import build_params
    from swarmproof.invariants.registry import properties
    from swarmproof.models.library import load
    from swarmproof.reference_impl.initial import random_connected
    from swarmproof.reference_impl.registry import get_algorithm

    lattice = load(target)
    start = random_connected(8, seed, range=lattice.range)
    algo = get_algorithm(algorithm_name, n_robots=8)
    p = build_params(algo, lattice.range, 8)
    streamed = [prop for prop in properties() if prop.stream is not None]
    assert {"connectivity", "tree_links", "collision", "deadlock", "oscillation", "premises"} <= {
        prop.name for prop in streamed}
    observers = tuple(prop.stream(algo, p, {}) for prop in streamed)
    sparse = simulate(algo, lattice, start, p, seed=seed, record_every=37, observers=observers)
    dense = simulate(get_algorithm(algorithm_name, n_robots=8), lattice, start, p, seed=seed)
    assert sparse.trace.sparse and sparse.steps == dense.steps
    for prop in streamed:
        a = prop.judge(sparse.trace, PropertyContext(algo, lattice, p, sparse, {}))
        b = prop.judge(dense.trace, PropertyContext(algo, lattice, p, dense, {}))
        assert (a.status, a.witness) == (b.status, b.witness), prop.name


def test_a_sparse_trace_counts_steps_not_frames(recorder, tmp_path):
    """``Trace.steps`` is the last step run, ``frames`` what was kept (issue 15 review): every
    reader of a sparse trace indexes frames and names steps."""
    from swarmproof.checkers.plotting import animate_trace
    from swarmproof.invariants.connectivity import first_disconnection
    from swarmproof.invariants.properties import collision

    faults = FaultModel(crashes={12: []}, additions={13: [(9, [0.0, 0.9, 0.0])]})
    r = _run(recorder, 5, steps=21, faults=faults)
    dense = _run(recorder, 1, steps=21, faults=faults)
    tr = r.trace
    assert tr.present is not None and tr.times == [0, 5, 10, 14, 15, 20, 21]
    assert (tr.steps, tr.frames, r.steps) == (21, 7, 21) and (dense.trace.steps, dense.trace.frames) == (21, 22)
    assert Trace.from_json(tr.to_json()).steps == 21
    # the last frame's robots (the addition included), not the frame numbered like the last step
    assert tr.final_ids().tolist() == dense.trace.final_ids().tolist() == [0, 1, 9]
    assert r.final_states == dense.final_states
    assert (tr.frame_of(14), tr.frame_of(13), tr.frame_of(22)) == (3, None, None)
    # the whole-trace forms index frames and name engine steps
    assert collision(tr, 0.3).witness["step"] == 0
    apart = Trace(ids=[0, 1], poses=np.array([[[0, 0, 0], [0.5, 0, 0]]] * 2 + [[[0, 0, 0], [2.0, 0, 0]]], float),
                  states=[(None, None)] * 3, times=[0, 5, 9])
    assert first_disconnection(apart, 1.0) == (9, [[0], [1]])
    # an animation of the kept frames, the violation at a step it did not keep left unmarked
    assert animate_trace(tr, str(tmp_path / "run.gif"), phi=1.0, mark_step=8, max_frames=10).endswith("run.gif")
