"""Small example algorithms that show the protocol end to end (not from a paper).

* :class:`GatherToLowestId` ("example-gather"): local sensing with IDs, messages.
* :class:`AnonymousLine` ("example-anonymous-line"): anonymous robots (positions
  only, no IDs, no messages, holonomic) form a line pattern -- a new algorithm
  of another kind is one module (issue 12).
* :class:`GridGoals` ("example-grid-goals"): robots on grid cells with
  asynchronous clocks claim goal cells of a shape by message (004's kind).

"Gather to the lowest ID":

It is not from a paper; docs/engine.md walks through it.  Every robot looks
at the neighbors it senses (IDs and body-frame poses, nothing global).  If
one has a lower ID than its own, it follows the lowest of them: it steers
to the point ``gap`` short of that neighbor (``Params.extra["gap"]``,
default ``range / 2``) and stops there.  A robot with no lower-ID neighbor
stays where it is.  It broadcasts ``("arrived", bool)`` every step, and a
robot counts as *done* once it has arrived and every neighbor it hears has
said it arrived too.  The run is finished when every robot is done.

Nothing here keeps the communication graph connected or forms a lattice:
the example exists to exercise the engine, the invariants and the CLI
(and to fail some of their checks honestly).

Examples
--------
>>> from swarmproof.reference_impl.engine import simulate
>>> from swarmproof.reference_impl.protocol import Params
>>> from swarmproof.models.trace import InitialConfiguration
>>> init = InitialConfiguration([1, 0], [[1.0, 0, 0], [0, 0, 0]])
>>> r = simulate(GatherToLowestId(), None, init, Params(range=1.5, v=0.1), seed=0)
>>> r.status, [round(float(x), 9) for x in r.trace.poses[-1][:, 0]]
('finished', [0.75, 0.0])
"""

from __future__ import annotations

import math

from ..protocol import (Assumption, Command, Observation, Params, ParamSpec, RobotModel, VerifyPlan,
                        connected_start, steer_toward)

__all__ = ["GatherToLowestId", "GatherController", "AnonymousLine", "AnonymousLineController", "GridGoals",
           "GridGoalsController"]


def _v_dt_below_range(params: Params, n: int, ids) -> str | None:
    if params.v * params.dt < params.range:
        return None
    return f"v*dt={params.v * params.dt!r} must be < range={params.range!r}"


class GatherController:
    """One robot's controller for :class:`GatherToLowestId`."""

    def __init__(self, robot_id: int, params: Params) -> None:
        self.robot_id = robot_id
        self.gap = float(params.extra.get("gap", params.range / 2))
        self.params = params
        self.target: int | None = None
        self.arrived = False
        self.done = False

    def step(self, obs: Observation) -> Command:
        lower = [k for k, i in enumerate(obs.neighbor_ids) if i < obs.robot_id]
        if not lower:                           # nobody to follow: stay
            self.target, self.arrived = None, True
            cmd = Command(message=("arrived", True))
        else:
            k = lower[0]                        # neighbor_ids are sorted: the lowest ID
            self.target = obs.neighbor_ids[k]
            x, y = float(obs.neighbor_poses[k, 0]), float(obs.neighbor_poses[k, 1])
            dist = math.hypot(x, y)
            if dist <= self.gap + 1e-9:
                self.arrived = True
                cmd = Command(message=("arrived", True))
            else:
                self.arrived = False
                s = (dist - self.gap) / dist    # the point `gap` short of the neighbor
                cmd = steer_toward((x * s, y * s), self.params, message=("arrived", False))
        self.done = self.arrived and all(m == ("arrived", True) for m in obs.messages.values()) \
            and len(obs.messages) == len(obs.neighbor_ids)
        return cmd

    def state(self):
        return (("target", self.target), ("arrived", self.arrived), ("done", self.done))


