"""The deterministic simulation engine: it owns global poses, sensing, messages, motion and faults.

The model is that of 001 Sec. III-A (and 000 Sec. III-A): n robots with
unique comparable IDs and poses in a global frame that only the engine
knows; time runs in steps of ``dt``.  :func:`simulate` runs the phases of a
step, one function each in :mod:`.phases` (over a :class:`~.phases.RunState`);
each phase's model lives in a module of its own:

1. *Faults and activation (start of step)*: robots crash or join
   (:mod:`.faults`), the schedule picks which robots act, and with
   ``clocks="async"`` a robot acts on its own clock's ticks (:mod:`.clocks`).
2. *Sensing* (:mod:`.sensing`): every robot senses the IDs and body-frame
   poses of the robots in range (strictly closer than phi, or at most phi:
   the model's ``neighbor_rule``; one ``cKDTree`` per step), in increasing ID
   order.  Anonymous models see every robot's position, without IDs or
   headings, ordered by body-frame ``(x, y)``.
3. *Delivery* (:mod:`.communication`): every robot receives the messages
   its current neighbors broadcast in the previous step
   (``communication="all"``: from every robot; ``"none"``: nothing), minus
   lost ones, plus late ones, possibly twice or out of order (fault models).
   With ``clocks="async"`` a robot whose clock does not tick in the step
   keeps them (its backlog) and reads them, oldest first, at its next tick.
4. *Decision*: every acting robot's controller gets an
   :class:`~swarmproof.reference_impl.protocol.Observation` (read-only
   arrays, no global coordinates unless ``sensing="global"``) and returns a
   :class:`~swarmproof.reference_impl.protocol.Command`.
   Optional shortcut (performance only): a controller may define
   ``repeat_step(step) -> Command | None``, "the command :meth:`step` would
   return for the observation of the previous step with only the step number
   changed, or None".  In the plain model (local sensing, neighbor messages,
   no fault hook) the engine calls it instead of ``step`` for a robot that
   senses the same neighbor IDs at bit-identical poses and hears the very
   same message objects as in the previous step, and calls ``step`` when it
   returns None; ``repeat_step`` must leave ``state()`` as it was.  A
   controller may also define ``repeat_horizon(step) -> int`` (called after
   its ``step`` or ``repeat_step`` at ``step``): while the observation stays
   unchanged, ``repeat_step`` would return the same command before that step,
   so the engine does not ask (nor reads its state, nor calls ``finished``
   while no state changed).  Sensing itself is reused when no present robot
   moved.
4b. *Exchanges* (:class:`.communication.Exchanges`): when a controller offers
   ``requests(obs)``, the step has two phases: every acting robot's requests
   go to the addressed neighbors, whose ``answer`` replies, and the replies
   come back to the askers' ``on_reply`` (negligible latency, unless the fault
   model loses or delays a direction); then every acting robot's ``step``.
5. *Motion* (:mod:`.motion`, vectorized): differential drive, turn in place
   then drive straight: ``|turn|`` is clamped to ``omega*dt`` and ``forward``
   to ``[0, v*(dt - |turn|/omega)]`` (docs/decisions.md "Model and
   geometry"); a clamp is recorded as an ``Event(kind="clamp")``.
   Holonomic: a free turn, at most ``v*dt``; grid: the engine's cells.
6. *Recording and monitors*: the trace keeps the step (every step, or
   sparsely: :class:`Recording`), and streaming monitors (``observers``)
   see it either way.

The run stops when ``algorithm.finished(states)`` holds (status
``"finished"``), when the system has been quiet (no pose, message or
controller state changed) for ``static_window`` consecutive steps (status
``"static"``), or at ``max_steps`` (status ``"step_cap"``).

Randomness: the only source is the ``seed``.  Robot slot ``k`` gets
``numpy.random.default_rng(SeedSequence(seed, spawn_key=(0, k)))``, the
fault model gets ``SeedSequence(seed, spawn_key=(1,))``; so the same
inputs and seed give a bit-identical trace, and adding a fault model does
not change the robots' own random draws.

References
----------
001_7a4e517b856331bc.txt (Song & O'Kane 2016), Sec. III-A (robot model),
Defs. 5-6 (static, execution time), Lemma 7 (a robot moves at most v*dt).
000_3ad33c5b62f11d5f.txt (Song & O'Kane 2014), Sec. III-A-3 (differential drive).

Examples
--------
>>> from swarmproof.reference_impl.examples import GatherToLowestId
>>> from swarmproof.reference_impl.protocol import Params
>>> from swarmproof.models.trace import InitialConfiguration
>>> init = InitialConfiguration([0, 1, 2], [[0, 0, 0], [0.8, 0, 0], [1.6, 0, 0]])
>>> r = simulate(GatherToLowestId(), None, init, Params(range=1.0, v=0.1), seed=0)
>>> r.status, r.steps
('finished', 12)
>>> [round(float(x), 6) for x in r.trace.poses[-1][:, 0]]
[0.0, 0.5, 1.0]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from swarmproof.models.errors import AssumptionError, ProtocolError, SwarmproofError, UsageError, check_type
from swarmproof.models.se2 import wrap_angle
from swarmproof.models.trace import Event, InitialConfiguration, Trace, to_jsonable

from ..protocol import Params
from .choices import Choices, check_chooser, state_digest
from .clocks import clock_model
from .common import PROGRESS_EVERY, _ro, _robot_rng
from .communication import Delivery, Exchanges
from .faults import DropSet, FaultModel, TableSchedule
from .motion import motion_model
from .phases import RunState, StepView, activate, apply_faults, decide, move, record, sense, stop_test
from .parameters import check_extra, check_motion, check_target_kind

__all__ = [
    "simulate", "SimulationResult", "Trace", "FaultModel", "TableSchedule", "DropSet", "default_max_steps",
    "default_static_window", "ENGINE_ASSUMPTIONS",
]

#: The engine's own assumption names (checked before every run).
ENGINE_ASSUMPTIONS = ("unique_ids",)

#: Anonymous sensing gives every robot every other robot's position: n^2 rows per step.
ANONYMOUS_MAX_ROBOTS = 2000


def check_team_size(algorithm, n: int) -> None:
    """Refuse a team larger than the algorithm runs (its ``max_robots``; anonymous sensing at most
    :data:`ANONYMOUS_MAX_ROBOTS`): a usage error naming n, the limit and why, before any work.

    >>> check_team_size(type("A", (), {"name": "a", "max_robots": 3, "model": None}), 4)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: robots=4 is more than algorithm 'a' runs (at most 3); fix: run at most 3 robots
    """
    cap = getattr(algorithm, "max_robots", None)
    if getattr(getattr(algorithm, "model", None), "sensing", None) == "anonymous":
        cap = ANONYMOUS_MAX_ROBOTS if cap is None else min(int(cap), ANONYMOUS_MAX_ROBOTS)
    if cap is not None and int(n) > int(cap):
        why = getattr(algorithm, "max_robots_reason", None)
        if why is None and getattr(getattr(algorithm, "model", None), "sensing", None) == "anonymous":
            why = "anonymous robots sense every robot: n^2 positions per step"
        raise UsageError(f"robots={int(n)} is more than algorithm {getattr(algorithm, 'name', '?')!r} runs "
                         f"(at most {int(cap)}{': ' + why if why else ''})", fix=f"run at most {int(cap)} robots")


def default_max_steps(n: int, params: Params) -> int:
    """The step cap when the caller and the algorithm give none.

    ``1000 + 20 * n * ceil(range / (v*dt))``: twenty times the steps needed for
    each of the n robots, one after the other, to cross one range at full speed,
    plus a constant.  An algorithm can override it with a method
    ``default_max_steps(params, n)`` (song2016 uses the Theorem 13 bound).

    >>> default_max_steps(10, Params(range=1.2, v=0.05))
    5800
    """
    step = max(params.v * params.dt, 1e-6)
    return int(1000 + 20 * n * math.ceil(params.range / step))


def default_static_window(n: int) -> int:
    """Quiet steps needed to call a run static: ``2*n + 10``.

    A quiet step changes no pose, no broadcast and no controller state.  A
    controller's state must change whenever its future behaviour may
    (protocol), so one quiet step is a strong hint; the window (longer than
    the timeouts of n steps song2016 uses) guards against controllers that
    read the step counter or draw random numbers.

    >>> default_static_window(10)
    30
    """
    return 2 * int(n) + 10


@dataclass
class SimulationResult:
    """What :func:`simulate` returns.

    Attributes
    ----------
    status : str
        ``"finished"`` (the algorithm's own end condition), ``"static"``
        (quiet for ``static_window`` steps), ``"step_cap"`` (inconclusive) or
        ``"stopped"`` (a ``stop_when`` monitor ended the run) or ``"crashed"`` (the
        algorithm under test raised an exception: ``crash``).
    steps : int
        Steps run (T).
    trace : Trace
    broken_assumptions : tuple of str
        Assumptions broken on purpose (``allow_violations=True`` or a fault model).
    seed : int
    static_window : int
    max_steps : int
    observers : tuple
        The streaming monitors the run carried (``simulate(observers=...)``), after
        seeing every step; ``observed(name)`` gives one's result.
    crash : dict or None
        Status ``"crashed"``: the algorithm under test raised an exception --
        ``{"step", "robot" (None: the algorithm, e.g. finished()), "error", "message",
        "where"}``; the trace ends at the start of that step.
    """

    status: str
    steps: int
    trace: Trace
    broken_assumptions: tuple[str, ...]
    seed: int
    static_window: int
    max_steps: int
    observers: tuple = ()
    crash: dict | None = None

    def observed(self, name: str):
        """The result of the observer called ``name`` (its ``name`` attribute), or None."""
        for ob in self.observers:
            if getattr(ob, "name", None) == name:
                return ob.result()
        return None

    @property
    def final_poses(self) -> np.ndarray:
        return self.trace.final_poses()

    @property
    def final_ids(self) -> np.ndarray:
        return self.trace.final_ids()

    @property
    def final_states(self) -> tuple:
        present = self.trace.present_at(-1)
        return tuple(s for s, p in zip(self.trace.states[-1], present) if p)

    @property
    def static(self) -> bool:
        """All robots were static at the end: the run stopped quiet, or it
        finished and no robot moved in its last step (a one-step view; the
        future of a finished run is the algorithm's claim, Def. 5 of 001)."""
        if self.status == "static":
            return True
        if self.status == "finished":
            if self.steps == 0:
                return True
            return bool(np.array_equal(self.trace.poses[-1], self.trace.poses[-2]))
        return False


#: Events too routine to keep a sparse trace's frame for (they stay in ``trace.events``): a clamp,
#: and a grid robot starting along an edge (004: nearly every step has one).
ROUTINE_EVENTS = frozenset({"clamp", "edge"})


class Recording:
    """What the trace keeps: every step (dense, ``record_every=1``), or step 0, every k-th step,
    every step with an event other than a routine one (:data:`ROUTINE_EVENTS`: a clamp, a grid
    edge start), and the last step (sparse; ``times``)."""

    def __init__(self, record_every: int, poses, present, record_messages: bool) -> None:
        self.every = record_every
        self.times = [0] if record_every > 1 else None
        self.poses = [poses.copy()]
        self.present = None if present is None else [present.copy()]
        self.states: list = []
        self.messages: list | None = [] if record_messages else None
        self._unrecorded_msgs = None

    def keeps(self, t: int, events: list, n_events: int) -> bool:
        """Whether step ``t`` (just run; its events from index ``n_events``) is kept."""
        return self.times is None or t % self.every == 0 or any(e.kind not in ROUTINE_EVENTS
                                                                for e in events[n_events:])

    def frame(self, t: int, poses, present) -> None:
        self.poses.append(poses.copy())
        if self.present is not None:
            self.present.append(present.copy())
        if self.times is not None:
            self.times.append(t)

    def after_step(self, record: bool, states, new_msgs, idx_l, ids_list) -> None:
        if record:
            self.states.append(states)
        if self.messages is None:
            return
        msgs = {ids_list[k]: new_msgs[k] for k in idx_l if new_msgs[k] is not None}
        if record:
            self.messages.append(msgs)
        else:
            self._unrecorded_msgs = msgs

    def finish(self, t: int, poses, present, states) -> None:
        """A sparse trace always ends with the last step."""
        if self.times is not None and self.times[-1] != t:
            self.frame(t, poses, present)
            self.states.append(states)
            if self.messages is not None:
                self.messages.append(self._unrecorded_msgs)

    def trace(self, ids, events, meta) -> Trace:
        return Trace(ids=ids, poses=np.stack(self.poses), states=self.states, events=events,
                     messages=self.messages,
                     present=None if self.present is None else np.stack(self.present), meta=meta,
                     times=self.times)


def run_caps(algorithm, params: Params, n0: int, max_steps, stop_when_static) -> tuple:
    """``(max_steps, static window)`` of a run from the caller's arguments (checked) and the
    algorithm's ``default_max_steps`` (shared with an algorithm's vectorised path)."""
    if max_steps is None:
        f = getattr(algorithm, "default_max_steps", None)
        max_steps = int(f(params, n0)) if callable(f) else default_max_steps(n0, params)
    check_type("max_steps", max_steps, (int, np.integer))
    max_steps = int(max_steps)
    if max_steps < 0:
        raise UsageError(f"max_steps={max_steps!r} must be >= 0")
    if stop_when_static is True:
        window = default_static_window(n0)
    elif stop_when_static is False or stop_when_static is None:
        window = 0
    else:
        check_type("stop_when_static", stop_when_static, (int, np.integer))
        window = int(stop_when_static)
        if window < 1:
            raise UsageError(f"stop_when_static={stop_when_static!r} must be True, False or an int >= 1")
    return max_steps, window


def run_meta(algorithm, lattice, params: Params, seed: int, status: str, t: int, max_steps: int, window: int,
             broken, faults, clocks, grid_meta, record_every: int, crash) -> dict:
    """``trace.meta`` of a run (shared with an algorithm's vectorised path); ``grid_meta``: grid
    motion's ``grid_spacing`` and speeds (None for other motion models)."""
    model = algorithm.model
    return {
        "algorithm": getattr(algorithm, "name", type(algorithm).__name__),
        "premise_monitors": list(getattr(algorithm, "premise_monitors", None) or ()),
        "lattice": (None if lattice is None or getattr(lattice, "kind", "lattice") != "lattice"
                    else getattr(lattice, "name", None)),
        "target": None if lattice is None else {"kind": getattr(lattice, "kind", "lattice"),
                                                 "name": getattr(lattice, "name", None)},
        "params": {"range": params.range, "v": params.v, "omega": params.omega, "dt": params.dt,
                   "extra": to_jsonable(dict(params.extra))},
        "seed": seed,
        "status": status,
        "steps": t,
        "max_steps": max_steps,
        "static_window": window,
        "broken_assumptions": list(broken),
        "faults": faults.describe(),
        **clocks.describe(),
        **(grid_meta or {}),
        **({"record_every": record_every} if record_every > 1 else {}),
        **({"crash": crash} if crash is not None else {}),
        "model": {"sensing": model.sensing, "communication": model.communication,
                  "motion": model.motion, "clocks": model.clocks,
                  "neighbor_rule": getattr(model, "neighbor_rule", "strict")},
    }


def _crash_record(exc: BaseException, calling: int, t: int, ids_list, anonymous: bool) -> dict:
    """What the algorithm under test raised, for the result, the trace and the explorer."""
    import traceback

    robot = None if calling < 0 else int(ids_list[calling])
    frames = traceback.extract_tb(exc.__traceback__)
    last = frames[-1] if frames else None
    where = f"{last.filename}:{last.lineno} in {last.name}" if last else ""
    text = str(exc).splitlines()[0][:300] if str(exc) else ""
    return {"step": int(t), "robot": robot, "error": type(exc).__name__, "message": text, "where": where}


def _check_params(params: Params) -> None:
    if not isinstance(params, Params):
        raise UsageError(f"params={params!r} must be a Params", fix="build it with Params(range=...)")
    for name in ("range", "omega", "dt"):
        v = getattr(params, name)
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise UsageError(f"params.{name}={v!r} must be a finite number > 0")
    if not (isinstance(params.v, (int, float)) and math.isfinite(params.v) and params.v >= 0):
        raise UsageError(f"params.v={params.v!r} must be a finite number >= 0")
    check_motion(params)     # a run that could not move is meaningless (issue 29)


def preflight(algorithm, lattice, initial: InitialConfiguration, params: Params, seed, allow_violations: bool,
              faults: FaultModel | None):
    """The checks before a run's first step (shared by :func:`simulate` and an algorithm's
    vectorised path, e.g. :mod:`swarmproof.reference_impl.wang2020.fast`): the seed, the start,
    the parameters, the team size, the algorithm's own options and every assumption (the
    engine's ``unique_ids`` and the algorithm's).  Returns ``(seed, faults, events, broken)``:
    the seed as an int, the fault model (a plain one if None), the ``assumption_broken``
    events and the names of the assumptions broken on purpose."""
    check_type("seed", seed, (int, np.integer))
    seed = int(seed)
    if seed < 0:
        raise UsageError(f"seed={seed!r} must be >= 0", fix="pass a non-negative integer seed")
    if not isinstance(initial, InitialConfiguration):
        raise UsageError(f"initial={initial!r} must be an InitialConfiguration",
                         fix="build one with reference_impl.initial.random_connected or from_file")
    _check_params(params)
    n0 = initial.n
    if n0 < 1:
        raise UsageError("initial configuration has n=0 robots", fix="give at least one robot")
    faults = faults if faults is not None else FaultModel()
    model = algorithm.model
    anonymous = model.sensing == "anonymous"
    hide_ids = anonymous and not getattr(model, "own_id", False)   # what controllers and assumptions see
    events: list[Event] = []
    broken: list[str] = []

    check_team_size(algorithm, n0)     # memory and time bounded on any input
    check_extra(algorithm, params.extra)   # declared keys, each in its range (engine/parameters.py)
    check_target_kind(algorithm, lattice)
    own_check = getattr(algorithm, "check_params", None)
    if callable(own_check):
        own_check(params, n0, lattice)   # an algorithm's own options (usage errors, before any step)

    # -- assumptions -----------------------------------------------------
    ids0 = initial.ids.tolist()
    if len(set(ids0)) != len(ids0):
        dup = sorted({i for i in ids0 if ids0.count(i) > 1})
        msg = f"ids contain duplicates {dup!r} (001 Sec. III-A: unique comparable IDs)"
        if not allow_violations:
            raise AssumptionError("unique_ids", msg,
                                  fix="give every robot its own ID, or pass allow_violations=True "
                                      "(--allow-violations on the command line)")
        broken.append("unique_ids")
    for a in algorithm.assumptions:
        msg = a.check(params, n0, None if hide_ids else ids0)
        if msg is None and a.check_start is not None:
            msg = a.check_start(params, None if hide_ids else ids0, initial.poses.copy())
        if msg is None and getattr(a, "check_target", None) is not None:
            msg = a.check_target(params, n0, lattice)
        if msg is not None:
            if not allow_violations:
                raise AssumptionError(a.name, f"{msg} ({a.statement}; {a.cites})",
                                      fix="change the value, or pass allow_violations=True "
                                          "(--allow-violations on the command line) to break "
                                          "the assumption on purpose")
            broken.append(a.name)
    for name in broken:
        events.append(Event(0, "assumption_broken", (), (("assumption", name),)))
    broken.extend(faults.broken_model_assumptions(model))
    return seed, faults, events, broken


def _slots(initial: InitialConfiguration, faults: FaultModel) -> tuple:
    """One slot per robot that is ever present: the start's, then the fault model's additions.

    Returns ``(ids, poses, present, slot_of_add)``: IDs and start poses (headings wrapped) by
    slot, who is present at step 0, and ``step -> [(slot, pose), ...]`` (additions in step order).
    """
    n0 = initial.n
    add_rows = []
    for step_k in sorted(faults.additions):
        for rid, pose in faults.additions[step_k]:
            p = np.asarray(pose, dtype=float)
            if p.shape != (3,) or not np.isfinite(p).all():
                raise UsageError(f"faults.additions[{step_k}] pose={pose!r} must be finite [x, y, theta]")
            add_rows.append((int(step_k), int(rid), p))
    n_total = n0 + len(add_rows)
    ids = np.array(initial.ids.tolist() + [r[1] for r in add_rows], dtype=np.int64)
    poses = np.zeros((n_total, 3))
    poses[:n0] = initial.poses
    poses[:, 2] = wrap_angle(poses[:, 2])
    present = np.zeros(n_total, dtype=bool)
    present[:n0] = True
    slot_of_add = {}
    for k, (step_k, rid, p) in enumerate(add_rows):
        slot_of_add.setdefault(step_k, []).append((n0 + k, p))
    return ids, poses, present, slot_of_add


def _new_run(algorithm, lattice, initial: InitialConfiguration, params: Params, seed, allow_violations: bool,
             faults: FaultModel | None, chooser=None, **options) -> RunState:
    """A run before its start (:class:`~.phases.RunState`).

    The checks (:func:`preflight`), the slots (:func:`_slots`), the motion and clock models and
    the fault model's generator.  ``options``: :func:`simulate`'s ``max_steps``,
    ``record_every``, ``observers``, ``progress``, ``stop_when`` and ``record_clamps``, checked
    when the run starts (:func:`_start`).
    """
    if chooser is not None:
        check_chooser(chooser)
    seed, faults, events, broken = preflight(algorithm, lattice, initial, params, seed, allow_violations, faults)
    model = algorithm.model
    ids, poses, present, slot_of_add = _slots(initial, faults)
    n0, n_total, ids_list = initial.n, len(ids), ids.tolist()
    mover = motion_model(model, params, n_total, seed)
    mover.start(poses, n0, ids_list)
    clocks = clock_model(model, params, n_total, seed)
    anonymous = model.sensing == "anonymous"
    fault_rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(1,)))
    choices = Choices(faults, fault_rng, chooser)
    for name in choices.broken_assumptions(model):
        if name not in broken:
            broken.append(name)
    run = RunState(algorithm, lattice, params, seed, faults, events, broken, ids, ids_list, n0, poses, present,
                   slot_of_add, any_presence_change=(n_total > n0 or any(faults.crashes.values())
                                                     or choices.crashes_left > 0),
                   mover=mover, clocks=clocks, fault_rng=fault_rng, choices=choices, **options)
    run.n_total = n_total
    run.anonymous = anonymous
    run.hide_ids = anonymous and not getattr(model, "own_id", False)   # what controllers and assumptions see
    run.grid = mover.grid
    run.async_clocks = not clocks.synchronous
    if run.async_clocks:
        run.outbox, run.last_outbox = [None] * n_total, [None] * n_total
    return run


