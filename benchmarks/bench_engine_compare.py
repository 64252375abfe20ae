"""CPU time of two fixed engine workloads, best of k runs: a before/after check of an engine change.

Usage (from the repository root)::

    .venv/bin/python benchmarks/bench_engine_compare.py [--repeat 5] [--only song2016|wang2020]

Workloads (each the same work on every run, seeded):

* ``song2016``: the per-robot engine (:func:`~swarmproof.reference_impl.engine.simulate`) running
  song2016 (001) on the ``square`` lattice, n = 30, seed 0, v = 0.05, omega = pi/4, dt = 1, from a
  ``random_connected`` start to its end (the ``repeat_step`` / ``repeat_horizon`` shortcuts and
  vectorised sensing are on this path).
* ``wang2020``: wang2020's vectorised path
  (:func:`~swarmproof.reference_impl.wang2020_fast.simulate_fast`), Fig. 10's instance of 256
  agents (``fig10_instance(256, 0)``) with ``experiment_params``, 300 ticks, sparse recording.

It prints the best (smallest) CPU time of this process (``time.process_time``) over ``--repeat``
runs of each.  To compare two commits, run it from each checkout with that checkout's own venv,
alternately and back to back (the machine may be shared); docs/performance.md ("Engine loop split
into phases (issue 28)") records one such comparison.
"""

from __future__ import annotations

import argparse
import math
import platform
import time

import numpy as np


def song2016_workload():
    """A thunk running the song2016 workload once (set-up outside the timed part)."""
    from swarmproof.models.library import load
    from swarmproof.reference_impl.engine import simulate
    from swarmproof.reference_impl.initial import random_connected
    from swarmproof.reference_impl.protocol import Params
    from swarmproof.reference_impl.song2016 import Song2016

    lattice = load("square")
    n = 30
    init = random_connected(n, 0, range=lattice.range, min_separation=0.3)
    params = Params(range=lattice.range, v=0.05, omega=math.pi / 4, dt=1.0)
    return lambda: simulate(Song2016(n_robots=n), lattice, init, params, seed=0)


def wang2020_workload(n: int = 256, steps: int = 300):
    """A thunk running the wang2020 vectorised workload once."""
    from swarmproof.models.trace import InitialConfiguration
    from swarmproof.reference_impl.wang2020 import Wang2020
    from swarmproof.reference_impl.wang2020_experiments import experiment_params, fig10_instance
    from swarmproof.reference_impl.wang2020_fast import simulate_fast

    goals, starts = fig10_instance(n, 0)
    params = experiment_params(n)
    spacing = float(params.extra["grid_spacing"])
    init = InitialConfiguration(list(range(n)), [[spacing * x, spacing * y, 0.0] for x, y in starts])
    return lambda: simulate_fast(Wang2020(), goals, init, params, seed=0, max_steps=steps,
                                 stop_when_static=False, record_every=1000)


WORKLOADS = {"song2016": song2016_workload, "wang2020": wang2020_workload}


def best_cpu(thunk, repeat: int) -> tuple[float, object]:
    """The smallest ``time.process_time`` of ``repeat`` calls of ``thunk``, and its last result."""
    best, result = math.inf, None
    for _ in range(repeat):
        t0 = time.process_time()
        result = thunk()
        best = min(best, time.process_time() - t0)
    return best, result


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="runs of each workload (the best counts)")
    ap.add_argument("--only", choices=sorted(WORKLOADS), default=None, help="run one workload")
    args = ap.parse_args(argv)
    print(f"# CPU time (time.process_time), best of {args.repeat}; {platform.machine()}, "
          f"Python {platform.python_version()}, numpy {np.__version__}")
    for name, make in WORKLOADS.items():
        if args.only not in (None, name):
            continue
        cpu, r = best_cpu(make(), args.repeat)
        print(f"{name:9s} {cpu:8.3f} s  ({r.status}, {r.steps} steps)", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
