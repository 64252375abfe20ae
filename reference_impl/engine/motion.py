"""Motion models: differential drive, holonomic, and the engine's grid (issue 12).

* ``differential`` (000 Sec. III-A-3, 001 Sec. III-A): turn in place by at most
  ``omega dt``, then drive straight at most ``v (dt - |turn|/omega)``;
* ``holonomic``: a free turn, then at most ``v dt``;
* ``grid`` (004): integer cells of ``params.extra["grid_spacing"]``; a command is a
  move to a 4-neighbouring cell or a wait; an edge takes ``spacing / v``; positions
  are exact on the way and on arrival (DESIGN.md section 5, "Grid motion").
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
    """``grid`` motion: the engine's cells and edge crossings (module docstring)."""

    grid = True

    def __init__(self, params: Params, n_total: int) -> None:
        self.spacing = _grid_spacing(params)
        self.cells = np.zeros((n_total, 2), dtype=np.int64)
        self.edge = np.zeros((n_total, 2), dtype=np.int64)   # the edge a robot is crossing (0, 0: at a cell)
        self.frac = np.zeros(n_total)                         # how far along it, in [0, 1)
        self.step = params.v * params.dt / self.spacing

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


def motion_model(model, params: Params, n_total: int):
    """The motion model a :class:`~swarmproof.reference_impl.protocol.RobotModel` names."""
    if model.motion == "grid":
        return GridMotion(params, n_total)
    return ContinuousMotion(params, model.motion == "differential")
