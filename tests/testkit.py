"""Helpers shared by test modules (``from testkit import ...``; conftest puts this folder on the path)."""

from __future__ import annotations


class Recorder:
    """A test algorithm whose controllers record every observation (``seen``: (robot_id, obs), in
    engine order) and answer ``command(robot_id, k, obs, rng)`` (k: the controller's call count);
    by default a random move and a message of what the robot saw."""

    name = "recorder"
    assumptions = ()

    def __init__(self, model, command=None):
        self.model = model
        self.command = command
        self.seen: list = []

    def controller(self, robot_id, params, target, rng):
        from swarmproof.reference_impl.protocol import Command

        algo = self

        class C:
            def __init__(self):
                self.k = 0

            def step(self, obs):
                algo.seen.append((robot_id, obs))
                self.k += 1
                if algo.command is not None:
                    return algo.command(robot_id, self.k - 1, obs, rng)
                msg = ("saw", len(obs.neighbor_poses), obs.step, round(float(rng.uniform()), 6))
                return Command(message=msg, turn=float(rng.uniform(-1, 1)), forward=float(rng.uniform(0, 0.1)))

            def state(self):
                return (("k", self.k),)

        return C()

    def finished(self, states):
        return False