def _new_controllers(run: RunState, initial: InitialConfiguration) -> None:
    """A controller per robot of the start, with its seeded generator.

    An algorithm that ``knows_start`` then gets the robot set and the start positions (read-only).
    """
    algorithm, ids_list, n0 = run.algorithm, run.ids_list, run.n0
    run.controllers = [None] * run.n_total
    run.robot_rngs = [None] * run.n_total
    for k in range(n0):
        run.calling = k
        run.robot_rngs[k] = _robot_rng(run.seed, k)
        run.controllers[k] = algorithm.controller(None if run.hide_ids else ids_list[k], run.params, run.lattice,
                                                  run.robot_rngs[k])
    run.calling = None
    if getattr(algorithm, "knows_start", False):
        # The paper's input: every robot knows the robot set and all initial positions in the
        # common frame (002 Sec. III-A, Alg. 1 "Input"); given once, read-only, before step 0.
        if getattr(algorithm.model, "sensing", None) != "global":
            raise UsageError(f"algorithm {getattr(algorithm, 'name', '?')!r} sets knows_start but its "
                             f"model.sensing={algorithm.model.sensing!r}",
                             fix="knows_start needs sensing='global' (positions in the common frame)")
        known_ids = tuple(int(x) for x in ids_list[:n0])
        known_xy = np.array(initial.poses[:, :2], dtype=float)
        known_xy.setflags(write=False)
        for k in range(n0):
            run.calling = k
            run.controllers[k].know_start(known_ids, known_xy)
        run.calling = None


