"""Robot-steps per second of the simulation engine with a trivial controller.

Usage: ``python benchmarks/bench_engine.py [--quick]``.  Prints one line per n for
two controllers: ``wander`` (every robot turns and drives every step: the engine's
general path, sensing every step) and ``still`` (nobody moves or changes its message,
and the controller offers ``repeat_step`` / ``repeat_horizon``: the fixed per-step cost
of the engine's shortcuts, docs/performance.md).  The numbers go to
docs/performance.md ("Simulation engine and song2016").
The anchor (DESIGN.md section 4) is 25,000 robot-steps/s for a plain per-robot
Python loop with neighbor search and a 10x10 assignment.
"""

from __future__ import annotations

import argparse
import math
import platform
import time

import numpy as np

from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Command, Params, RobotModel


class _Wander:
    """Each robot turns a little and drives a little every step; broadcasts its ID."""

    def __init__(self, robot_id):
        self.robot_id = robot_id
        self.k = 0

    def step(self, obs):
        self.k += 1
        return Command(message=(self.robot_id, len(obs.neighbor_ids)), turn=0.01, forward=0.01)

    def state(self):
        return self.k


class _Still:
    """Stands still with a constant broadcast; repeats itself until further notice."""

    def __init__(self, robot_id):
        self.cmd = Command(message=(robot_id,))

    def step(self, obs):
        return self.cmd

    def repeat_step(self, step):
        return self.cmd

    def repeat_horizon(self, step):
        return 2 ** 62

    def state(self):
        return 0


class Trivial:
    name = "trivial"
    model = RobotModel()
    assumptions = ()

    def __init__(self, still: bool = False):
        self.still = still

    def controller(self, robot_id, params, lattice, rng):
        return _Still(robot_id) if self.still else _Wander(robot_id)

    def finished(self, states):
        return False


def bench(n: int, robot_steps: int, repeat: int = 3, still: bool = False) -> float:
    init = random_connected(n, 1, range=1.2, min_separation=0.4)
    steps = max(robot_steps // n, 20)
    best = math.inf
    for _ in range(repeat):
        t0 = time.process_time()
        simulate(Trivial(still), None, init, Params(range=1.2), seed=1, max_steps=steps,
                 stop_when_static=False, record_clamps=True)
        best = min(best, time.process_time() - t0)
    return n * steps / best


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    total = 20_000 if a.quick else 100_000
    print("# CPU time of this process (time.process_time), best of 3")
    print(f"# {platform.platform()}, Python {platform.python_version()}, numpy {np.__version__}")
    for n in (10, 30, 100, 300):
        print(f"n={n:4d}: wander {bench(n, total):10.0f}  still {bench(n, total, still=True):10.0f} "
              "robot-steps/s")


if __name__ == "__main__":
    main()
