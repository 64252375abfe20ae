"""A tiny example algorithm that shows the protocol end to end: "gather to the lowest ID".

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

from .protocol import Assumption, Command, Observation, Params, RobotModel, connected_start, steer_toward

__all__ = ["GatherToLowestId", "GatherController"]


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
    model = RobotModel(sensing="local", communication="neighbors", motion="differential", clocks="sync")
    assumptions = (
        Assumption("v_dt_below_range", "v*dt < phi", "example (cf. 001 Lemma 7)", _v_dt_below_range),
        connected_start("example (cf. 001 Sec. III)"),
    )

    def controller(self, robot_id, params, lattice, rng):
        return GatherController(robot_id, params)

    def finished(self, states) -> bool:
        return all(dict(s)["done"] for s in states if s is not None)