class GatherToLowestId:
    """The example algorithm (registry name ``"example-gather"``)."""

    name = "example-gather"
    #: The controller-state fields the shared checkers may read: none (no spanning tree).  Not from a
    #: paper, so no ``paper``: its unclaimed rows say "not claimed by the algorithm".
    state_fields = ()
    #: The reading version (protocol.Algorithm.reading: bumped when its behaviour changes on
    #: purpose; CHANGELOG.md).
    reading = "1"
    model = RobotModel(sensing="local", communication="neighbors", motion="differential", clocks="sync")
    assumptions = (
        Assumption("v_dt_below_range", "v*dt < phi", "example (cf. 001 Lemma 7)", _v_dt_below_range),
        connected_start("example (cf. 001 Sec. III)"),
    )
    #: The ``Params.extra`` keys it reads (``--param gap=0.4``); the engine refuses any other key and a
    #: value out of range before the run.  No ``target_kinds``: it forms nothing, any target is run.
    parameters = (ParamSpec("gap", float, None, low=0, low_open=True,
                            meaning="how far short of the lowest-ID neighbor a robot stops; default range/2"),)
    #: ``swarmproof prove``'s lemma about it and the monitor bound to its runs (.lemmas,
    #: docs/lemmas.md): a follower near its leader that does not end farther stays in range.
    lemmas = ("gather_follower_link_kept",)
    premise_monitors = ("gather_link",)
    #: ``swarmproof verify`` runs it on the square lattice and explores its lemma's premises (the
    #: monitor ``gather_link`` on every step of every explored run); nothing is claimed, so its rows
    #: are findings, never failures.
    verify = VerifyPlan(targets=("square",), robots=6, seeds=(0, 1, 2), explore=True, rank=45,
                        explore_properties=("premises",), explore_cost=5)

    def controller(self, robot_id, params, lattice, rng):
        return GatherController(robot_id, params)

    def finished(self, states) -> bool:
        return all(dict(s)["done"] for s in states if s is not None)


# ----------------------------------------------------------------------------
# anonymous robots forming a line (positions only)
# ----------------------------------------------------------------------------

def _principal_axis(points):
    """Unit vector of the points' principal axis, its sign fixed by the third moment of the
    projections (frame-invariant); None when the moment is ~0 (a symmetric spread)."""
    import numpy as np

    c = points.mean(axis=0)
    q = points - c
    _, _, vt = np.linalg.svd(q, full_matrices=False)
    u = vt[0]
    skew = float(((q @ u) ** 3).sum())
    scale = float((np.abs(q @ u) ** 3).sum()) or 1.0
    if abs(skew) <= 1e-9 * scale:
        return c, u, False
    return c, (u if skew > 0 else -u), True


class AnonymousLineController:
    """One anonymous robot of :class:`AnonymousLine`: memoryless, positions only."""

    def __init__(self, params: Params, interval: float) -> None:
        self.params = params
        self.interval = float(interval)
        self.arrived = False
        self.agreed = True

    def step(self, obs: Observation) -> Command:
        import numpy as np

        others = np.asarray(obs.neighbor_poses, dtype=float).reshape(-1, 2)
        pts = np.vstack(([0.0, 0.0], others))            # row 0: this robot, at its own origin
        n = len(pts)
        if n == 1:
            self.arrived = True
            return Command()
        c, u, self.agreed = _principal_axis(pts)
        if not self.agreed:                              # no frame-invariant direction: a tie
            u = u if u[0] > 0 or (u[0] == 0 and u[1] > 0) else -u   # this robot's own guess
        w = np.array([-u[1], u[0]])
        proj = (pts - c) @ u
        perp = (pts - c) @ w
        order = np.lexsort((perp, proj))                 # along the axis, ties across it
        rank = int(np.flatnonzero(order == 0)[0])
        slot = c + (rank - (n - 1) / 2.0) * self.interval * u
        dist = float(np.hypot(*slot))
        self.arrived = dist <= 1e-9 * self.interval
        if self.arrived:
            return Command()
        return steer_toward((float(slot[0]), float(slot[1])), self.params)

    def state(self):
        return (("arrived", self.arrived), ("agreed", self.agreed))


