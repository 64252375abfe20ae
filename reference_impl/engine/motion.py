"""Motion models: differential drive, holonomic, and the engine's grid (issue 12).

* ``differential`` (000 Sec. III-A-3, 001 Sec. III-A): turn in place by at most
  ``omega dt``, then drive straight at most ``v (dt - |turn|/omega)``;
* ``holonomic``: a free turn, then at most ``v dt``;
* ``grid`` (004): integer cells of ``params.extra["grid_spacing"]``; a command is a
  move to a 4-neighbouring cell or a wait; an edge takes ``spacing / v``; positions
  are exact on the way and on arrival (DESIGN.md section 5, "Grid motion").  With
  ``params.extra["speed_min"] < params.extra["speed_max"]`` every grid robot has a speed of
  its own, drawn from the seed (004 Sec. V-B3: ``v_min <= v_m^i <= v_max``; :func:`grid_speeds`),
  and an edge takes it ``spacing / speed``.  The two keys are for grid robots only: other
  motion models refuse them (:func:`motion_model`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from swarmproof.models.errors import ProtocolError, UsageError
from swarmproof.models.se2 import wrap_angle
from swarmproof.models.trace import Event

from ..protocol import Command, Params
from .common import _extra_number


def _grid_spacing(params: Params) -> float:
    """``motion="grid"``: the cell spacing, ``params.extra["grid_spacing"]`` (default 1)."""
    return _extra_number(params, "grid_spacing", 1.0)


#: ``SeedSequence(seed, spawn_key=SPEED_SPAWN_KEY)`` draws the grid robots' speeds: a generator of
#: their own, beside the robots' ``(0, k)``, the faults' ``(1,)`` and the clocks' ``(2,)``.
SPEED_SPAWN_KEY = (3,)
SPEED_KEYS = ("speed_min", "speed_max")


def _speed_bound(params: Params, key: str) -> float:
    """``params.extra[key]`` (m/s), default ``params.v``; a usage error naming it if it is no
    finite number > 0."""
    ex = params.extra or {}
    if key not in ex:
        return float(params.v)
    val = ex[key]
    ok = (not isinstance(val, bool) and isinstance(val, (int, float, np.integer, np.floating))
          and math.isfinite(val) and val > 0)
    if not ok:
        raise UsageError(f"params.extra[{key!r}]={val!r} must be a finite speed > 0 (m/s)",
                         fix=f"give a positive number, e.g. --param {key}=0.05, or leave {key} out "
                             f"(default: v={params.v!r})")
    return float(val)


def grid_speeds(params: Params, n: int, seed: int | None):
    """The speeds of ``n`` grid robots: ``(speed_min, speed_max, speeds)``.

    004 Sec. V-B3 relaxes Sec. II-A d) ("each agent has the same v_m") to ``v_min <= v_m^i <=
    v_max``.  ``params.extra["speed_min"]`` and ``["speed_max"]`` (m/s) default to ``params.v``
    each.  When they are equal there is no random draw at all (``speeds`` is None: every robot
    moves at that speed, and a run is what it was before the keys existed); otherwise robot slot
    ``k`` gets ``speeds[k]``, uniform in ``[speed_min, speed_max]`` from
    ``numpy.random.default_rng(SeedSequence(seed, spawn_key=(3,)))`` (its own generator: the
    robots', faults' and clocks' draws are untouched).  A robot keeps its speed on every edge.

    Raises
    ------
    UsageError
        ``speed_min`` or ``speed_max`` not a finite number > 0, or ``speed_min > speed_max``, or
        ``speed_min < speed_max`` without a seed to draw from.

    Examples
    --------
    >>> from swarmproof.reference_impl.protocol import Params
    >>> grid_speeds(Params(range=1.0, v=0.05), 3, seed=0)
    (0.05, 0.05, None)
    >>> lo, hi, s = grid_speeds(Params(range=1.0, extra={"speed_min": 0.04, "speed_max": 0.06}), 3, seed=0)
    >>> bool(((0.04 <= s) & (s <= 0.06)).all()), len(s)
    (True, 3)
    >>> grid_speeds(Params(range=1.0, v=0.05, extra={"speed_max": 0.03}), 3, seed=0)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: params.extra speed_min=0.05 > speed_max=0.03; fix: give speed_min <= speed_max (each defaults to v=0.05)
    """
    lo, hi = _speed_bound(params, "speed_min"), _speed_bound(params, "speed_max")
    if lo > hi:
        raise UsageError(f"params.extra speed_min={lo!r} > speed_max={hi!r}",
                         fix=f"give speed_min <= speed_max (each defaults to v={params.v!r})")
    if lo == hi:
        return lo, hi, None
    if seed is None:
        raise UsageError(f"params.extra speed_min={lo!r} < speed_max={hi!r}: drawing the robots' speeds needs "
                         "the run's seed", fix="pass seed= (simulate passes the run's seed)")
    srng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=SPEED_SPAWN_KEY))
    return lo, hi, srng.uniform(lo, hi, n)


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
    advances ``v dt / spacing`` of it (``grid_step``: one number for all, or an array per slot
    when robots have speeds of their own, ``speed[k] dt / spacing``) and stops at the far cell when it gets there (it does
    not start the next edge in the same step, so within a step every robot moves along one
    straight segment: the collision property's exact minimum distance holds).  A position
    on an edge is ``(cell + frac * edge) * spacing``; at a cell it is exactly ``cell * spacing``.
    """
    changed = False
    started = []
    per_robot = np.ndim(grid_step) > 0
    for a, k in enumerate(idx.tolist()):
        mv = moves[a] if a < len(moves) else None
        if mv is not None and not edge[k].any():
            edge[k] = mv
            frac[k] = 0.0
            started.append(int(pres_ids[a]))
        if not edge[k].any():
            continue
        f = frac[k] + (grid_step[k] if per_robot else grid_step)
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


class ContinuousMotion:
    """``differential`` or ``holonomic`` motion: a command is (turn, forward)."""

    grid = False

    def __init__(self, params: Params, differential: bool) -> None:
        self.params, self.differential = params, differential
        self.max_turn = params.omega * params.dt

    def start(self, poses, n0: int, ids) -> None:
        """Nothing to set up: any pose is a valid start."""

    def add(self, slot: int, poses, robot_id, t: int) -> None:
        """A robot joining needs nothing either."""

    def command(self, cmd, robot_id, t: int):
        """``(turn, forward)`` of a checked command."""
        return _command_values(cmd, robot_id, t)

    def apply(self, poses, idx, commands, pres_ids, t: int, events, record_clamps: bool) -> bool:
        """Move the present robots ``idx`` by ``commands = (turns, forwards)`` (per present
        robot), clamped to the model's limits; returns whether no pose changed."""
        params = self.params
        turns = np.array(commands[0], dtype=float)
        fwds = np.array(commands[1], dtype=float)
        if self.differential:
            tc = np.clip(turns, -self.max_turn, self.max_turn)
            limit = np.maximum(params.v * (params.dt - np.abs(tc) / params.omega), 0.0)
        else:  # holonomic: free turn, drive at most v*dt
            tc = turns
            limit = np.full(len(idx), params.v * params.dt)
        fc = np.minimum(fwds, limit)
        if record_clamps:
            clamped = (tc != turns) | (fc != fwds)
            if clamped.any():
                events.append(Event(t, "clamp", tuple(pres_ids[clamped].tolist())))
        moving = (tc != 0) | (fc != 0)
        if not moving.any():
            return True
        old = poses.copy()
        mv = idx[moving]
        th = wrap_angle(poses[mv, 2] + tc[moving])
        poses[mv, 0] += fc[moving] * np.cos(th)
        poses[mv, 1] += fc[moving] * np.sin(th)
        poses[mv, 2] = th
        return np.array_equal(old, poses)


class GridMotion:
    """``grid`` motion: the engine's cells and edge crossings (module docstring).

    ``seed`` draws the robots' own speeds when ``speed_min < speed_max`` (:func:`grid_speeds`);
    without it such parameters are a usage error.
    """

    grid = True

    def __init__(self, params: Params, n_total: int, seed: int | None = None) -> None:
        self.spacing = _grid_spacing(params)
        self.cells = np.zeros((n_total, 2), dtype=np.int64)
        self.edge = np.zeros((n_total, 2), dtype=np.int64)   # the edge a robot is crossing (0, 0: at a cell)
        self.frac = np.zeros(n_total)                         # how far along it, in [0, 1)
        lo, hi, speeds = grid_speeds(params, n_total, seed)
        self.speed_min, self.speed_max, self.speeds = lo, hi, speeds
        if speeds is None:   # one speed for all: the scalar step, as before per-robot speeds existed
            self.step = lo * params.dt / self.spacing
        else:
            self.step = speeds * params.dt / self.spacing

    def describe(self) -> dict:
        """The recorded speeds (``trace.meta["speeds"]``), only when they were drawn."""
        if self.speeds is None:
            return {}
        return {"speeds": {"min": self.speed_min, "max": self.speed_max,
                           "speed": [float(x) for x in self.speeds]}}

    def start(self, poses, n0: int, ids) -> None:
        """Snap the initial robots to their cells (they must be on cells, one each), heading 0."""
        self.cells[:n0] = _snap_cells(poses[:n0], self.spacing, ids[:n0], "initial")
        _check_free_cells(self.cells[:n0], ids[:n0])
        poses[:n0, :2] = self.cells[:n0] * self.spacing
        poses[:, 2] = 0.0

    def add(self, slot: int, poses, robot_id, t: int) -> None:
        self.cells[slot] = _snap_cells(poses[slot:slot + 1], self.spacing, [robot_id], f"additions[{t}]")[0]
        poses[slot, :2] = self.cells[slot] * self.spacing
        poses[slot, 2] = 0.0

    def command(self, cmd, robot_id, t: int):
        return _grid_move(cmd, robot_id, t)

    def apply(self, poses, idx, commands, pres_ids, t: int, events, record_clamps: bool) -> bool:
        return _grid_motion(poses, self.cells, self.edge, self.frac, idx, commands, self.step, self.spacing,
                            pres_ids, t, events)


def motion_model(model, params: Params, n_total: int, seed: int | None = None):
    """The motion model a :class:`~swarmproof.reference_impl.protocol.RobotModel` names.

    ``params.extra["speed_min"]`` / ``["speed_max"]`` (per-robot speeds, 004 Sec. V-B3) are for
    ``motion="grid"`` only: a differential or holonomic model refuses them with a usage error
    naming the key (those robots already choose any speed up to ``v`` in every step).
    """
    if model.motion == "grid":
        return GridMotion(params, n_total, seed)
    for key in SPEED_KEYS:
        if params.extra and key in params.extra:
            raise UsageError(f"params.extra[{key!r}]={params.extra[key]!r} sets per-robot speeds on a grid edge "
                             f"(004 Sec. V-B3); it is for motion='grid' only, not motion={model.motion!r}",
                             fix=f"leave {key} out: {model.motion} robots drive at most v per unit time in "
                                 "every step (set v)")
    return ContinuousMotion(params, model.motion == "differential")
