"""The engine's point-to-point exchanges (``Controller.requests``, issue 30): a request and its
answer within the step, between every robot's ``requests`` and every robot's ``step``; the fault
model's loss and delay on each direction, recorded exchanges, and the refusals (docs/engine.md,
"Point-to-point exchanges")."""

from __future__ import annotations

import pytest

from swarmproof.models.errors import ProtocolError
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import FaultModel, simulate
from swarmproof.reference_impl.protocol import Command, Params, RobotModel


class _PingCtl:
    """Asks every neighbour it senses in steps 0..2; answers ``("pong", its id, the asker's step)``."""

    def __init__(self, rid, answers=True) -> None:
        self.id, self.answers = rid, answers
        self.got: list = []
        self.asked: list = []

    def requests(self, obs):
        ids = obs.neighbor_ids if obs.neighbor_ids is not None else range(len(obs.neighbor_poses))
        return tuple((int(n), (self.id, obs.step)) for n in ids) if obs.step < 3 else ()

    def step(self, obs):
        # the second phase: every answer of this step is in already (the broadcast says how many)
        return Command(message=len(self.got))

    def answer(self, sender, payload, clock):
        self.asked.append((int(sender), tuple(payload), float(clock)))
        return ("pong", self.id, payload[1]) if self.answers else None

    def on_reply(self, peer, payload, reply, clock):
        self.got.append((int(peer), tuple(payload), tuple(reply), float(clock)))

    def state(self):
        return (("got", tuple(self.got)), ("asked", tuple(self.asked)))


class _Ping:
    name = "ping"
    reading = "1"
    assumptions = ()

    def __init__(self, sensing="local", answers=True) -> None:
        self.model = RobotModel(sensing=sensing, communication="neighbors", motion="holonomic", clocks="sync")
        self.answers = answers

    def controller(self, robot_id, params, lattice, rng):
        return _PingCtl(robot_id, self.answers)

    def finished(self, states) -> bool:
        return False


def _run(alg=None, *, faults=None, seed=0, record_messages=False, poses=((0, 0, 0), (0.5, 0, 0), (3.0, 0, 0))):
    init = InitialConfiguration(list(range(len(poses))), [list(p) for p in poses])
    return simulate(alg or _Ping(), None, init, Params(range=1.0), seed=seed, max_steps=8, stop_when_static=False,
                    faults=faults, allow_violations=True, record_messages=record_messages)


def _state(r, step, rid):
    return dict(r.trace.states[step][list(r.trace.ids).index(rid)])


def test_a_request_is_answered_and_the_answer_read_within_the_step_it_was_sent():
    r = _run(record_messages=True)
    # the answer is read before the asker's step: its broadcast of step 0 counts it
    assert r.trace.messages[0] == {0: 1, 1: 1, 2: 0}
    # after step 0 (frame 1): robots 0 and 1 asked each other in step 0 and both have the answer
    assert _state(r, 1, 0)["got"] == ((1, (0, 0), ("pong", 1, 0), 0.0),)
    assert _state(r, 1, 1)["asked"] == ((0, (0, 0), 0.0),)
    assert _state(r, 1, 1)["got"] == ((0, (1, 0), ("pong", 0, 0), 0.0),)
    # robot 2 is out of range (3 m): it neither asks nor is asked; three rounds, then nothing
    assert _state(r, 8, 2) == {"got": (), "asked": ()}
    assert [g[1][1] for g in _state(r, 8, 0)["got"]] == [0, 1, 2]
    assert not any(e.kind in ("drop", "late_delivery") for e in r.trace.events)


def test_recorded_messages_show_every_exchange_and_a_request_to_a_robot_out_of_range_is_lost():
    class Far(_PingCtl):
        def requests(self, obs):
            return ((2, (self.id, obs.step)),) if obs.step == 0 and self.id == 0 else ()

    alg = _Ping()
    alg.controller = lambda rid, p, lat, rng: Far(rid)
    r = _run(alg, record_messages=True)
    assert [(e.step, e.kind, e.detail) for e in r.trace.events] == [(0, "drop", (("exchanges", ((0, 2),)),))]
    r = _run(record_messages=True)
    ex = [e for e in r.trace.events if e.kind == "exchange"]
    first = [(e.robots, dict(e.detail)["kind"]) for e in ex if e.step == 0]
    assert first == [((0, 1), "request"), ((1, 0), "request"), ((1, 0), "reply"), ((0, 1), "reply")]  # (from, to)
    assert dict(ex[2].detail)["reply"] == ("pong", 1, 0)


def test_no_answer_means_no_reply_and_loss_applies_to_each_direction():
    r = _run(_Ping(answers=False))
    assert _state(r, 8, 1)["asked"] and _state(r, 8, 0)["got"] == ()
    r = _run(faults=FaultModel(message_loss=1.0))
    assert _state(r, 8, 0) == {"got": (), "asked": ()}
    drops = [e for e in r.trace.events if e.kind == "drop"]
    assert drops and all(dict(e.detail).get("exchanges") for e in drops if "exchanges" in dict(e.detail))
    assert sum(len(dict(e.detail).get("exchanges", ())) for e in drops) == 6      # 2 robots x 3 steps


def test_a_delayed_answer_arrives_in_a_later_step_and_the_run_replays_bit_for_bit():
    f = FaultModel(message_delay=3)
    a, b = _run(faults=f, seed=4), _run(faults=f, seed=4)
    assert a.trace.states == b.trace.states and a.trace.events == b.trace.events
    got = _state(a, 8, 0)["got"]
    assert got and any(clock > payload[1] for _, payload, _, clock in got)        # read after its step
    assert any(e.kind == "late_delivery" and "exchanges" in dict(e.detail) for e in a.trace.events)


def test_a_crashed_robot_loses_what_was_due_to_it():
    """Robot 1 crashes at the start of step 1; what was due to it later is lost, and robot 0 reads
    no answer of its after the crash."""
    lost = 0
    for seed in range(6):
        r = _run(faults=FaultModel(message_delay=3, crashes={1: [1]}), seed=seed)
        assert r.trace.states[8][1] is None
        got = _state(r, 8, 0)["got"]
        assert all(clock == 0.0 for _, _, _, clock in got)      # only an answer that came at once
        lost += not got
    assert lost > 0                                              # some seed delayed robot 0's request past the crash


def test_robots_without_ids_cannot_address_an_exchange():
    with pytest.raises(ProtocolError, match="without an ID"):
        _run(_Ping(sensing="anonymous"))


def test_malformed_requests_are_a_protocol_error():
    class Bad(_PingCtl):
        def requests(self, obs):
            return (7,)

    alg = _Ping()
    alg.controller = lambda rid, p, lat, rng: Bad(rid)
    with pytest.raises(ProtocolError, match=r"requests\(\)=\(7,\)"):
        _run(alg)


def test_a_controller_that_asks_but_cannot_answer_is_a_protocol_error():
    class Mute(_PingCtl):
        answer = None

    alg = _Ping()
    alg.controller = lambda rid, p, lat, rng: Mute(rid)
    with pytest.raises(ProtocolError, match=r"robot 1 received a request in step 0 but its controller has no answer"):
        _run(alg)


def test_what_was_due_to_a_crashed_robot_is_a_drop_event():
    for seed in range(6):
        r = _run(faults=FaultModel(message_delay=3, crashes={1: [1]}), seed=seed)
        drops = [d for e in r.trace.events if e.kind == "drop" for d in dict(e.detail).get("exchanges", ())]
        if drops:
            assert all(1 in d for d in drops)           # to or from the crashed robot 1
            return
    raise AssertionError("no seed delayed an exchange past robot 1's crash")
