"""Asynchronous clocks keep what a robot receives while its clock does not tick (issue 15's
engine defect: a robot with clock rate < 1 lost the deliveries of the steps it skipped; 004
Sec. II-A / V-B3 relax clock rates, and message loss is a separate assumption)."""

from __future__ import annotations

import numpy as np
import pytest

from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import FaultModel, simulate
from swarmproof.reference_impl.protocol import Command, Params, RobotModel
from testkit import Recorder

LOCAL = RobotModel(sensing="local", communication="neighbors", motion="holonomic", clocks="async")


@pytest.fixture
def fixed_clocks(monkeypatch):
    """Give the run's robots these clock phases and rates (slot order) instead of drawn ones."""
    from swarmproof.reference_impl.engine import clocks as clocks_mod
    from swarmproof.reference_impl.engine import run as run_mod

    def use(phase, rate, every=1.0):
        def model(m, params, n, seed):
            c = clocks_mod.AsyncClocks(params, n, seed)
            c.phase, c.rate, c.every = np.array(phase, float), np.array(rate, float), float(every)
            return c
        monkeypatch.setattr(run_mod, "clock_model", model)
    return use


def _talker(rid, k, obs, rng):
    return Command(message=("m", rid, obs.step))


def _run(model=LOCAL, *, steps=8, seed=0, faults=None, n=2, extra=None):
    algo = Recorder(model, _talker)
    init = InitialConfiguration(list(range(n)), [[0.5 * i, 0.0, 0.0] for i in range(n)])
    r = simulate(algo, None, init, Params(range=5.0, v=0.1, dt=1.0, extra=extra or {}), seed=seed,
                 max_steps=steps, stop_when_static=False, faults=faults)
    return algo, r


def _inboxes(algo, rid):
    return {obs.step: obs.inbox for who, obs in algo.seen if who == rid}


def test_the_slow_robot_reads_the_message_of_the_step_it_skipped(fixed_clocks):
    """Robot 0 (rate 1) decides and broadcasts every step; robot 1 (rate 0.5, phase 0) decides
    at steps 1, 3, 5, 7.  At step 3 its inbox holds robot 0's message of step 1 (received in
    step 2, when it did not tick) before that of step 2; ``messages`` keeps the latest."""
    fixed_clocks([0.0, 0.0], [1.0, 0.5])
    algo, r = _run()
    slow = {obs.step: obs for who, obs in algo.seen if who == 1}
    assert sorted(slow) == [1, 3, 5, 7]
    assert slow[1].inbox == ((0, ("m", 0, 0)),)
    for t in (3, 5, 7):
        assert slow[t].inbox == ((0, ("m", 0, t - 2)), (0, ("m", 0, t - 1)))
        assert dict(slow[t].messages) == {0: ("m", 0, t - 1)}
    # every broadcast of robot 0 that robot 1 could hear before the end reaches it exactly once
    got = [m for t in sorted(slow) for _, m in slow[t].inbox]
    assert got == [("m", 0, s) for s in range(7)]
    # the fast robot hears the slow one on its broadcast ticks, its last decided message
    fast = _inboxes(algo, 0)
    assert len(fast) == 8 and fast[0] == ()


def test_without_the_backlog_the_skipped_step_was_lost(fixed_clocks, monkeypatch):
    """The test above can fail: with the engine's old behaviour (no backlog) the inbox at step 3
    holds only the message of step 2."""
    from swarmproof.reference_impl.engine.communication import Delivery

    monkeypatch.setattr(Delivery, "hold", lambda self, *a: None)
    fixed_clocks([0.0, 0.0], [1.0, 0.5])
    algo, _ = _run()
    assert _inboxes(algo, 1)[3] == ((0, ("m", 0, 2)),)


