"""The deterministic simulation engine: it owns global poses, sensing, messages, motion and faults.

The model is that of 001 Sec. III-A (and 000 Sec. III-A): n robots with
unique comparable IDs and poses in a global frame that only the engine
knows; time runs in synchronous steps of ``dt``.  In every step:

1. *Faults (start of step)*: robots crash or join (:class:`FaultModel`),
   and the schedule picks which robots act (all of them by default).
2. *Sensing*: every robot senses the IDs and body-frame poses of the robots
   strictly closer than phi (:func:`swarmproof.models.sensing.neighbor_pairs`,
   one ``cKDTree`` per step), in increasing ID order.  Anonymous models see
   every robot, without IDs, ordered by body-frame ``(x, y)``.
3. *Messages*: every robot receives the messages its current neighbors
   broadcast in the previous step (``communication="all"``: from every
   robot; ``"none"``: nothing).
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
5. *Motion* (vectorized): differential drive, turn in place then drive
   straight: ``|turn|`` is clamped to ``omega*dt`` and ``forward`` to
   ``[0, v*(dt - |turn|/omega)]`` (docs/decisions.md "Model and geometry");
   a clamp is recorded as an ``Event(kind="clamp")``.

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
from collections.abc import Mapping as _MappingABC
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from swarmproof.models.errors import AssumptionError, ProtocolError, UsageError, check_type
from swarmproof.models.sensing import neighbor_pairs
from swarmproof.models.se2 import wrap_angle
from swarmproof.models.trace import Event, InitialConfiguration, Trace, to_jsonable

from .protocol import Command, Observation, Params

__all__ = [
    "simulate", "SimulationResult", "Trace", "FaultModel", "TableSchedule", "DropSet", "default_max_steps",
    "default_static_window", "ENGINE_ASSUMPTIONS",
]

#: The engine's own assumption names (checked before every run).
ENGINE_ASSUMPTIONS = ("unique_ids",)

#: How often (in steps) the progress callback is called.
PROGRESS_EVERY = 50


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


@dataclass(frozen=True)
class FaultModel:
    """Hook points for faults (issue 6); every field is optional.

    Attributes
    ----------
    schedule : callable ``(step, ids, rng) -> mask``, optional
        Which robots act in this step (asynchronous activation).  ``ids`` are
        the IDs of the present robots in slot order; return a boolean array of
        the same length.  A robot that does not act neither moves nor
        broadcasts in that step (its neighbors hear nothing from it next step)
        and its controller is not called.
    crashes : mapping ``step -> IDs``
        Robots that crash at the start of that step: they vanish (no longer
        sensed, no messages, no motion); their trace slot keeps the last pose
        with ``present=False``.
    additions : mapping ``step -> [(id, [x, y, theta]), ...]``
        Robots that join at the start of that step with a fresh controller.
    drop_message : callable ``(step, sender_id, receiver_id, rng) -> bool``, optional
        True drops that delivery.
    message_loss : float
        Probability that each delivery is lost (drawn from the fault
        generator), applied after ``drop_message``.
    sensing_noise : callable ``(step, robot_id, rel, rng) -> rel``, optional
        Perturb the ``(k, 3)`` body-frame poses a robot senses (return a new array).
    noise_std : (float, float)
        Gaussian noise standard deviations on sensed (x, y) and theta.
    message_delay : int
        Each delivery (after loss) arrives 0..``message_delay`` steps late,
        drawn uniformly per delivery.
    message_duplication : float
        Probability that a delivery arrives twice (both copies with the same delay).
    message_reorder : bool
        Each robot's deliveries of a step are shuffled (``Observation.inbox``
        order; ``messages`` keeps the last one per sender).

    Every random draw uses the fault generator, spawned from the run's seed,
    so a run with the same fault model and seed -- a replay -- is bit-identical;
    late and duplicated deliveries are recorded as ``late_delivery`` events.
    """

    schedule: Callable[[int, np.ndarray, np.random.Generator], Any] | None = None
    crashes: Mapping[int, Sequence[int]] = field(default_factory=dict)
    additions: Mapping[int, Sequence[tuple[int, Sequence[float]]]] = field(default_factory=dict)
    drop_message: Callable[[int, int, int, np.random.Generator], bool] | None = None
    message_loss: float = 0.0
    sensing_noise: Callable[[int, int, np.ndarray, np.random.Generator], np.ndarray] | None = None
    noise_std: tuple[float, float] = (0.0, 0.0)
    message_delay: int = 0
    message_duplication: float = 0.0
    message_reorder: bool = False

    def __post_init__(self) -> None:
        for name in ("message_loss", "message_duplication"):
            p = getattr(self, name)
            if isinstance(p, bool) or not isinstance(p, (int, float)) or not 0.0 <= float(p) <= 1.0:
                raise UsageError(f"{name}={p!r} must be a number in [0, 1]")
        d = self.message_delay
        if isinstance(d, bool) or not isinstance(d, (int, np.integer)) or d < 0:
            raise UsageError(f"message_delay={d!r} must be an integer >= 0 (steps)")
        for k, s in enumerate(self.noise_std):
            if not (math.isfinite(float(s)) and float(s) >= 0):
                raise UsageError(f"noise_std[{k}]={s!r} must be a finite number >= 0")

    @property
    def drops_messages(self) -> bool:
        return self.drop_message is not None or self.message_loss > 0

    @property
    def late_messages(self) -> bool:
        """Deliveries may come late, twice or out of order."""
        return self.message_delay > 0 or self.message_duplication > 0 or bool(self.message_reorder)

    @property
    def noisy(self) -> bool:
        return self.sensing_noise is not None or any(float(s) > 0 for s in self.noise_std)

    def broken_model_assumptions(self, model) -> list[str]:
        """Names of the robot-model assumptions this fault model breaks."""
        out = []
        if self.schedule is not None and getattr(model, "clocks", "sync") == "sync":
            out.append("synchronous_clocks")
        if any(self.crashes.values()):
            out.append("no_crashes")
        if any(self.additions.values()):
            out.append("fixed_robot_set")
        if self.drops_messages:
            out.append("reliable_messages")
        if self.noisy:
            out.append("exact_sensing")
        if self.message_delay > 0:
            out.append("timely_messages")
        if self.message_duplication > 0:
            out.append("messages_delivered_once")
        if self.message_reorder:
            out.append("ordered_messages")
        return out

    def describe(self) -> dict:
        """JSON-friendly summary for traces, reports and counterexample files.

        Data-driven hooks (:class:`TableSchedule`, :class:`DropSet`) are written
        as their data, so :meth:`from_dict` rebuilds the same fault model;
        other callables are written by name only (not replayable).
        """
        def hook(f):
            if f is None:
                return None
            if hasattr(f, "as_dict"):
                return f.as_dict()
            return {"kind": "callable", "name": getattr(f, "__name__", type(f).__name__)}

        out = {
            "schedule": hook(self.schedule),
            "crashes": {str(k): [int(i) for i in v] for k, v in sorted(self.crashes.items())},
            "additions": {str(k): [[int(i), [float(x) for x in p]] for i, p in v]
                          for k, v in sorted(self.additions.items())},
            "drop_message": hook(self.drop_message),
            "message_loss": float(self.message_loss),
            "sensing_noise": hook(self.sensing_noise),
            "noise_std": [float(s) for s in self.noise_std],
        }
        # written only when used, so the files of earlier fault models stay as they were
        if self.message_delay:
            out["message_delay"] = int(self.message_delay)
        if self.message_duplication:
            out["message_duplication"] = float(self.message_duplication)
        if self.message_reorder:
            out["message_reorder"] = True
        return out

    @staticmethod
    def from_dict(d: Mapping) -> "FaultModel":
        """Rebuild a fault model written by :meth:`describe` (data-driven hooks only).

        Raises
        ------
        UsageError
            A hook given only by name (a Python callable cannot be rebuilt from JSON).

        Examples
        --------
        >>> f = FaultModel(schedule=TableSchedule({2: (1, 3)}), drop_message=DropSet({(0, 1, 3)}),
        ...                crashes={4: [3]}, noise_std=(0.01, 0.0))
        >>> FaultModel.from_dict(f.describe()).describe() == f.describe()
        True
        """
        def hook(v, name):
            if v is None:
                return None
            kind = v.get("kind") if isinstance(v, Mapping) else None
            if kind == "table_schedule":
                return TableSchedule.from_dict(v)
            if kind == "drop_set":
                return DropSet.from_dict(v)
            raise UsageError(f"faults.{name}={v!r} cannot be rebuilt from data",
                             fix="use TableSchedule / DropSet for replayable faults")

        try:
            return FaultModel(
                schedule=hook(d.get("schedule"), "schedule"),
                crashes={int(k): [int(i) for i in v] for k, v in dict(d.get("crashes") or {}).items()},
                additions={int(k): [(int(i), [float(x) for x in p]) for i, p in v]
                           for k, v in dict(d.get("additions") or {}).items()},
                drop_message=hook(d.get("drop_message"), "drop_message"),
                message_loss=float(d.get("message_loss", 0.0)),
                sensing_noise=hook(d.get("sensing_noise"), "sensing_noise"),
                noise_std=tuple(float(x) for x in d.get("noise_std", (0.0, 0.0))),
                message_delay=int(d.get("message_delay", 0)),
                message_duplication=float(d.get("message_duplication", 0.0)),
                message_reorder=bool(d.get("message_reorder", False)),
            )
        except (TypeError, ValueError, AttributeError) as exc:
            if isinstance(exc, UsageError):
                raise
            raise UsageError(f"faults={dict(d)!r} is malformed ({exc})") from None


@dataclass(frozen=True)
class TableSchedule:
    """A replayable asynchronous schedule: ``table[step]`` lists the IDs that act.

    Steps missing from the table let every present robot act.

    >>> s = TableSchedule({1: (2,)})
    >>> s(1, np.array([1, 2, 3]), None).tolist(), s(0, np.array([1, 2]), None).tolist()
    ([False, True, False], [True, True])
    """

    table: Mapping[int, Sequence[int]]

    __name__ = "table_schedule"

    def __call__(self, step, ids, rng):
        act = self.table.get(int(step))
        if act is None:
            return np.ones(len(ids), dtype=bool)
        return np.isin(ids, np.asarray(list(act), dtype=np.int64))

    def as_dict(self) -> dict:
        return {"kind": "table_schedule",
                "table": {str(k): sorted(int(i) for i in v) for k, v in sorted(self.table.items())}}

    @staticmethod
    def from_dict(d: Mapping) -> "TableSchedule":
        return TableSchedule({int(k): tuple(int(i) for i in v) for k, v in dict(d["table"]).items()})


@dataclass(frozen=True)
class DropSet:
    """Replayable lost messages: the deliveries ``(step, sender_id, receiver_id)`` in ``drops``.

    >>> DropSet({(3, 1, 2)})(3, 1, 2, None), DropSet({(3, 1, 2)})(3, 2, 1, None)
    (True, False)
    """

    drops: frozenset | set

    __name__ = "drop_set"

    def __call__(self, step, sender, receiver, rng) -> bool:
        return (int(step), int(sender), int(receiver)) in self.drops

    def as_dict(self) -> dict:
        return {"kind": "drop_set", "drops": sorted([int(a), int(b), int(c)] for a, b, c in self.drops)}

    @staticmethod
    def from_dict(d: Mapping) -> "DropSet":
        return DropSet(frozenset((int(a), int(b), int(c)) for a, b, c in d["drops"]))


@dataclass
class SimulationResult:
    """What :func:`simulate` returns.

    Attributes
    ----------
    status : str
        ``"finished"`` (the algorithm's own end condition), ``"static"``
        (quiet for ``static_window`` steps), ``"step_cap"`` (inconclusive) or
        ``"stopped"`` (a ``stop_when`` monitor ended the run).
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
    """

    status: str
    steps: int
    trace: Trace
    broken_assumptions: tuple[str, ...]
    seed: int
    static_window: int
    max_steps: int
    observers: tuple = ()

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


def _check_params(params: Params) -> None:
    if not isinstance(params, Params):
        raise UsageError(f"params={params!r} must be a Params", fix="build it with Params(range=...)")
    for name in ("range", "omega", "dt"):
        v = getattr(params, name)
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise UsageError(f"params.{name}={v!r} must be a finite number > 0")
    if not (isinstance(params.v, (int, float)) and math.isfinite(params.v) and params.v >= 0):
        raise UsageError(f"params.v={params.v!r} must be a finite number >= 0")


def _rel_rows(frames: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Row-wise ``frames[k]^-1 @ poses[k]`` (same formulas as ``se2.relative_many``)."""
    c = np.cos(frames[:, 2])
    s = np.sin(frames[:, 2])
    dx = poses[:, 0] - frames[:, 0]
    dy = poses[:, 1] - frames[:, 1]
    out = np.empty_like(poses)
    out[:, 0] = c * dx + s * dy
    out[:, 1] = -s * dx + c * dy
    out[:, 2] = wrap_angle(poses[:, 2] - frames[:, 2])
    return out


_OBS_FIELDS = ("step", "robot_id", "neighbor_ids", "neighbor_poses", "messages", "own_pose")


def _new_observation(step, robot_id, neighbor_ids, neighbor_poses, messages, own_pose) -> Observation:
    """Build a frozen Observation without the dataclass ``__init__`` overhead (hot path).

    Equivalent to ``Observation(step, robot_id, ...)``: the object is the same
    frozen dataclass (assignment still raises), only its fields are filled directly.
    """
    obs = object.__new__(Observation)
    d = obs.__dict__
    d["step"] = step
    d["robot_id"] = robot_id
    d["neighbor_ids"] = neighbor_ids
    d["neighbor_poses"] = neighbor_poses
    d["messages"] = messages
    d["own_pose"] = own_pose
    return obs


class _AllBut(_MappingABC):
    """Read-only view of one step's broadcasts without the receiver's own (``communication="all"``):
    built once per step and shared, so delivery costs O(n) per step, not O(n^2)."""

    __slots__ = ("_base", "_own")

    def __init__(self, base: dict, own) -> None:
        self._base, self._own = base, own

    def __getitem__(self, key):
        if key == self._own:
            raise KeyError(key)
        return self._base[key]

    def __iter__(self):
        own = self._own
        return (k for k in self._base if k != own)

    def __len__(self) -> int:
        return len(self._base) - (self._own in self._base)

    def __contains__(self, key) -> bool:
        return key != self._own and key in self._base

    def __repr__(self) -> str:
        return repr(dict(self.items()))


def _deliver_pending(pending: dict, k: int, t: int, reorder: bool, rng) -> tuple[dict, tuple]:
    """The deliveries due at step ``t`` for receiver slot ``k`` (removed from ``pending``):
    ``(messages by sender ID, ((sender slot, message), ...) in delivery order)``.

    Due deliveries come in (due step, sending order); ``reorder`` shuffles them
    with the fault generator.  ``messages`` keeps each sender's last delivery.
    """
    box = pending.get(k)
    if not box:
        return {}, ()
    due = [e for e in box if e[0] <= t]
    if not due:
        return {}, ()
    pending[k] = [e for e in box if e[0] > t]
    due.sort(key=lambda e: (e[0], e[1]))
    if reorder and len(due) > 1:
        due = [due[i] for i in rng.permutation(len(due)).tolist()]
    return {e[3]: e[4] for e in due}, tuple((e[2], e[4]) for e in due)


def _ro(a: np.ndarray) -> np.ndarray:
    """A read-only view (observers must not change the engine's arrays)."""
    v = a.view()
    v.setflags(write=False)
    return v


def _extra_number(params: Params, key: str, default: float, *, positive: bool = True) -> float:
    val = params.extra.get(key, default) if params.extra else default
    if isinstance(val, bool) or not isinstance(val, (int, float)) or not math.isfinite(val) \
            or (positive and val <= 0):
        raise UsageError(f"params.extra[{key!r}]={val!r} must be a finite number > 0")
    return float(val)


def _grid_spacing(params: Params) -> float:
    """``motion="grid"``: the cell spacing, ``params.extra["grid_spacing"]`` (default 1)."""
    return _extra_number(params, "grid_spacing", 1.0)


def _snap_cells(poses: np.ndarray, spacing: float, ids, where: str) -> np.ndarray:
    """Integer cells of positions that lie on the grid (within 1e-9 of a spacing); else a usage error."""
    cells = np.rint(poses[:, :2] / spacing).astype(np.int64)
    off = np.abs(poses[:, :2] - cells * spacing).max(axis=1) if len(poses) else np.zeros(0)
    bad = np.flatnonzero(off > 1e-9 * spacing)
    if len(bad):
        k = int(bad[0])
        raise UsageError(f"{where}: robot {ids[k]!r} at ({poses[k, 0]:.6g}, {poses[k, 1]:.6g}) is not on a "
                         f"grid cell (grid_spacing={spacing:g})",
                         fix="start grid robots on cells: integer multiples of the spacing")
    return cells


def _check_free_cells(cells: np.ndarray, ids) -> None:
    seen: dict = {}
    for k, c in enumerate(map(tuple, cells.tolist())):
        if c in seen:
            raise UsageError(f"robots {ids[seen[c]]!r} and {ids[k]!r} start on one cell {c}",
                             fix="give every grid robot its own cell")
        seen[c] = k


_GRID_MOVES = ((1, 0), (-1, 0), (0, 1), (0, -1))


def _grid_move(cmd: Any, robot_id, step: int):
    """The move of a grid robot's command: None (wait) or a unit step; a malformed one is a ProtocolError."""
    if not isinstance(cmd, Command):
        raise ProtocolError(f"controller of robot {robot_id!r} returned {cmd!r} at step {step}, "
                            "expected a Command")
    if cmd.turn or cmd.forward:
        raise ProtocolError(f"robot {robot_id!r} step {step}: grid motion takes Command(move=(dx, dy)), "
                            f"not turn={cmd.turn!r}, forward={cmd.forward!r}")
    mv = cmd.move
    if mv is None:
        return None
    try:
        mv = (int(mv[0]), int(mv[1])) if len(mv) == 2 and all(float(x).is_integer() for x in mv) else None
    except (TypeError, ValueError):
        mv = None
    if mv not in _GRID_MOVES:
        raise ProtocolError(f"robot {robot_id!r} step {step}: Command move={cmd.move!r} must be None or one of "
                            f"{list(_GRID_MOVES)!r}")
    return mv


def _grid_motion(poses, cells, edge, frac, idx, moves, grid_step, spacing, pres_ids, t, events) -> bool:
    """One step of grid motion for the present robots ``idx``; returns whether no pose changed.

    A robot at a cell that was given a move starts crossing that edge; a robot on an edge
    advances ``v dt / spacing`` of it and stops at the far cell when it gets there (it does
    not start the next edge in the same step, so within a step every robot moves along one
    straight segment: the collision property's exact minimum distance holds).  A position
    on an edge is ``(cell + frac * edge) * spacing``; at a cell it is exactly ``cell * spacing``.
    """
    changed = False
    started = []
    for a, k in enumerate(idx.tolist()):
        mv = moves[a] if a < len(moves) else None
        if mv is not None and not edge[k].any():
            edge[k] = mv
            frac[k] = 0.0
            started.append(int(pres_ids[a]))
        if not edge[k].any():
            continue
        f = frac[k] + grid_step
        if f >= 1.0:
            cells[k] += edge[k]
            edge[k] = 0
            frac[k] = 0.0
            poses[k, 0], poses[k, 1] = cells[k, 0] * spacing, cells[k, 1] * spacing
        else:
            frac[k] = f
            poses[k, 0] = (cells[k, 0] + f * edge[k, 0]) * spacing
            poses[k, 1] = (cells[k, 1] + f * edge[k, 1]) * spacing
        changed = True
    if started:
        events.append(Event(t, "edge", tuple(started)))
    return not changed


def _draw_clocks(params: Params, n: int, seed: int):
    """``clocks="async"``: per-robot phase in [0, 1) and rate in ``[clock_rate_min,
    clock_rate_max]`` (``params.extra``, default 1 each), drawn from the run's seed (a
    generator of their own, so the robots' and the faults' draws are untouched), and the
    broadcast interval ``broadcast_every`` (local time units, default 1)."""
    lo = _extra_number(params, "clock_rate_min", 1.0)
    hi = _extra_number(params, "clock_rate_max", lo)
    if hi < lo:
        raise UsageError(f"params.extra clock_rate_max={hi!r} < clock_rate_min={lo!r}",
                         fix="give clock_rate_min <= clock_rate_max")
    every = _extra_number(params, "broadcast_every", 1.0)
    crng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2,)))
    phase = crng.uniform(0.0, 1.0, n)
    rate = crng.uniform(lo, hi, n) if hi > lo else np.full(n, lo)
    return phase, rate, every