class AnonymousLine:
    """Anonymous robots form a line at a uniform interval (registry name ``"example-anonymous-line"``).

    The kind of 003 (Lee & Chong): no IDs, positions only, no messages,
    holonomic motion; the target is a line pattern (``lines`` kind, 003
    Sec. 3's uni-line type with interval d_u).  Every robot sees every other
    robot's body-frame position; it computes the centroid and the principal
    axis of all positions (its sign fixed by the projections' third moment,
    which every robot computes alike in its own frame), ranks the robots
    along the axis and steers to its slot ``centroid + (rank - (n-1)/2) d_u
    axis``.  Not from a paper: where the spread is symmetric the sign has no
    frame-invariant choice, each robot guesses in its own frame, and robots
    may disagree -- the explorer's business (``state()["agreed"]``).

    >>> from swarmproof.reference_impl.engine import simulate
    >>> from swarmproof.models.targets import resolve_target
    >>> from swarmproof.models.trace import InitialConfiguration
    >>> line = resolve_target("lines:line")
    >>> init = InitialConfiguration([5, 9, 2], [[0, 0, 0.3], [0.9, 0.4, 2.0], [0.2, 1.1, -1.0]])
    >>> r = simulate(AnonymousLine(), line, init, Params(range=1.5, v=0.1, omega=3.2), seed=0)
    >>> r.status, line.satisfied(r.final_ids, r.final_poses).status
    ('finished', 'held')
    """

    name = "example-anonymous-line"
    #: The controller-state fields the shared checkers may read: none (no spanning tree).  Not from a
    #: paper, so no ``paper``: its unclaimed rows say "not claimed by the algorithm".
    state_fields = ()
    #: The reading version (protocol.Algorithm.reading: bumped when its behaviour changes on
    #: purpose; CHANGELOG.md).
    reading = "1"
    model = RobotModel(sensing="anonymous", communication="none", motion="holonomic", clocks="sync")
    assumptions = (
        Assumption("v_dt_below_range", "v*dt < phi", "example (cf. 001 Lemma 7)", _v_dt_below_range),
        connected_start("example (cf. 003 Sec. 2: robots start within sensing range)"),
    )
    #: The explorer draws its scenarios toward the bundled line (003's uni-line type).
    explore_targets = ("lines:line",)
    #: Nothing is claimed: it is an example (a violation is a finding, not a failed claim).
    claims: dict = {}
    #: ``swarmproof verify`` shows it beside the papers' algorithms (its rows are findings).
    verify = VerifyPlan(targets=("lines:line",), robots=6, seeds=(0, 1, 2), explore=True, rank=50,
                        explore_cost=51)
    parameters = (ParamSpec("interval", float, None, low=0, low_open=True,
                            meaning="the spacing along the line; default the target's interval"),)
    target_kinds = ("lines",)

    def controller(self, robot_id, params: Params, target, rng) -> AnonymousLineController:
        interval = params.extra.get("interval", getattr(target, "interval", None) or 1.0)
        return AnonymousLineController(params, float(interval))

    def finished(self, states) -> bool:
        return all(dict(s)["arrived"] for s in states if s is not None)


# ----------------------------------------------------------------------------
# grid robots with asynchronous clocks claiming goal cells
# ----------------------------------------------------------------------------

class GridGoalsController:
    """One robot of :class:`GridGoals`: its goal, the cell it is heading for, what it heard."""

    def __init__(self, robot_id: int, params: Params, goals, spacing: float, origin) -> None:
        self.robot_id = robot_id
        self.goals = sorted(goals)
        self.spacing = float(spacing)
        self.origin = (float(origin[0]), float(origin[1]))
        self.goal = None
        self.on_goal = False

    def _cell(self, x: float, y: float):
        return (round((x - self.origin[0]) / self.spacing), round((y - self.origin[1]) / self.spacing))

    def step(self, obs: Observation) -> Command:
        x, y = float(obs.own_pose[0]), float(obs.own_pose[1])
        here = self._cell(x, y)
        (ox, oy), spacing = self.origin, self.spacing
        on_edge = math.hypot(x - (ox + here[0] * spacing), y - (oy + here[1] * spacing)) > 1e-9 * spacing
        # the neighbors' cells (self._cell inlined: this runs for every neighbor of every robot
        # on every tick, and is most of an exploration run's time)
        at = {(round((x + dx - ox) / spacing), round((y + dy - oy) / spacing)): rid
              for rid, (dx, dy) in zip(obs.neighbor_ids, obs.neighbor_poses[:, :2].tolist())}
        # claims heard: (goal, next cell, swap request) of each neighbor; a lower ID wins a clash
        taken, reserved, goal_of = set(), set(), {}
        for sender, msg in obs.inbox:
            if not (isinstance(msg, tuple) and len(msg) == 4 and msg[0] == "claim"):
                continue
            goal_of[sender] = msg[1]
            if msg[3] is not None and msg[3][0] == self.robot_id and msg[3][1] is not None:
                self.goal = msg[3][1]             # a blocked neighbor hands me its goal (a swap)
            if sender < self.robot_id:
                taken.add(msg[1])
                reserved.add(msg[2])
        if self.goal is None or self.goal in taken or (self.goal in at and self.goal != here
                                                       and goal_of.get(at[self.goal]) == self.goal):
            free = [g for g in self.goals if g not in taken and (g == here or g not in at)]
            self.goal = min(free, key=lambda g: (abs(g[0] - here[0]) + abs(g[1] - here[1]), g), default=None)
        self.on_goal = self.goal is not None and self.goal == here and not on_edge
        nxt, move, swap = here, None, None
        if self.goal is not None and not on_edge and self.goal != here:
            dist = abs(self.goal[0] - here[0]) + abs(self.goal[1] - here[1])
            blocker = None
            for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                c = (here[0] + dx, here[1] + dy)
                if abs(self.goal[0] - c[0]) + abs(self.goal[1] - c[1]) >= dist:
                    continue
                if c not in at and c not in reserved:
                    nxt, move = c, (dx, dy)
                    break
                if c in at and goal_of.get(at[c]) == c and blocker is None:
                    blocker = (at[c], c)
            if move is None and blocker is not None:
                # blocked by a robot that sits on its goal: swap goals (004 Sec. IV's task swap, simplified)
                swap = (blocker[0], self.goal)
                self.goal = blocker[1]
        return Command(message=("claim", self.goal, nxt, swap), move=move)

    def state(self):
        return (("goal", self.goal), ("on_goal", self.on_goal))