def _first_states(run: RunState) -> tuple:
    """Every controller's ``state()`` before step 0, each checked hashable.

    A crash there is the algorithm's (``run.calling`` -1), not one robot's.
    """
    run.calling = -1
    states = tuple(None if c is None or not run.present[k] else c.state() for k, c in enumerate(run.controllers))
    run.calling = None
    for k, st in enumerate(states):
        try:
            hash(st)
        except TypeError:
            raise ProtocolError(f"controller of robot {run.ids_list[k]!r}: state() returned an unhashable "
                                f"{type(st).__name__} ({st!r:.80}); return tuples of (key, value) "
                                "pairs, a namedtuple or a frozen dataclass") from None
    return states


def _plan_shortcuts(run: RunState) -> None:
    """Whether ``repeat_step`` may stand in for ``step`` (engine module docstring).

    Only in the plain model (every robot acts, hears its neighbors, senses exactly; no robot
    joins or crashes) and when every controller offers it.
    """
    model, faults, n_total = run.algorithm.model, run.faults, run.n_total
    run.repeaters = [getattr(c, "repeat_step", None) for c in run.controllers]
    run.repeat_ok = (run.choices.chooser is None and model.sensing == "local" and model.communication == "neighbors"
                     and not faults.drops_messages and not faults.noisy and faults.schedule is None
                     and not faults.late_messages and not run.grid and not run.async_clocks
                     and not run.any_presence_change and not run.two_phase
                     and all(callable(f) for f in run.repeaters))
    run.horizons = [getattr(c, "repeat_horizon", None) for c in run.controllers]
    run.hold = [0] * n_total
    run.last_cmds = [None] * n_total
    run.turns = [0.0] * run.n0
    run.fwds = [0.0] * run.n0
    run.heard_msgs = [None] * n_total