def _robot_rng(seed: int, slot: int) -> np.random.Generator:
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(0, slot)))


def _command_values(cmd: Any, robot_id, step: int) -> tuple[float, float]:
    """``(turn, forward)`` of a controller's command, checked (fast for well-formed ones)."""
    if type(cmd) is Command:  # fast path; anything unusual gets the full check
        tu, fw = cmd.turn, cmd.forward
        if (type(tu) is float and type(fw) is float and fw >= 0.0
                and tu - tu == 0.0 and fw - fw == 0.0):
            return tu, fw
    return _check_command(cmd, robot_id, step)


def _check_command(cmd: Any, robot_id, step: int) -> tuple[float, float]:
    if not isinstance(cmd, Command):
        raise ProtocolError(f"controller of robot {robot_id!r} returned {cmd!r} at step {step}, "
                            "expected a Command")
    try:
        turn = float(cmd.turn)
        fwd = float(cmd.forward)
    except (TypeError, ValueError):
        raise ProtocolError(f"robot {robot_id!r} step {step}: Command turn={cmd.turn!r}, "
                            f"forward={cmd.forward!r} must be numbers") from None
    if not (math.isfinite(turn) and math.isfinite(fwd)):
        raise ProtocolError(f"robot {robot_id!r} step {step}: Command turn={turn!r}, "
                            f"forward={fwd!r} must be finite")
    if fwd < 0:
        raise ProtocolError(f"robot {robot_id!r} step {step}: Command forward={fwd!r} must be >= 0 "
                            "(turn first, then drive forward)")
    return turn, fwd


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
        clamp, and the last step (``trace.times`` lists them), so a long run
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
    events: list[Event] = []
    broken: list[str] = []

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
        msg = a.check(params, n0, None if anonymous else ids0)
        if msg is None and a.check_start is not None:
            msg = a.check_start(params, None if anonymous else ids0, initial.poses.copy())
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

    grid = model.motion == "grid"
    if grid:
        spacing = _grid_spacing(params)
        cells = np.zeros((n_total, 2), dtype=np.int64)
        cells[:n0] = _snap_cells(poses[:n0], spacing, ids_list[:n0], "initial")
        _check_free_cells(cells[:n0], ids_list[:n0])
        poses[:n0, :2] = cells[:n0] * spacing
        poses[:, 2] = 0.0
        edge = np.zeros((n_total, 2), dtype=np.int64)   # the edge a robot is crossing (0, 0: at a cell)
        frac = np.zeros(n_total)                         # how far along it, in [0, 1)
        grid_step = params.v * params.dt / spacing
    async_clocks = model.clocks == "async"
    if async_clocks:
        clock_phase, clock_rate, bcast_every = _draw_clocks(params, n_total, seed)
        outbox: list = [None] * n_total
        last_outbox: list = [None] * n_total
    fault_rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(1,)))
    controllers: list = [None] * n_total
    for k in range(n0):
        controllers[k] = algorithm.controller(None if anonymous else ids_list[k], params, lattice,
                                              _robot_rng(seed, k))

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
    times = [0] if record_every > 1 else None
    pose_hist = [poses.copy()]
    present_hist = [present.copy()] if any_presence_change else None
    states = _states()
    for k, st in enumerate(states):
        try:
            hash(st)
        except TypeError:
            raise ProtocolError(f"controller of robot {ids_list[k]!r}: state() returned an unhashable "
                                f"{type(st).__name__} ({st!r:.80}); return tuples of (key, value) "
                                "pairs, a namedtuple or a frozen dataclass") from None
    state_hist = [states]
    msg_hist: list | None = [] if record_messages else None
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
    max_turn = params.omega * params.dt
    differential = model.motion == "differential"
    global_sensing = model.sensing == "global"
    comm = model.communication
    std_xy, std_th = (float(s) for s in faults.noise_std)
    drops = faults.drops_messages
    noisy = faults.noisy
    inclusive = model.neighbor_rule == "inclusive"
    late = faults.late_messages
    max_delay = int(faults.message_delay)
    dup_p = float(faults.message_duplication)
    pending: dict = {}   # receiver slot -> [(due step, seq, sender slot, sender id, message)]
    seq = 0
    status = "step_cap"
    quiet = 0
    finished = bool(algorithm.finished(tuple(s for s, p in zip(states, present) if p)))
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
                    pending.pop(k, None)
                    events.append(Event(t, "crash", (int(rid),)))
        for slot, p in slot_of_add.get(t, ()):
            poses[slot] = p
            poses[slot, 2] = wrap_angle(p[2])
            if grid:
                cells[slot] = _snap_cells(poses[slot:slot + 1], spacing, [ids_list[slot]], f"additions[{t}]")[0]
                poses[slot, :2] = cells[slot] * spacing
                poses[slot, 2] = 0.0
            present[slot] = True
            controllers[slot] = algorithm.controller(None if anonymous else ids_list[slot], params,
                                                     lattice, _robot_rng(seed, slot))
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
            tau0 = clock_phase[idx] + clock_rate[idx] * t
            tau1 = tau0 + clock_rate[idx]
            act &= np.floor(tau1) > np.floor(tau0)
            bcast = np.floor((tau1 + 0.5) / bcast_every) > np.floor((tau0 + 0.5) / bcast_every)

        # 2. sensing (vectorized).  Sensing is a pure function of the present robots'
        #    poses, so when none of them changed since the last sensing (bit for bit) the
        #    last result is reused; noise is drawn afresh every step, so never with noise.
        pp = poses[idx]
        pp_bytes = pp.tobytes()
        if (sensed is not None and not noisy and sensed[1] == pp_bytes
                and np.array_equal(sensed[0], idx)):
            nb_ids, nb_slots, nb_rel = sensed[2]
        else:
            if anonymous:
                ii, jj = np.meshgrid(np.arange(m), np.arange(m), indexing="ij")
                mask = ii != jj
                src, dst = ii[mask], jj[mask]
                rel = _rel_rows(pp[src], pp[dst])
                order = np.lexsort((rel[:, 1], rel[:, 0], src))
            else:
                i, j, _ = neighbor_pairs(pp[:, :2], phi, inclusive)
                src = np.concatenate((i, j))
                dst = np.concatenate((j, i))
                order = np.lexsort((pres_ids[dst], src))
                rel = None
            src = src[order]
            dst = dst[order]
            rel = _rel_rows(pp[src], pp[dst]) if rel is None else rel[order]
            off = np.zeros(m + 1, dtype=np.intp)
            np.cumsum(np.bincount(src, minlength=m), out=off[1:])
            if noisy:
                for a in range(m):
                    lo, hi = off[a], off[a + 1]
                    if hi == lo:
                        continue
                    block = rel[lo:hi]
                    if std_xy > 0 or std_th > 0:
                        block = block + np.column_stack((
                            fault_rng.normal(0.0, std_xy, (hi - lo, 2)) if std_xy > 0 else np.zeros((hi - lo, 2)),
                            fault_rng.normal(0.0, std_th, hi - lo) if std_th > 0 else np.zeros(hi - lo)))
                        block[:, 2] = wrap_angle(block[:, 2])
                    if faults.sensing_noise is not None:
                        block = np.asarray(faults.sensing_noise(t, int(pres_ids[a]), block.copy(), fault_rng),
                                           dtype=float)
                        if block.shape != (hi - lo, 3):
                            raise UsageError(f"faults.sensing_noise returned shape={block.shape!r}, "
                                             f"expected ({hi - lo}, 3)")
                    rel[lo:hi] = block
            rel.setflags(write=False)
            dst_slots = idx[dst]
            dst_ids = ids[dst_slots].tolist()
            dst_slots_l = dst_slots.tolist()
            off_l = off.tolist()
            nb_ids = [tuple(dst_ids[off_l[a]:off_l[a + 1]]) for a in range(m)]
            nb_slots = [dst_slots_l[off_l[a]:off_l[a + 1]] for a in range(m)]
            nb_rel = [rel[off_l[a]:off_l[a + 1]] for a in range(m)]
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
        dropped = []
        idx_l = idx.tolist()
        pres_ids_l = pres_ids.tolist()
        all_senders = [(ids_list[s], s) for s in idx_l] if comm == "all" else None
        all_msgs = ({sid: last_msgs[s] for sid, s in all_senders if last_msgs[s] is not None}
                    if comm == "all" and not (drops or late or anonymous) else None)
        late_log = [] if late else None
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
                cmd = repeaters[k](t) if same_obs is not None and same_obs[a] else None
                if cmd is None:
                    msgs = (dict(zip(nb_ids[a], map(get_msg, nb_slots[a]))) if not silent else
                            {sid: last_msgs[s] for sid, s in zip(nb_ids[a], nb_slots[a])
                             if last_msgs[s] is not None})
                    cmd = controllers[k].step(_new_observation(t, pres_ids_l[a], nb_ids[a], nb_rel[a],
                                                               msgs, None))
                    stepped.append(k)
                if cmd is not last_cmds[k]:
                    turns_l[a], fwds_l[a] = _command_values(cmd, pres_ids_l[a], t)
                    new_msgs[k] = cmd.message
                    last_cmds[k] = cmd
                hold[a] = t + 1 if horizons[k] is None else horizons[k](t)
        else:
            turns_l = [0.0] * m
            fwds_l = [0.0] * m
            moves_l = [None] * m
            new_msgs = [None] * n_total
            stepped = None
        # the general path: any model, fault hooks (empty when repeat_ok)
        for a in (range(0) if repeat_ok else range(m)):
            if not act_l[a]:
                continue
            k = idx_l[a]
            my_id = pres_ids_l[a]
            delivered = None
            if all_msgs is not None:
                heard = None
                msgs = _AllBut(all_msgs, my_id)
            elif comm == "none":
                heard = ()
            elif comm == "all":
                heard = [(sid, s) for sid, s in all_senders if s != k]
            elif anonymous:
                # anonymous robots sense everyone; they hear the ones in range
                d = np.hypot(nb_rel[a][:, 0], nb_rel[a][:, 1])
                near = (d <= phi) if inclusive else (d < phi)
                heard = [(ids_list[s], s) for s, ok in zip(nb_slots[a], near.tolist()) if ok]
            elif not drops and not silent and not late:
                heard = None
                msgs = dict(zip(nb_ids[a], map(get_msg, nb_slots[a])))
            else:
                heard = zip(nb_ids[a], nb_slots[a])
            if heard is None:
                pass
            elif not drops and not late:
                msgs = {s if anonymous else sid: last_msgs[s] for sid, s in heard if last_msgs[s] is not None}
            else:
                msgs = {}
                for sid, s in heard:
                    msg = last_msgs[s]
                    if msg is None:
                        continue
                    if faults.drop_message is not None and faults.drop_message(t, sid, my_id, fault_rng):
                        dropped.append((sid, my_id))
                        continue
                    if faults.message_loss > 0 and fault_rng.random() < faults.message_loss:
                        dropped.append((sid, my_id))
                        continue
                    if late:
                        delay = int(fault_rng.integers(0, max_delay + 1)) if max_delay else 0
                        copies = 2 if dup_p > 0 and fault_rng.random() < dup_p else 1
                        box = pending.setdefault(k, [])
                        for _ in range(copies):
                            box.append((t + delay, seq, s, sid, msg))
                            seq += 1
                        if delay or copies > 1:
                            late_log.append((sid, my_id, t + delay, copies))
                    else:
                        msgs[s if anonymous else sid] = msg
            if late:
                msgs, delivered = _deliver_pending(pending, k, t, faults.message_reorder, fault_rng)
            if anonymous:
                # no sender IDs: a message is keyed by the row of neighbor_poses its sender is
                # sensed at (messages of robots not sensed now are in the inbox only)
                row = {s: r for r, s in enumerate(nb_slots[a])}
                if delivered is None:   # msgs is keyed by sender slot here
                    delivered = tuple((None, m_) for m_ in msgs.values())
                    msgs = {row[s_]: m_ for s_, m_ in msgs.items() if s_ in row}
                else:
                    msgs = {row[s_]: m_ for s_, m_ in delivered if s_ in row}
                    delivered = tuple((None, m_) for _, m_ in delivered)
            elif delivered is not None:
                delivered = tuple((ids_list[s_], m_) for s_, m_ in delivered)
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
            cmd = controllers[k].step(obs)
            if grid:
                moves_l[a] = _grid_move(cmd, my_id, t)
            else:
                tu, fw = _command_values(cmd, my_id, t)
                turns_l[a] = tu
                fwds_l[a] = fw
            if async_clocks:
                outbox[k] = cmd.message
            else:
                new_msgs[k] = cmd.message
        if dropped:
            events.append(Event(t, "drop", (), (("deliveries", tuple(dropped)),)))
        if late_log:
            events.append(Event(t, "late_delivery", (), (("deliveries", tuple(late_log)),)))
        if async_clocks:
            for a, k in enumerate(idx_l):
                if bcast[a]:
                    new_msgs[k] = outbox[k]

        # 5. motion
        if grid:
            same_poses = _grid_motion(poses, cells, edge, frac, idx, moves_l, grid_step, spacing,
                                      pres_ids, t, events)
            turns_l = fwds_l = ()
        turns = np.array(turns_l, dtype=float)
        fwds = np.array(fwds_l, dtype=float)
        if grid:
            moving = np.zeros(0, dtype=bool)
        elif differential:
            tc = np.clip(turns, -max_turn, max_turn)
            limit = np.maximum(params.v * (params.dt - np.abs(tc) / params.omega), 0.0)
        else:  # holonomic: free turn, drive at most v*dt
            tc = turns
            limit = np.full(m, params.v * params.dt)
        if not grid:
            fc = np.minimum(fwds, limit)
            if record_clamps:
                clamped = (tc != turns) | (fc != fwds)
                if clamped.any():
                    events.append(Event(t, "clamp", tuple(pres_ids[clamped].tolist())))
            moving = (tc != 0) | (fc != 0)
            same_poses = True
        if moving.any():
            old = poses.copy()
            mv = idx[moving]
            th = wrap_angle(poses[mv, 2] + tc[moving])
            poses[mv, 0] += fc[moving] * np.cos(th)
            poses[mv, 1] += fc[moving] * np.sin(th)
            poses[mv, 2] = th
            same_poses = np.array_equal(old, poses)
        t += 1
        record = times is None or t % record_every == 0 or any(
            e.kind != "clamp" for e in events[n_events:])
        if record:
            pose_hist.append(poses.copy())
            if present_hist is not None:
                present_hist.append(present.copy())
            if times is not None:
                times.append(t)
        # Unchanged states are stored as the previous object (a trace of a long
        # run keeps one copy per change, not one per step); equal values, same trace.
        # (With repeat_step only the robots that stepped are asked: repeating leaves
        # a state as it was.)
        changed = False
        merged = list(states)
        for k in range(n_total) if stepped is None else stepped:
            c = controllers[k]
            st = None if c is None or not present[k] else c.state()
            if st is not states[k] and not st == states[k]:
                merged[k] = st
                changed = True
        new_states = tuple(merged) if changed else states
        if record:
            state_hist.append(new_states)
            if msg_hist is not None:
                msg_hist.append({ids_list[k]: new_msgs[k] for k in idx_l if new_msgs[k] is not None})
        elif msg_hist is not None:
            last_unrecorded_msgs = {ids_list[k]: new_msgs[k] for k in idx_l if new_msgs[k] is not None}
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
        if (changed or not repeat_ok) and algorithm.finished(tuple(s for s, p in zip(states, present) if p)):
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
    if times is not None and times[-1] != t:      # a sparse trace always ends with the last step
        times.append(t)
        pose_hist.append(poses.copy())
        if present_hist is not None:
            present_hist.append(present.copy())
        state_hist.append(states)
        if msg_hist is not None:
            msg_hist.append(last_unrecorded_msgs)

    meta = {
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
        **({"clocks": {"phase": [float(x) for x in clock_phase], "rate": [float(x) for x in clock_rate],
                       "broadcast_every": bcast_every}} if async_clocks else {}),
        **({"grid_spacing": spacing} if grid else {}),
        **({"record_every": record_every} if record_every > 1 else {}),
        "model": {"sensing": model.sensing, "communication": model.communication,
                  "motion": model.motion, "clocks": model.clocks,
                  "neighbor_rule": getattr(model, "neighbor_rule", "strict")},
    }
    trace = Trace(ids=ids, poses=np.stack(pose_hist), states=state_hist, events=events,
                  messages=msg_hist,
                  present=None if present_hist is None else np.stack(present_hist), meta=meta, times=times)
    return SimulationResult(status=status, steps=t, trace=trace, broken_assumptions=tuple(broken),
                            seed=seed, static_window=window, max_steps=max_steps, observers=observers)