def _grid_default_params(range: float, n: int) -> Params:
    """004 Sec. V-A/V-B3 values: v = 0.05 m/s, l = 0.20 m, clock rates within 10 %."""
    return Params(range=range, v=0.05, dt=1.0, extra={"grid_spacing": 0.2, "clock_rate_min": 0.9,
                                                      "clock_rate_max": 1.1})


class GridGoals:
    """Robots on a grid claim the cells of a shape (registry name ``"example-grid-goals"``).

    The kind of 004 (Wang & Rubenstein): global coordinates, messages to the
    robots within ``R`` (inclusive), grid motion (one edge at a time, taking
    ``l / v``), asynchronous clocks (per-robot phase and rate, broadcasting on
    its own schedule); the target is a goal set (``shape`` kind).  Each robot
    claims the nearest goal cell that no lower-ID neighbor claims and that no
    sensed robot stands on, and steps toward it onto a free cell no lower-ID
    neighbor reserved; blocked by a robot sitting on its goal, it hands that
    robot its own goal and takes the blocker's (a goal swap).  Not 004's
    algorithm (no handshake, no priority planner): an example of the kind,
    whose conflicts the explorer may find.

    >>> from swarmproof.reference_impl.engine import simulate
    >>> from swarmproof.models.targets import resolve_target
    >>> from swarmproof.models.trace import InitialConfiguration
    >>> shape = resolve_target("shape:letter-l")
    >>> cells = [(-2, 0), (-1, 0), (-2, 1), (-1, 1), (-2, 2)]
    >>> init = InitialConfiguration([1, 2, 3, 4, 5], [[0.2 * x, 0.2 * y, 0] for x, y in cells])
    >>> alg = GridGoals()
    >>> r = simulate(alg, shape, init, alg.default_params(range=0.6, n=5), seed=0)
    >>> r.status, shape.satisfied(r.final_ids, r.final_poses).status
    ('finished', 'held')
    """

    name = "example-grid-goals"
    #: The controller-state fields the shared checkers may read: none (no spanning tree).  Not from a
    #: paper, so no ``paper``: its unclaimed rows say "not claimed by the algorithm".
    state_fields = ()
    #: The reading version (protocol.Algorithm.reading: bumped when its behaviour changes on
    #: purpose; CHANGELOG.md).
    reading = "1"
    model = RobotModel(sensing="global", communication="neighbors", motion="grid", clocks="async",
                       neighbor_rule="inclusive")
    assumptions = (
        Assumption("v_dt_below_range", "v*dt < R", "example (cf. 004 Sec. V-A)", _v_dt_below_range),
        connected_start("example (cf. 004 Sec. III: robots start within range R)"),
    )
    explore_targets = ("shape:letter-l", "shape:square-9")
    claims: dict = {}
    verify = VerifyPlan(targets=("shape:letter-l",), robots=5, seeds=(0, 1, 2), explore=True, rank=60,
                        explore_cost=145)
    #: No keys of its own: only the engine's grid and clock keys (grid_spacing, clock rates, ...).
    parameters = ()
    target_kinds = ("shape",)

    @staticmethod
    def default_params(range: float, n: int) -> Params:
        return _grid_default_params(range, n)

    def controller(self, robot_id, params: Params, target, rng) -> GridGoalsController:
        cells = getattr(target, "cells", None)
        if cells is None:
            from swarmproof.models.errors import UsageError

            raise UsageError(f"example-grid-goals needs a shape target (goal cells), not {target!r}",
                             fix="e.g. --target shape:letter-l")
        return GridGoalsController(robot_id, params, cells, target.spacing, target.origin)

    def finished(self, states) -> bool:
        return all(dict(s)["on_goal"] for s in states if s is not None)