def _start(run: RunState, initial: InitialConfiguration, stop_when_static, record_messages: bool) -> None:
    """Step 0: everything the loop needs, and whether the run is over before its first step.

    The controllers, the caps and options checked, the first recorded frame and states, the
    models of the loop, the observers' start; the run is over when ``finished`` holds already
    or ``stop_when`` stops it.
    """
    _new_controllers(run, initial)
    algorithm, model, faults = run.algorithm, run.algorithm.model, run.faults
    run.max_steps, run.window = run_caps(algorithm, run.params, run.n0, run.max_steps, stop_when_static)
    run.choices.clock_phases(run.clocks, run.max_steps, run.ids_list[:run.n0])   # a chooser's, before step 0
    check_type("record_every", run.record_every, (int, np.integer))
    run.record_every = int(run.record_every)
    if run.record_every < 1:
        raise UsageError(f"record_every={run.record_every!r} must be an integer >= 1", fix="1 records every step")
    run.observers = tuple(run.observers or ())
    for ob in run.observers:
        if not (callable(getattr(ob, "start", None)) and callable(getattr(ob, "observe", None))):
            raise UsageError(f"observer={ob!r} has no start(ids) and observe(t, poses, states, present)",
                             fix="use a streaming monitor such as ConnectivityMonitor")
    run.rec = Recording(run.record_every, run.poses, run.present if run.any_presence_change else None,
                        record_messages)
    run.states = _first_states(run)
    run.rec.states.append(run.states)
    run.last_msgs = [None] * run.n_total
    run.two_phase = any(callable(getattr(c, "requests", None)) for c in run.controllers if c is not None)
    _plan_shortcuts(run)
    run.phi = float(run.params.range)
    run.global_sensing = model.sensing == "global"
    std_xy, std_th = (float(s) for s in faults.noise_std)   # (a noise_std that is not a pair fails here)
    run.noisy = faults.noisy
    run.inclusive = model.neighbor_rule == "inclusive"
    run.delivery = Delivery(model, run.phi, run.ids_list, run.choices)
    run.exchanges = Exchanges(model, run.ids_list, run.choices)
    run.record_exchanges = bool(record_messages)
    run.calling = -1
    finished = bool(algorithm.finished(tuple(s for s, p in zip(run.states, run.present) if p)))
    run.calling = None
    if finished:
        run.status = "finished"
    for ob in run.observers:
        ob.start(run.ids.copy())
        ob.observe(0, _ro(run.poses), run.states, _ro(run.present))
    if run.stop_when is not None and not finished and run.stop_when(0, run.poses, run.states, run.present):
        run.status = "stopped"


