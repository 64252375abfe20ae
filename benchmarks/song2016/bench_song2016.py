"""song2016: execution time (steps) against n, the fitted exponent, and robot-steps/s.

Usage: ``python benchmarks/song2016/bench_song2016.py [--quick] [--lattice square] [--seeds 3] [--sizes 100]``.

For each n, runs song2016 (001 Sec. V; timeouts = n as in Sec. VI; range = the
library's, v = 0.05, omega = pi/4, dt = 1) from ``random_connected`` starts to
completion, and prints the steps (execution time T in steps, Def. 6), CPU and wall
seconds and robot-steps per second.  Then fits ``steps ~ c * n^k`` by least squares
on log-log (Theorem 13 predicts k <= 2; the Sec. VI text "scaling quadratically").
The last lines say, for each n = 100 start, whether it finished within 60 s (CPU time
of this process, ``time.process_time``; wall time and the load average are printed too,
as the machine may be shared).  Starts that end static are deadlocks of the algorithm as
published (docs/song2016.md, "What the implementation found"), not a timing result.
Numbers go to docs/performance.md ("### song2016").
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time

import numpy as np

from swarmproof.models.library import load
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Params
from swarmproof.reference_impl.song2016.algorithm import Song2016


def run(lattice, n: int, seed: int):
    init = random_connected(n, seed, range=lattice.range, min_separation=0.3)
    p = Params(range=lattice.range, v=0.05, omega=math.pi / 4, dt=1.0)
    c0, w0 = time.process_time(), time.perf_counter()
    r = simulate(Song2016(n_robots=n), lattice, init, p, seed=seed)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    return r.status, r.steps, cpu, wall


def fit_exponent(ns, steps) -> tuple[float, float]:
    """Least-squares ``log steps = log c + k log n``; returns (k, c)."""
    k, logc = np.polyfit(np.log(np.asarray(ns, float)), np.log(np.asarray(steps, float)), 1)
    return float(k), float(math.exp(logc))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="n = 10, 20, 40 only, one seed")
    ap.add_argument("--lattice", default="square")
    ap.add_argument("--seeds", type=int, default=3, help="starts per n (seeds 0, 1, ...)")
    ap.add_argument("--sizes", default=None, help="comma-separated n (default 10,...,100)")
    args = ap.parse_args(argv)
    lattice = load(args.lattice)
    sizes = (10, 20, 40) if args.quick else (10, 20, 30, 40, 60, 80, 100)
    if args.sizes:
        sizes = tuple(int(x) for x in args.sizes.split(","))
    print(f"song2016 on {lattice.name} (range {lattice.range}), {platform.machine()} "
          f"{platform.python_version()}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"load average {os.getloadavg()[0]:.1f}")
    print(f"{'n':>4} {'seed':>4} {'status':>9} {'steps':>7} {'cpu_s':>7} {'wall_s':>7} "
          f"{'robot-steps/s (cpu)':>20}")
    ns, steps, rates, n100 = [], [], [], []
    for n in sizes:
        seeds = 1 if args.quick else args.seeds
        for seed in range(seeds):
            status, t, cpu, wall = run(lattice, n, seed)
            print(f"{n:>4} {seed:>4} {status:>9} {t:>7} {cpu:>7.2f} {wall:>7.2f} "
                  f"{n * t / cpu:>20,.0f}", flush=True)
            if status == "finished":
                ns.append(n)
                steps.append(t)
                rates.append(n * t / cpu)
            if n == 100:
                n100.append((seed, status, t, wall, cpu))
    if len(set(ns)) >= 2:
        k, c = fit_exponent(ns, steps)
        print(f"fit: steps ~ {c:.3g} * n^{k:.2f} over the finished runs, n = {sorted(set(ns))} "
              f"(Theorem 13: O(n^2))")
    if rates:
        print(f"robot-steps/s (cpu): median {np.median(rates):,.0f}, min {min(rates):,.0f}, "
              f"max {max(rates):,.0f} (finished runs)")
    for seed, status, t, wall, cpu in n100:
        if status == "finished":
            verdict = "yes" if cpu < 60 else "NO"
            print(f"n = 100 on {lattice.name}, seed {seed}: finished after {t} steps in {cpu:.1f} s "
                  f"CPU ({wall:.1f} s wall); under 60 s: {verdict}")
        else:
            print(f"n = 100 on {lattice.name}, seed {seed}: {status} after {t} steps "
                  f"({cpu:.1f} s CPU): no run to completion from this start")
    print(f"load average at the end {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
