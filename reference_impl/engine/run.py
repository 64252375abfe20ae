"""The deterministic simulation engine: it owns global poses, sensing, messages, motion and faults.

The model is that of 001 Sec. III-A (and 000 Sec. III-A): n robots with
unique comparable IDs and poses in a global frame that only the engine
knows; time runs in steps of ``dt``.  The loop below runs the phases of a
step; each phase's model lives in a module of its own:

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
from .clocks import clock_model
from .common import _ro
from .communication import Delivery
from .faults import DropSet, FaultModel, TableSchedule
from .motion import _command_values, motion_model
from .parameters import check_extra, check_motion, check_target_kind
from .sensing import _new_observation, sense

__all__ = [
    "simulate", "SimulationResult", "Trace", "FaultModel", "TableSchedule", "DropSet", "default_max_steps",
    "default_static_window", "ENGINE_ASSUMPTIONS",
]

#: The engine's own assumption names (checked before every run).
ENGINE_ASSUMPTIONS = ("unique_ids",)

#: How often (in steps) the progress callback is called.
PROGRESS_EVERY = 50


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
        present = self.trace.present_at(self.steps)
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


def _robot_rng(seed: int, slot: int) -> np.random.Generator:
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(0, slot)))


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


def simulate(algorithm, lattice, initial: InitialConfiguration, params: Params, *, seed: int,
             max_steps: int | None = None, allow_violations: bool = False,
             record_messages: bool = False, stop_when_static: bool | int = True,
             faults: FaultModel | None = None,
             progress: Callable[[int, int], None] | None = None,
             record_clamps: bool = True,
             stop_when: Callable[[int, np.ndarray, tuple, np.ndarray], bool] | None = None,
             record_every: int = 1, observers: Sequence = ()) -> SimulationResult:
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
    seed, faults, events, broken = preflight(algorithm, lattice, initial, params, seed, allow_violations, faults)
    n0 = initial.n
    ids0 = initial.ids.tolist()
    model = algorithm.model
    anonymous = model.sensing == "anonymous"
    hide_ids = anonymous and not getattr(model, "own_id", False)   # what controllers and assumptions see

    # -- slots -----------------------------------------------------------
    add_rows = []
    for step_k in sorted(faults.additions):
        for rid, pose in faults.additions[step_k]:
            p = np.asarray(pose, dtype=float)
            if p.shape != (3,) or not np.isfinite(p).all():
                raise UsageError(f"faults.additions[{step_k}] pose={pose!r} must be finite [x, y, theta]")
            add_rows.append((int(step_k), int(rid), p))
    n_total = n0 + len(add_rows)
    ids = np.array(ids0 + [r[1] for r in add_rows], dtype=np.int64)
    ids_list = ids.tolist()
    poses = np.zeros((n_total, 3))
    poses[:n0] = initial.poses
    poses[:, 2] = wrap_angle(poses[:, 2])
    present = np.zeros(n_total, dtype=bool)
    present[:n0] = True
    slot_of_add = {}
    for k, (step_k, rid, p) in enumerate(add_rows):
        slot_of_add.setdefault(step_k, []).append((n0 + k, p))
    any_presence_change = bool(add_rows) or any(faults.crashes.values())

    mover = motion_model(model, params, n_total, seed)
    mover.start(poses, n0, ids_list)
    grid = mover.grid
    clocks = clock_model(model, params, n_total, seed)
    async_clocks = not clocks.synchronous
    if async_clocks:
        outbox: list = [None] * n_total
        last_outbox: list = [None] * n_total
    fault_rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(1,)))
    calling = None   # the robot slot (-1: the algorithm) whose code runs now; None: the engine's
    rec = window = None
    states = None
    crash = None
    t = 0
    try:
        controllers: list = [None] * n_total
        for k in range(n0):
            calling = k
            controllers[k] = algorithm.controller(None if hide_ids else ids_list[k], params, lattice,
                                                  _robot_rng(seed, k))
        calling = None
        if getattr(algorithm, "knows_start", False):
            # The paper's input: every robot knows the robot set and all initial positions in the
            # common frame (002 Sec. III-A, Alg. 1 "Input"); given once, read-only, before step 0.
            if getattr(algorithm.model, "sensing", None) != "global":
                raise UsageError(f"algorithm {getattr(algorithm, 'name', '?')!r} sets knows_start but its "
                                 f"model.sensing={algorithm.model.sensing!r}",
                                 fix="knows_start needs sensing='global' (positions in the common frame)")
            known_ids = tuple(int(x) for x in ids0)
            known_xy = np.array(initial.poses[:, :2], dtype=float)
            known_xy.setflags(write=False)
            for k in range(n0):
                calling = k
                controllers[k].know_start(known_ids, known_xy)
            calling = None

        max_steps, window = run_caps(algorithm, params, n0, max_steps, stop_when_static)

        def _states() -> tuple:
            return tuple(None if c is None or not present[k] else c.state()
                         for k, c in enumerate(controllers))

        check_type("record_every", record_every, (int, np.integer))
        record_every = int(record_every)
        if record_every < 1:
            raise UsageError(f"record_every={record_every!r} must be an integer >= 1", fix="1 records every step")
        observers = tuple(observers or ())
        for ob in observers:
            if not (callable(getattr(ob, "start", None)) and callable(getattr(ob, "observe", None))):
                raise UsageError(f"observer={ob!r} has no start(ids) and observe(t, poses, states, present)",
                                 fix="use a streaming monitor such as ConnectivityMonitor")
        rec = Recording(record_every, poses, present if any_presence_change else None, record_messages)
        calling = -1
        states = _states()
        calling = None
        for k, st in enumerate(states):
            try:
                hash(st)
            except TypeError:
                raise ProtocolError(f"controller of robot {ids_list[k]!r}: state() returned an unhashable "
                                    f"{type(st).__name__} ({st!r:.80}); return tuples of (key, value) "
                                    "pairs, a namedtuple or a frozen dataclass") from None
        rec.states.append(states)
        last_msgs: list = [None] * n_total
        sensed = None  # (idx, position bytes, per-robot neighbor IDs, slots, poses)
        # Repeating the last command (Controller.repeat_step) when a robot's observation is
        # last step's except the step number: only in the plain model (every robot acts,
        # hears its neighbors, senses exactly; no robot joins or crashes).
        repeaters = [getattr(c, "repeat_step", None) for c in controllers]
        repeat_ok = (model.sensing == "local" and model.communication == "neighbors"
                     and not faults.drops_messages and not faults.noisy and faults.schedule is None
                     and not faults.late_messages and not grid and not async_clocks
                     and not any_presence_change and all(callable(f) for f in repeaters))
        last_keys = resensed = None
        horizons = [getattr(c, "repeat_horizon", None) for c in controllers]
        hold = [0] * n_total
        last_cmds: list = [None] * n_total
        turns_l = [0.0] * n0
        fwds_l = [0.0] * n0
        heard_msgs: list = [None] * n_total
        idx_l_prev: list = []

        phi = float(params.range)
        global_sensing = model.sensing == "global"
        comm = model.communication
        std_xy, std_th = (float(s) for s in faults.noise_std)
        noisy = faults.noisy
        inclusive = model.neighbor_rule == "inclusive"
        delivery = Delivery(model, faults, phi, ids_list, fault_rng)
        status = "step_cap"
        quiet = 0
        calling = -1
        finished = bool(algorithm.finished(tuple(s for s, p in zip(states, present) if p)))
        calling = None
        if finished:
            status = "finished"
        t = 0
        for ob in observers:
            ob.start(ids.copy())
            ob.observe(0, _ro(poses), states, _ro(present))
        if stop_when is not None and not finished and stop_when(0, poses, states, present):
            status, finished = "stopped", True
        while not finished and t < max_steps:
            n_events = len(events)
            # 1. faults at the start of the step
            for rid in faults.crashes.get(t, ()):
                for k in range(n_total):
                    if present[k] and ids_list[k] == int(rid):
                        present[k] = False
                        controllers[k] = None
                        last_msgs[k] = None
                        delivery.forget(k)
                        events.append(Event(t, "crash", (int(rid),)))
            for slot, p in slot_of_add.get(t, ()):
                poses[slot] = p
                poses[slot, 2] = wrap_angle(p[2])
                mover.add(slot, poses, ids_list[slot], t)
                present[slot] = True
                calling = slot
                controllers[slot] = algorithm.controller(None if hide_ids else ids_list[slot], params,
                                                         lattice, _robot_rng(seed, slot))
                calling = None
                events.append(Event(t, "add", (ids_list[slot],)))
            idx = np.flatnonzero(present)
            m = len(idx)
            pres_ids = ids[idx]
            if faults.schedule is not None:
                act = np.asarray(faults.schedule(t, pres_ids.copy(), fault_rng), dtype=bool)
                if act.shape != (m,):
                    raise UsageError(f"faults.schedule returned shape={act.shape!r}, expected ({m},)")
            else:
                act = np.ones(m, dtype=bool)
            if async_clocks:
                # a robot decides in step t when its local clock passes an integer during the step,
                # and broadcasts its last decided message when the clock passes a broadcast instant
                decide, bcast, tau0 = clocks.ticks(t, idx)
                act &= decide
                ticked_l = decide.tolist()

            # 2. sensing (vectorized).  Sensing is a pure function of the present robots'
            #    poses, so when none of them changed since the last sensing (bit for bit) the
            #    last result is reused; noise is drawn afresh every step, so never with noise.
            pp = poses[idx]
            pp_bytes = pp.tobytes()
            if (sensed is not None and not noisy and sensed[1] == pp_bytes
                    and np.array_equal(sensed[0], idx)):
                nb_ids, nb_slots, nb_rel = sensed[2]
            else:
                nb_ids, nb_slots, nb_rel = sense(pp, idx, ids, pres_ids, phi, inclusive=inclusive, anonymous=anonymous,
                                                 noise=faults if noisy else None, t=t, rng=fault_rng)
                sensed = None if noisy else (idx, pp_bytes, (nb_ids, nb_slots, nb_rel))
                if repeat_ok:
                    # which robots sense something else than last step (IDs or pose bits)
                    keys = [(nb_ids[a], nb_slots[a], nb_rel[a].tobytes()) for a in range(m)]
                    if last_keys is not None and len(last_keys) == m:
                        resensed = [x != y for x, y in zip(keys, last_keys)]
                    else:
                        resensed = None
                    last_keys = keys
            # Robots whose whole observation (neighbor IDs, pose bits, message objects)
            # is last step's may repeat their last command (Controller.repeat_step).
            same_obs = None
            if repeat_ok and t > 0 and resensed is not None:
                new_senders = {s for s in idx_l_prev if last_msgs[s] is not heard_msgs[s]}
                if new_senders:
                    same_obs = [not r and new_senders.isdisjoint(sl) for r, sl in zip(resensed, nb_slots)]
                else:
                    same_obs = [not r for r in resensed]
            resensed = [False] * m if repeat_ok else None

            # 3.-4. messages and decisions (per robot)
            act_l = act.tolist()
            idx_l = idx.tolist()
            pres_ids_l = pres_ids.tolist()
            # every present robot broadcast last step (the usual case): no None to filter
            silent = comm == "neighbors" and any(last_msgs[s] is None for s in idx_l)
            get_msg = last_msgs.__getitem__
            if repeat_ok:
                # The plain model with repeat_step: a robot whose observation is last step's
                # and whose hold (repeat_horizon) has not run out keeps its last command
                # (turns_l, fwds_l and its message stand); one whose observation is the same
                # is asked repeat_step; every other robot (and one that declines) steps.
                new_msgs = last_msgs.copy()
                stepped = []
                if same_obs is None:
                    todo = range(m)
                else:
                    todo = [a for a in range(m) if not same_obs[a] or t >= hold[a]]
                for a in todo:
                    k = idx_l[a]
                    calling = k
                    cmd = repeaters[k](t) if same_obs is not None and same_obs[a] else None
                    if cmd is None:
                        msgs = (dict(zip(nb_ids[a], map(get_msg, nb_slots[a]))) if not silent else
                                {sid: last_msgs[s] for sid, s in zip(nb_ids[a], nb_slots[a])
                                 if last_msgs[s] is not None})
                        calling = k
                        cmd = controllers[k].step(_new_observation(t, pres_ids_l[a], nb_ids[a], nb_rel[a],
                                                                   msgs, None))
                        stepped.append(k)
                    calling = None
                    if cmd is not last_cmds[k]:
                        turns_l[a], fwds_l[a] = _command_values(cmd, pres_ids_l[a], t)
                        new_msgs[k] = cmd.message
                        last_cmds[k] = cmd
                    calling = k
                    hold[a] = t + 1 if horizons[k] is None else horizons[k](t)
                    calling = None
            else:
                turns_l = [0.0] * m
                fwds_l = [0.0] * m
                moves_l = [None] * m
                new_msgs = [None] * n_total
                stepped = None
            # the general path: any model, fault hooks (empty when repeat_ok)
            if not repeat_ok:
                delivery.begin(last_msgs, idx_l, silent)
                direct = delivery.direct
            for a in (range(0) if repeat_ok else range(m)):
                if not act_l[a]:
                    if async_clocks and not ticked_l[a]:
                        # its clock did not tick: what it receives now waits for its next tick
                        delivery.hold(t, idx_l[a], pres_ids_l[a], nb_ids[a], nb_slots[a], nb_rel[a])
                    continue
                k = idx_l[a]
                my_id = pres_ids_l[a]
                if direct and not (async_clocks and k in delivery.backlog):
                    # the plain model: every neighbor broadcast, no message faults
                    msgs, delivered = dict(zip(nb_ids[a], map(get_msg, nb_slots[a]))), None
                else:
                    msgs, delivered = delivery.receive(t, k, my_id, nb_ids[a], nb_slots[a], nb_rel[a])
                own = None
                if global_sensing:
                    own = poses[k].copy()
                    own.setflags(write=False)
                obs = _new_observation(t, None if anonymous else my_id,
                                       None if anonymous else nb_ids[a],
                                       nb_rel[a][:, :2] if anonymous else nb_rel[a], msgs, own)
                if delivered is not None:
                    obs.__dict__["delivered"] = delivered
                if async_clocks:
                    obs.__dict__["clock"] = float(tau0[a])
                calling = k
                cmd = controllers[k].step(obs)
                calling = None
                if grid:
                    moves_l[a] = mover.command(cmd, my_id, t)
                else:
                    tu, fw = _command_values(cmd, my_id, t)
                    turns_l[a] = tu
                    fwds_l[a] = fw
                if async_clocks:
                    outbox[k] = cmd.message
                else:
                    new_msgs[k] = cmd.message
            if not repeat_ok:
                delivery.end(t, events)
            if async_clocks:
                for a, k in enumerate(idx_l):
                    if bcast[a]:
                        new_msgs[k] = outbox[k]

            # 5. motion
            same_poses = mover.apply(poses, idx, moves_l if grid else (turns_l, fwds_l), pres_ids, t, events,
                                     record_clamps)
            t += 1
            record = rec.keeps(t, events, n_events)
            if record:
                rec.frame(t, poses, present)
            # Unchanged states are stored as the previous object (a trace of a long
            # run keeps one copy per change, not one per step); equal values, same trace.
            # (With repeat_step only the robots that stepped are asked: repeating leaves
            # a state as it was.)
            changed = False
            merged = list(states)
            for k in range(n_total) if stepped is None else stepped:
                c = controllers[k]
                calling = k
                st = None if c is None or not present[k] else c.state()
                calling = None
                if st is not states[k] and not st == states[k]:
                    merged[k] = st
                    changed = True
            new_states = tuple(merged) if changed else states
            rec.after_step(record, new_states, new_msgs, idx_l, ids_list)
            for ob in observers:
                ob.observe(t, _ro(poses), new_states, _ro(present))
            if async_clocks:
                # broadcasts come and go with the clocks; what a robot would say is its outbox
                quiet_step = not changed and same_poses and outbox == last_outbox
                last_outbox = list(outbox)
            else:
                quiet_step = not changed and same_poses and new_msgs == last_msgs
            heard_msgs = last_msgs
            idx_l_prev = idx_l
            last_msgs = new_msgs
            states = new_states
            quiet = quiet + 1 if quiet_step else 0
            if progress is not None and t % PROGRESS_EVERY == 0:
                progress(t, max_steps)
            # (finished depends on the states alone: unchanged states, same answer)
            calling = -1
            done = (changed or not repeat_ok) and algorithm.finished(tuple(s for s, p in zip(states, present) if p))
            calling = None
            if done:
                status = "finished"
                break
            if window and quiet >= window:
                status = "static"
                break
            if stop_when is not None and stop_when(t, poses, states, present):
                status = "stopped"
                break
        if progress is not None:
            progress(t, max_steps)
    except SwarmproofError:
        raise
    except Exception as exc:  # noqa: BLE001 - only what the algorithm under test raised
        if calling is None:
            raise                      # the engine's own bug: not the algorithm's
        crash = _crash_record(exc, calling, t, ids_list, anonymous)
        status = "crashed"
        events.append(Event(t, "algorithm_crash", () if crash["robot"] is None else (crash["robot"],),
                            (("error", crash["error"]), ("message", crash["message"]))))
        if rec is None:
            rec = Recording(1, poses, None, False)
            states = tuple([None] * len(ids_list))
            rec.states.append(states)
        if window is None:
            window = 0
        if max_steps is None:
            max_steps = 0
    rec.finish(t, poses, present, states)

    meta = run_meta(algorithm, lattice, params, seed, status, t, max_steps, window, broken, faults, clocks,
                    {"grid_spacing": mover.spacing, **mover.describe()} if grid else None, record_every, crash)
    trace = rec.trace(ids, events, meta)
    return SimulationResult(status=status, steps=t, trace=trace, broken_assumptions=tuple(broken),
                            seed=seed, static_window=window, max_steps=max_steps, observers=observers,
                            crash=crash)