def _end(run: RunState) -> None:
    """The loop ended: status ``"step_cap"`` unless a stop test ended it, and the last progress call."""
    if run.status is None:
        run.status = "step_cap"
    if run.progress is not None:
        run.progress(run.t, run.max_steps)


def _crashed(run: RunState, exc: BaseException) -> None:
    """Status ``"crashed"``: what the algorithm under test raised, as the run's result.

    The exception (``run.calling`` says whose code ran) becomes the result's ``crash`` and an
    ``algorithm_crash`` event; the trace ends at the start of that step (a crash before the
    recording exists leaves one frame whose states are all None).
    """
    crash = run.crash = _crash_record(exc, run.calling, run.t, run.ids_list, run.anonymous)
    run.status = "crashed"
    run.events.append(Event(run.t, "algorithm_crash", () if crash["robot"] is None else (crash["robot"],),
                            (("error", crash["error"]), ("message", crash["message"]))))
    if run.rec is None:
        run.rec = Recording(1, run.poses, None, False)
        run.states = tuple([None] * len(run.ids_list))
        run.rec.states.append(run.states)
    if run.window is None:
        run.window = 0
    if run.max_steps is None:
        run.max_steps = 0


def _result(run: RunState) -> SimulationResult:
    """The :class:`SimulationResult` of a run that ended.

    Its trace (a sparse one ends with the last step) with ``trace.meta`` (:func:`run_meta`).
    """
    run.rec.finish(run.t, run.poses, run.present, run.states)
    mover = run.mover
    meta = run_meta(run.algorithm, run.lattice, run.params, run.seed, run.status, run.t, run.max_steps, run.window,
                    run.broken, run.faults, run.clocks,
                    {"grid_spacing": mover.spacing, **mover.describe()} if run.grid else None, run.record_every,
                    run.crash)
    if run.choices.chooser is not None:
        meta["choices"] = run.choices.chooser.describe()
    trace = run.rec.trace(run.ids, run.events, meta)
    return SimulationResult(status=run.status, steps=run.t, trace=trace, broken_assumptions=tuple(run.broken),
                            seed=run.seed, static_window=run.window, max_steps=run.max_steps,
                            observers=run.observers, crash=run.crash)