def test_a_crashed_senders_received_messages_stay(fixed_clocks):
    """Robot 0 crashes at the start of step 3: robot 1 received its step-1 message in step 2 (a
    radio buffers what it received) and reads it at step 3; nothing of step 2 (robot 0 is gone)."""
    fixed_clocks([0.0, 0.0], [1.0, 0.5])
    algo, r = _run(faults=FaultModel(crashes={3: [0]}))
    slow = {obs.step: obs for who, obs in algo.seen if who == 1}
    assert slow[3].inbox == ((0, ("m", 0, 1)),) and dict(slow[3].messages) == {0: ("m", 0, 1)}
    assert slow[5].inbox == ()


def test_a_crashed_receiver_loses_its_backlog():
    """What a robot received but never read goes with it when it crashes (Delivery.forget)."""
    from swarmproof.reference_impl.engine.choices import Choices
    from swarmproof.reference_impl.engine.communication import Delivery

    d = Delivery(LOCAL, 5.0, [0, 1], Choices(FaultModel(), np.random.default_rng(0)))
    d.begin([("m", 0), None], [0, 1], True)
    d.hold(2, 1, 1, (0,), [0], np.zeros((1, 3)))
    assert d.backlog == {1: [(0, ("m", 0))]}
    d.forget(1)
    assert d.backlog == {}


def test_backlog_with_anonymous_robots_and_talking_to_all(fixed_clocks):
    """The backlog keeps sender slots, so anonymous robots get it without IDs and
    ``communication="all"`` gets it from every robot."""
    fixed_clocks([0.0, 0.0, 0.0], [1.0, 1.0, 0.5])
    anon = RobotModel(sensing="anonymous", communication="neighbors", motion="holonomic", clocks="async")
    algo = Recorder(anon, lambda rid, k, obs, rng: Command(message=("m", k)))
    init = InitialConfiguration([0, 1, 2], [[0, 0, 0], [0.5, 0, 0], [1.0, 0, 0]])
    simulate(algo, None, init, Params(range=5.0, v=0.1, dt=1.0), seed=0, max_steps=4, stop_when_static=False)
    third = [obs for who, obs in algo.seen][-1]            # the slow robot at step 3
    assert third.step == 3 and third.robot_id is None
    assert third.inbox == ((None, ("m", 1)), (None, ("m", 1)), (None, ("m", 2)), (None, ("m", 2)))
    assert sorted(third.messages.values()) == [("m", 2), ("m", 2)]
    fixed_clocks([0.0, 0.0, 0.0], [1.0, 1.0, 0.5])
    algo, _ = _run(RobotModel(sensing="local", communication="all", motion="holonomic", clocks="async"), n=3)
    assert _inboxes(algo, 2)[3] == ((0, ("m", 0, 1)), (1, ("m", 1, 1)), (0, ("m", 0, 2)), (1, ("m", 1, 2)))


def test_slow_clocks_with_message_faults_replay_bit_identically():
    """Determinism: drawn clocks below 1 with loss, delay, duplication and reordering give the
    same observations (inboxes included) and trace twice, and another seed something else."""
    faults = dict(message_delay=2, message_duplication=0.3, message_reorder=True, message_loss=0.2)
    kw = dict(steps=30, n=4, extra={"clock_rate_min": 0.3, "clock_rate_max": 1.0})
    a1, r1 = _run(faults=FaultModel(**faults), seed=5, **kw)
    a2, r2 = _run(faults=FaultModel.from_dict(r1.trace.meta["faults"]), seed=5, **kw)
    seen1 = [(w, o.step, o.clock, o.inbox) for w, o in a1.seen]
    assert seen1 == [(w, o.step, o.clock, o.inbox) for w, o in a2.seen]
    assert r1.trace.events == r2.trace.events and r1.trace.meta == r2.trace.meta
    # some inbox holds two messages of one sender: the backlog at work
    assert any(len({s for s, _ in box}) < len(box) for _, _, _, box in seen1)
    a3, _ = _run(faults=FaultModel(**faults), seed=6, **kw)
    assert seen1 != [(w, o.step, o.clock, o.inbox) for w, o in a3.seen]
