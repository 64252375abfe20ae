"""The phases of one engine step, each a function of the run's state (:class:`RunState`).

:func:`~swarmproof.reference_impl.engine.run.simulate` sets a run up and then, step after
step, calls::

    apply_faults(run, step)   # 1. robots crash or join
    activate(run, step)       # 1. which robots act: the schedule, the clocks
    sense(run, step)          # 2. what every present robot senses (vectorised)
    decide(run, step)         # 3.-4. message delivery, exchanges, every acting robot's decision
    move(run, step)           # 5. motion (vectorised), then the step count advances
    record(run, step)         # 6. the trace, the monitors, quiet steps
    stop_test(run, step)      # finished, static, or stopped by a monitor

``run`` (:class:`RunState`) holds what lives from step to step: the robots' poses and
presence, their controllers and states, last step's broadcasts, the models, the recording
and the caches of the shortcuts.  ``step`` (:class:`StepView`) holds what one step's phases
pass each other: the present robots, who acts, what each senses, the new broadcasts.  The
engine module docstring (:mod:`.run`) states the model each phase implements.

``run.calling`` names whose code runs now: a robot slot while its controller runs, -1 while
the algorithm's own ``finished`` runs, None while the engine's code runs; an exception raised
while it is not None is the algorithm's (a crash of the run, not of the engine).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from swarmproof.models.errors import ProtocolError
from swarmproof.models.se2 import wrap_angle
from swarmproof.models.trace import Event

from .common import PROGRESS_EVERY, _ro, _robot_rng
from .motion import _command_values
from .sensing import _new_observation
from .sensing import sense as _sense

__all__ = ["RunState", "StepView", "apply_faults", "activate", "sense", "decide", "exchange", "move", "record",
           "stop_test"]


@dataclass(slots=True, eq=False)
class RunState:
    """What a run keeps from step to step (the engine's loop mutates it; one per run).

    Attributes
    ----------
    algorithm, lattice, params, seed, faults
        The run's inputs (``faults``: never None).
    ids, ids_list : numpy.ndarray, list
        Robot ID per slot: the start's robots, then the fault model's additions.
    poses : numpy.ndarray, shape (slots, 3)
        Global poses (only the engine knows them), changed in place.
    present : numpy.ndarray of bool
        Which slots hold a robot now (crashed and not yet added: False).
    mover, clocks, delivery, fault_rng
        The motion, clock and delivery models, and the fault model's generator.
    controllers, states : list, tuple
        Per slot: the controller (None when absent) and its last ``state()``.
    last_msgs : list
        Per slot, last step's broadcast (None: silent or absent).
    t, status, calling
        Steps run; None while running, else the status; whose code runs (module docstring).
    """

    # -- the run's inputs and models (set up once) --
    algorithm: Any
    lattice: Any
    params: Any
    seed: int
    faults: Any
    events: list
    broken: list
    ids: np.ndarray
    ids_list: list
    n0: int
    poses: np.ndarray
    present: np.ndarray
    slot_of_add: dict
    any_presence_change: bool
    mover: Any
    clocks: Any
    fault_rng: np.random.Generator
    choices: Any                        # the run's decisions (choices.Choices): drawn, or a chooser's
    progress: Callable | None
    stop_when: Callable | None
    record_clamps: bool
    max_steps: Any          # the caller's value until the run's caps are set (run.run_caps)
    record_every: Any       # likewise, until checked
    observers: Any          # likewise, until checked (then a tuple)
    n_total: int = 0
    anonymous: bool = False
    hide_ids: bool = False  # anonymous robots without their own ID: controllers get None
    global_sensing: bool = False
    inclusive: bool = False
    noisy: bool = False
    grid: bool = False
    async_clocks: bool = False
    phi: float = 0.0
    # -- set when the run starts (run._start) --
    window: int | None = None
    rec: Any = None
    delivery: Any = None
    exchanges: Any = None               # point-to-point exchanges (communication.Exchanges)
    record_exchanges: bool = False      # messages recorded: every exchange is an event
    two_phase: bool = False             # some controller offers requests(obs): two-phase steps
    controllers: list = field(default_factory=list)
    robot_rngs: list = field(default_factory=list)  # per slot, the generator its controller got
    states: tuple | None = None
    # -- the loop's state --
    t: int = 0
    status: str | None = None
    calling: int | None = None
    crash: dict | None = None
    quiet: int = 0                      # consecutive quiet steps
    last_msgs: list = field(default_factory=list)
    heard_msgs: list = field(default_factory=list)   # the broadcasts robots heard last step
    idx_l_prev: list = field(default_factory=list)   # last step's present slots
    outbox: list | None = None          # async clocks: each robot's last decided message
    last_outbox: list | None = None
    sensed: tuple | None = None         # (slots, pose bytes, sensing): reused while nobody moved
    # -- the plain model's shortcuts (repeat_step / repeat_horizon) --
    repeat_ok: bool = False
    repeaters: list = field(default_factory=list)
    horizons: list = field(default_factory=list)
    last_keys: list | None = None       # what each robot sensed last time sensing ran
    resensed: list | None = None        # which robots sense something new since last step
    hold: list = field(default_factory=list)       # per robot: the step its last command holds until
    last_cmds: list = field(default_factory=list)
    turns: list = field(default_factory=list)      # per present robot, this step's (turn, forward)
    fwds: list = field(default_factory=list)


class StepView:
    """What the phases of step ``t`` pass each other (one per step).

    ``idx``: the present slots (``idx_l`` as a list), ``pres_ids`` their IDs; ``act_l`` who
    decides; ``nb_ids``, ``nb_slots``, ``nb_rel``: per present robot, what it senses;
    ``new_msgs``: per slot, this step's broadcasts; ``stepped``: the slots whose controller
    stepped (None: every slot may have changed state); ``same_poses``: nobody moved.

    A plain class, made every step with two fields: the others read as the class-level defaults
    below until a phase sets them.
    """

    idx = pres_ids = idx_l = pres_ids_l = act_l = None
    m = 0
    ticked_l = bcast = tau0 = None      # async clocks: whose clock ticks, who broadcasts, clocks at t
    nb_ids = nb_slots = nb_rel = None
    new_msgs = stepped = None
    moves = None                        # grid motion: each robot's move
    same_poses = changed = False        # nobody moved; some controller's state changed

    def __init__(self, t: int, n_events: int) -> None:
        self.t = t
        self.n_events = n_events        # events before the step (the recording's test)


def apply_faults(run: RunState, step: StepView) -> None:
    """1. Faults at the start of the step: the fault model's crashes, then its additions.

    A crashed robot vanishes with its controller, its broadcast and what waits for it; an added
    one takes its slot at its pose (heading wrapped) with a fresh controller and seeded
    generator.

    Parameters
    ----------
    run : RunState
        Changed in place.
    step : StepView
        This step's values; the phase adds its own.
    """
    t, events, ids_list, present, poses = step.t, run.events, run.ids_list, run.present, run.poses
    for rid in run.choices.crashed(t, run.ids, present):
        for k in range(run.n_total):
            if present[k] and ids_list[k] == int(rid):
                present[k] = False
                run.controllers[k] = None
                run.last_msgs[k] = None
                run.delivery.forget(k)
                run.exchanges.forget(k)
                events.append(Event(t, "crash", (int(rid),)))
    for slot, p in run.slot_of_add.get(t, ()):
        poses[slot] = p
        poses[slot, 2] = wrap_angle(p[2])
        run.mover.add(slot, poses, ids_list[slot], t)
        present[slot] = True
        run.calling = slot
        run.robot_rngs[slot] = _robot_rng(run.seed, slot)
        run.controllers[slot] = run.algorithm.controller(None if run.hide_ids else ids_list[slot], run.params,
                                                         run.lattice, run.robot_rngs[slot])
        run.calling = None
        run.two_phase = run.two_phase or callable(getattr(run.controllers[slot], "requests", None))
        events.append(Event(t, "add", (ids_list[slot],)))


def activate(run: RunState, step: StepView) -> None:
    """1. Activation: the present robots, and which of them decide in this step.

    Every present robot, or the ones the fault model's ``schedule`` picks; with asynchronous
    clocks only those whose local clock passes an integer during the step, and they broadcast
    their last decided message when it passes a broadcast instant (:mod:`.clocks`).

    Parameters
    ----------
    run : RunState
        Changed in place.
    step : StepView
        This step's values; the phase adds its own.
    """
    t = step.t
    idx = np.flatnonzero(run.present)
    m = len(idx)
    pres_ids = run.ids[idx]
    choices = run.choices
    if run.async_clocks and "activate" in choices.kinds:
        # the chooser picks among the robots whose clock ticks (choices.Choices.ticking)
        decide_now, step.bcast, step.tau0 = run.clocks.ticks(t, idx)
        act = choices.ticking(t, pres_ids, decide_now)
        step.ticked_l = decide_now.tolist()
    else:
        act = choices.activation(t, pres_ids)
        if act is None:
            act = np.ones(m, dtype=bool)
        if run.async_clocks:
            decide_now, step.bcast, step.tau0 = run.clocks.ticks(t, idx)
            act &= decide_now
            step.ticked_l = decide_now.tolist()
    step.idx, step.m, step.pres_ids = idx, m, pres_ids
    step.idx_l, step.pres_ids_l, step.act_l = idx.tolist(), pres_ids.tolist(), act.tolist()


def sense(run: RunState, step: StepView) -> None:
    """2. Sensing, vectorised: what every present robot senses (:func:`.sensing.sense`).

    Per present robot, the IDs, slots and read-only body-frame poses of what it senses.
    Sensing is a pure function of the present robots' poses, so when none of them changed since
    the last sensing (bit for bit) the last result is reused; noise is drawn afresh every step,
    so never with noise.  In the plain model it also notes which robots sense something else
    than last time (``run.resensed``, for the ``repeat_step`` shortcut).

    Parameters
    ----------
    run : RunState
        Changed in place.
    step : StepView
        This step's values; the phase adds its own.
    """
    idx = step.idx
    pp = run.poses[idx]
    pp_bytes = pp.tobytes()
    sensed = run.sensed
    if sensed is not None and not run.noisy and sensed[1] == pp_bytes and np.array_equal(sensed[0], idx):
        step.nb_ids, step.nb_slots, step.nb_rel = sensed[2]
        return
    nb_ids, nb_slots, nb_rel = _sense(pp, idx, run.ids, step.pres_ids, run.phi, inclusive=run.inclusive,
                                      anonymous=run.anonymous, noise=run.faults if run.noisy else None,
                                      t=step.t, rng=run.fault_rng)
    step.nb_ids, step.nb_slots, step.nb_rel = nb_ids, nb_slots, nb_rel
    run.sensed = None if run.noisy else (idx, pp_bytes, (nb_ids, nb_slots, nb_rel))
    if run.repeat_ok:
        # which robots sense something else than last step (IDs or pose bits)
        m = step.m
        keys = [(nb_ids[a], nb_slots[a], nb_rel[a].tobytes()) for a in range(m)]
        if run.last_keys is not None and len(run.last_keys) == m:
            run.resensed = [x != y for x, y in zip(keys, run.last_keys)]
        else:
            run.resensed = None
        run.last_keys = keys


def decide(run: RunState, step: StepView) -> None:
    """3.-4. Message delivery and decision, robot by robot.

    Every acting robot receives its messages, gets its Observation and its controller returns a
    Command; the checked commands go to ``run.turns``, ``run.fwds`` (or ``step.moves``), the new
    broadcasts to ``step.new_msgs``.  In the plain model with ``repeat_step`` the shortcut path
    runs (:func:`_decide_repeating`), else :func:`_decide_general`.  Delivery stays interleaved
    with the decisions (each robot receives just before it decides): a fault hook's draws and
    errors come in the same order as the robots' own code.

    Parameters
    ----------
    run : RunState
        Changed in place.
    step : StepView
        This step's values; the phase adds its own.
    """
    if run.repeat_ok:
        _decide_repeating(run, step)
    else:
        _decide_general(run, step)


def _decide_general(run: RunState, step: StepView) -> None:
    """3.-4. Delivery and decision in any model, with the fault model's hooks.

    A robot whose asynchronous clock does not tick keeps what it receives now for its next tick;
    the delivery's ``drop`` and ``late_delivery`` events are recorded once every robot has
    received (a crash while deciding records none); with asynchronous clocks a robot broadcasts
    its last decided message when its clock passes a broadcast instant.  When a controller
    offers ``requests`` (``run.two_phase``) the step has two phases: every acting robot's
    ``requests(obs)``, the exchanges (:func:`exchange`), then every acting robot's ``step(obs)``."""
    t, m, idx_l, pres_ids_l, act_l = step.t, step.m, step.idx_l, step.pres_ids_l, step.act_l
    nb_ids, nb_slots, nb_rel = step.nb_ids, step.nb_slots, step.nb_rel
    async_clocks, anonymous, global_sensing = run.async_clocks, run.anonymous, run.global_sensing
    controllers, delivery, last_msgs = run.controllers, run.delivery, run.last_msgs
    run.turns = [0.0] * m
    run.fwds = [0.0] * m
    step.moves = [None] * m
    new_msgs = step.new_msgs = [None] * run.n_total
    # every present robot broadcast last step (the usual case): no None to filter
    silent = delivery.comm == "neighbors" and any(last_msgs[s] is None for s in idx_l)
    delivery.begin(last_msgs, idx_l, silent)
    direct, get_msg = delivery.direct, last_msgs.__getitem__
    two_phase = run.two_phase
    acting = [] if two_phase else None
    for a in range(m):
        if not act_l[a]:
            if async_clocks and not step.ticked_l[a]:
                # its clock did not tick: what it receives now waits for its next tick
                delivery.hold(t, idx_l[a], pres_ids_l[a], nb_ids[a], nb_slots[a], nb_rel[a])
            continue
        k, my_id = idx_l[a], pres_ids_l[a]
        # 3. delivery: in the plain model (every neighbor broadcast, no message faults) its
        #    neighbors' broadcasts of the previous step; else the delivery and fault models
        if direct and not (async_clocks and k in delivery.backlog):
            msgs, delivered = dict(zip(nb_ids[a], map(get_msg, nb_slots[a]))), None
        else:
            msgs, delivered = delivery.receive(t, k, my_id, nb_ids[a], nb_slots[a], nb_rel[a])
        # 4. decision: no IDs and positions only when anonymous, its own pose (a read-only
        #    copy) only with global sensing, its inbox when it differs, its local clock
        own = None
        if global_sensing:
            own = run.poses[k].copy()
            own.setflags(write=False)
        obs = _new_observation(t, None if anonymous else my_id, None if anonymous else nb_ids[a],
                               nb_rel[a][:, :2] if anonymous else nb_rel[a], msgs, own)
        if delivered is not None:
            obs.__dict__["delivered"] = delivered
        if async_clocks:
            obs.__dict__["clock"] = float(step.tau0[a])
        run.calling = k
        if two_phase:
            # the first part of the step: its requests, answered before anyone's step (exchange)
            ask = getattr(controllers[k], "requests", None)
            reqs = ask(obs) if callable(ask) else ()
            if reqs:
                run.exchanges.send(t, k, my_id, reqs, None if delivery.comm == "all" else nb_ids[a])
            run.calling = None
            acting.append((a, k, my_id, obs))
            continue
        cmd = controllers[k].step(obs)
        run.calling = None
        _take_command(run, step, a, k, my_id, cmd)
    delivery.end(t, run.events)
    if two_phase:
        exchange(run, step)
        for a, k, my_id, obs in acting:
            run.calling = k
            cmd = controllers[k].step(obs)
            run.calling = None
            _take_command(run, step, a, k, my_id, cmd)
    if async_clocks:
        for a, k in enumerate(idx_l):
            if step.bcast[a]:
                new_msgs[k] = run.outbox[k]


def _take_command(run: RunState, step: StepView, a: int, k: int, my_id, cmd) -> None:
    """A deciding robot's command: checked, its motion to ``run.turns``, ``run.fwds`` (or
    ``step.moves``), its broadcast to the outbox (asynchronous clocks) or ``step.new_msgs``."""
    t = step.t
    if run.grid:
        step.moves[a] = run.mover.command(cmd, my_id, t)
    else:
        run.turns[a], run.fwds[a] = _command_values(cmd, my_id, t)
    if run.async_clocks:
        run.outbox[k] = cmd.message
    else:
        step.new_msgs[k] = cmd.message


def _same_observation(run: RunState, step: StepView) -> list | None:
    """Per present robot, whether its whole observation is last step's.

    The same neighbor IDs at the same pose bits, and the same message objects; None: not
    known (every robot steps).
    """
    same_obs = None
    if step.t > 0 and run.resensed is not None:
        last_msgs, heard_msgs = run.last_msgs, run.heard_msgs
        new_senders = {s for s in run.idx_l_prev if last_msgs[s] is not heard_msgs[s]}
        if new_senders:
            same_obs = [not r and new_senders.isdisjoint(sl) for r, sl in zip(run.resensed, step.nb_slots)]
        else:
            same_obs = [not r for r in run.resensed]
    run.resensed = [False] * step.m
    return same_obs


def _decide_repeating(run: RunState, step: StepView) -> None:
    """3.-4. Delivery and decision in the plain model with ``repeat_step``.

    The plain model: every robot acts, hears its neighbors and senses exactly; no robot joins
    or crashes.  A robot whose observation is last step's and whose hold (``repeat_horizon``) has not run out
    keeps its last command (``run.turns``, ``run.fwds`` and its message stand); one whose
    observation is the same is asked ``repeat_step``; every other robot (and one that declines)
    receives its neighbors' broadcasts and steps.
    """
    same_obs = _same_observation(run, step)
    t, hold, last_msgs = step.t, run.hold, run.last_msgs
    new_msgs = step.new_msgs = last_msgs.copy()
    stepped = step.stepped = []
    todo = range(step.m) if same_obs is None else [a for a in range(step.m) if not same_obs[a] or t >= hold[a]]
    if not todo:
        return          # every robot holds its last command
    idx_l, pres_ids_l = step.idx_l, step.pres_ids_l
    nb_ids, nb_slots, nb_rel = step.nb_ids, step.nb_slots, step.nb_rel
    controllers, repeaters, horizons = run.controllers, run.repeaters, run.horizons
    last_cmds, turns, fwds = run.last_cmds, run.turns, run.fwds
    get_msg = last_msgs.__getitem__
    # every present robot broadcast last step (the usual case): no None to filter
    silent = any(last_msgs[s] is None for s in idx_l)
    for a in todo:
        k = idx_l[a]
        run.calling = k
        cmd = repeaters[k](t) if same_obs is not None and same_obs[a] else None
        if cmd is None:
            msgs = (dict(zip(nb_ids[a], map(get_msg, nb_slots[a]))) if not silent else
                    {sid: last_msgs[s] for sid, s in zip(nb_ids[a], nb_slots[a]) if last_msgs[s] is not None})
            run.calling = k
            cmd = controllers[k].step(_new_observation(t, pres_ids_l[a], nb_ids[a], nb_rel[a], msgs, None))
            stepped.append(k)
        run.calling = None
        if cmd is not last_cmds[k]:
            turns[a], fwds[a] = _command_values(cmd, pres_ids_l[a], t)
            new_msgs[k] = cmd.message
            last_cmds[k] = cmd
        run.calling = k
        hold[a] = t + 1 if horizons[k] is None else horizons[k](t)
        run.calling = None


def exchange(run: RunState, step: StepView) -> None:
    """4b. The point-to-point exchanges due now (``Controller.requests``; :class:`.communication.Exchanges`).

    Between the two phases of a two-phase step (:func:`_decide_general`, which lets every
    controller's state change: ``step.stepped`` stays None): each request due is answered by its
    addressee's ``answer``, and each answer due is read by the asker's ``on_reply``, oldest first (due step, then sending
    order); an answer due in this step (no delay) is read in this step.  Each robot is passed its
    local clock in the step.  A robot gone by then loses what was due to it.  With messages
    recorded, every delivery is an ``exchange`` event.

    Parameters
    ----------
    run : RunState
        Changed in place.
    step : StepView
        This step's values.
    """
    ex = run.exchanges
    if not ex.queue:
        ex.end(step.t, run.events)
        return
    t, controllers, present, ids_list = step.t, run.controllers, run.present, run.ids_list
    while True:
        e = ex.due(t)
        if e is None:
            break
        _, _, kind, a, b, payload, reply = e
        to, frm = (b, a) if kind == "request" else (a, b)
        if not present[to] or controllers[to] is None:
            ex.dropped.append((ids_list[frm], ids_list[to]))      # gone: lost
            continue
        clock = run.clocks.clock_of(to, t)
        fn = getattr(controllers[to], "answer" if kind == "request" else "on_reply", None)
        if not callable(fn):
            need = "answer(sender_id, payload, clock)" if kind == "request" else "on_reply(peer_id, payload, reply, clock)"
            raise ProtocolError(f"robot {ids_list[to]!r} received a {kind} in step {t} but its controller has no "
                                f"{need}: a controller that takes part in exchanges (requests) defines answer and "
                                "on_reply")
        run.calling = to
        if kind == "request":
            reply = fn(ids_list[a], payload, clock)
        else:
            fn(ids_list[b], payload, reply, clock)
        run.calling = None
        if run.record_exchanges:
            run.events.append(Event(t, "exchange", (ids_list[a], ids_list[b]) if kind == "request" else
                                    (ids_list[b], ids_list[a]),
                                    (("kind", kind), ("request", payload), ("reply", reply))))
        if kind == "request" and reply is not None:
            ex.answered(t, a, b, ids_list[a], ids_list[b], payload, reply)
    ex.end(t, run.events)


def move(run: RunState, step: StepView) -> None:
    """5. Motion of the present robots, vectorised; the step count advances.

    :mod:`.motion`: a clamped turn and drive, or grid edges (``step.same_poses``: nobody moved).

    Parameters
    ----------
    run : RunState
        Changed in place.
    step : StepView
        This step's values; the phase adds its own.
    """
    step.same_poses = run.mover.apply(run.poses, step.idx, step.moves if run.grid else (run.turns, run.fwds),
                                      step.pres_ids, step.t, run.events, run.record_clamps)
    run.t = step.t + 1


def _new_states(run: RunState, stepped) -> tuple:
    """``(changed, states)`` after a step: every controller's ``state()``.

    With ``repeat_step`` only the robots that stepped are asked (repeating leaves a state as it
    was).  An unchanged state is kept as the previous object (a long run's trace keeps one copy
    per change, not one per step; equal values, same trace), and so is the whole tuple when
    nothing changed.
    """
    states, controllers, present = run.states, run.controllers, run.present
    changed = False
    merged = list(states)
    for k in range(run.n_total) if stepped is None else stepped:
        c = controllers[k]
        run.calling = k
        st = None if c is None or not present[k] else c.state()
        run.calling = None
        if st is not states[k] and not st == states[k]:
            merged[k] = st
            changed = True
    return changed, (tuple(merged) if changed else states)


def record(run: RunState, step: StepView) -> None:
    """6. Recording and monitors: the trace, the observers, the quiet count, the progress.

    The trace keeps the step (:class:`.run.Recording`, dense or sparse), every observer sees it,
    and the step counts as quiet when no pose, controller state or broadcast (with asynchronous
    clocks: what each robot would say) changed.

    Parameters
    ----------
    run : RunState
        Changed in place.
    step : StepView
        This step's values; the phase adds its own.
    """
    t, rec, poses, present = run.t, run.rec, run.poses, run.present
    keep = rec.keeps(t, run.events, step.n_events)
    if keep:
        rec.frame(t, poses, present)
    changed, new_states = _new_states(run, step.stepped)
    rec.after_step(keep, new_states, step.new_msgs, step.idx_l, run.ids_list)
    for ob in run.observers:
        ob.observe(t, _ro(poses), new_states, _ro(present))
    if run.async_clocks:
        # broadcasts come and go with the clocks; what a robot would say is its outbox
        quiet_step = not changed and step.same_poses and run.outbox == run.last_outbox
        run.last_outbox = list(run.outbox)
    else:
        quiet_step = not changed and step.same_poses and step.new_msgs == run.last_msgs
    run.heard_msgs, run.idx_l_prev, run.last_msgs = run.last_msgs, step.idx_l, step.new_msgs
    run.states = new_states
    run.quiet = run.quiet + 1 if quiet_step else 0
    step.changed = changed
    if run.progress is not None and t % PROGRESS_EVERY == 0:
        run.progress(t, run.max_steps)


def stop_test(run: RunState, step: StepView) -> None:
    """Whether the run ends after this step (``run.status``).

    It ends when the algorithm's ``finished`` holds (it depends on the states alone, so with
    ``repeat_step`` it is asked only when a state changed), when the run was quiet for the
    static window, or when the ``stop_when`` monitor says so.

    Parameters
    ----------
    run : RunState
        Changed in place.
    step : StepView
        This step's values; the phase adds its own.
    """
    run.calling = -1
    done = (step.changed or not run.repeat_ok) and run.algorithm.finished(
        tuple(s for s, p in zip(run.states, run.present) if p))
    run.calling = None
    if done:
        run.status = "finished"
    elif run.window and run.quiet >= run.window:
        run.status = "static"
    elif run.stop_when is not None and run.stop_when(run.t, run.poses, run.states, run.present):
        run.status = "stopped"