def simulate(algorithm, lattice, initial: InitialConfiguration, params: Params, *, seed: int,
             max_steps: int | None = None, allow_violations: bool = False,
             record_messages: bool = False, stop_when_static: bool | int = True,
             faults: FaultModel | None = None,
             progress: Callable[[int, int], None] | None = None,
             record_clamps: bool = True,
             stop_when: Callable[[int, np.ndarray, tuple, np.ndarray], bool] | None = None,
             record_every: int = 1, observers: Sequence = (), chooser=None) -> SimulationResult:
    """Run ``algorithm`` from ``initial`` until it finishes, goes static or hits the cap.

    Parameters
    ----------
    algorithm : protocol.Algorithm
        Provides ``name``, ``model``, ``assumptions``, ``controller(...)``,
        ``finished(states)``; optionally ``default_max_steps(params, n)``.
    lattice : LatticeGraph or None
        Passed to every controller (the engine does not read it).
    initial : InitialConfiguration
    params : Params
    seed : int
        Non-negative; the only source of randomness.
    max_steps : int, optional
        Step cap; default ``algorithm.default_max_steps(params, n)`` if the
        algorithm defines it, else :func:`default_max_steps`.
    allow_violations : bool
        Run even if an assumption is broken; the result lists the broken ones.
    record_messages : bool
        Keep every step's broadcasts in the trace.
    stop_when_static : bool or int
        True: stop after :func:`default_static_window` quiet steps; an int K:
        after K quiet steps; False: never stop on quiet.
    faults : FaultModel, optional
        Fault hooks (schedule, crashes, additions, lost messages, noise).
    progress : callable ``(step, max_steps)``, optional
        Called every :data:`PROGRESS_EVERY` steps and at the end.
    record_clamps : bool
        Record an Event per step listing the robots whose command was clamped.
    stop_when : callable ``(t, poses, states, present) -> bool``, optional
        A run-time monitor, called with the start (t = 0) and after every
        step t with the poses, controller states and presence mask the trace
        records for t (read-only views); True ends the run there with status
        ``"stopped"`` (the explorer's early stop at a repeated global state).
    record_every : int
        1 (default): record every step (dense).  k > 1: a sparse trace that
        keeps step 0, every k-th step, every step with an event other than a
        clamp or a grid edge start, and the last step (``trace.times`` lists them), so a long run
        of many robots fits in memory.
    observers : sequence of streaming monitors
        Objects with ``start(ids)``, ``observe(t, poses, states, present)``
        (called at the start and after *every* step, recorded or not, with
        read-only views) and ``result()``; e.g.
        :class:`~swarmproof.invariants.connectivity.ConnectivityMonitor`.
        Properties judged this way see every step whatever is recorded.
    chooser : choices.Chooser, optional
        Makes the decisions of the kinds it names (which robots act, each delivery's fate,
        crashes: :mod:`.choices`) instead of the fault generator (issue 33), and is asked after
        every step whether to go on (status ``"pruned"`` when it says no).  None (default): the
        fault model draws as always.

    Returns
    -------
    SimulationResult

    Raises
    ------
    AssumptionError
        An assumption (the engine's ``unique_ids``, or one of the
        algorithm's) is broken and ``allow_violations`` is False.
    UsageError
        Bad arguments (no robots, bad params, negative seed ...).
    ProtocolError
        A controller returned something that is not a valid Command.
    """
    run = _new_run(algorithm, lattice, initial, params, seed, allow_violations, faults, chooser, max_steps=max_steps,
                   record_every=record_every, observers=observers, progress=progress, stop_when=stop_when,
                   record_clamps=record_clamps)
    after_step = getattr(chooser, "after_step", None)
    try:
        _start(run, initial, stop_when_static, record_messages)
        while run.status is None and run.t < run.max_steps:
            step = StepView(run.t, len(run.events))
            apply_faults(run, step)     # 1. robots crash or join
            activate(run, step)         # 1. who acts: the schedule, the clocks
            sense(run, step)            # 2.
            decide(run, step)           # 3.-4. message delivery, exchanges and decisions
            move(run, step)             # 5.
            record(run, step)           # 6. the trace and the monitors
            stop_test(run, step)
            if after_step is not None and run.status is None and run.t < run.max_steps and after_step(
                    run.t, lambda symmetric=False: state_digest(run, symmetric=symmetric and run.hide_ids)):
                run.status = "pruned"   # the chooser has seen this state (exhaustive checking)
        _end(run)
    except (Exception, SystemExit, GeneratorExit) as exc:  # noqa: BLE001 - only what the algorithm raised
        # SystemExit and GeneratorExit from the algorithm's code are crashes too (a SystemExit once
        # ended swarmproof with exit 0 and no report); KeyboardInterrupt stays Ctrl-C (exit 130)
        if isinstance(exc, SwarmproofError) or run.calling is None:
            raise      # a usage or protocol error, or the engine's own bug: not the algorithm's
        _crashed(run, exc)
    return _result(run)
