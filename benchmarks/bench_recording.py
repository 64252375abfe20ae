"""Memory of a long run of many robots, dense and sparse (issue 12: "a sparse mode ... so that
1,000 robots for 10,000 steps fits in memory").

Usage: ``python benchmarks/bench_recording.py [--robots N] [--steps T] [--every K ...]``.
Each setting runs in a fresh process (peak resident memory, ``ru_maxrss``, is per process):
the engine's ``wander`` controller (benchmarks/bench_engine.py: every robot turns and drives
every step) with a streaming connectivity monitor, recorded every K steps (K = 1: dense).
Prints peak memory, the trace's recorded steps and CPU seconds.  The numbers go to
docs/performance.md ("Recording").
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time


def one(n: int, steps: int, every: int) -> dict:
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from bench_engine import Trivial

    from swarmproof.invariants.connectivity import ConnectivityMonitor
    from swarmproof.reference_impl.engine import simulate
    from swarmproof.reference_impl.initial import random_connected
    from swarmproof.reference_impl.protocol import Params

    init = random_connected(n, 1, range=1.2, min_separation=0.4)
    mon = ConnectivityMonitor(1.2)
    c0 = time.process_time()
    r = simulate(Trivial(), None, init, Params(range=1.2, v=0.05), seed=0, max_steps=steps,
                 stop_when_static=False, record_every=every, record_clamps=False, observers=(mon,))
    cpu = time.process_time() - c0
    peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {"robots": n, "steps": r.steps, "record_every": every, "recorded": len(r.trace.poses),
            "poses_mib": round(r.trace.poses.nbytes / 2**20, 1), "peak_rss_mib": round(peak_kib / 1024, 1),
            "cpu_s": round(cpu, 1), "connectivity": r.observed("connectivity").status}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--robots", type=int, default=1000)
    ap.add_argument("--steps", type=int, default=10000)
    ap.add_argument("--every", type=int, nargs="+", default=[100, 1])
    ap.add_argument("--one", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one is not None:
        print(json.dumps(one(args.robots, args.steps, args.one)))
        return 0
    print(f"# {args.robots} robots, {args.steps} steps, wander controller, streaming connectivity monitor")
    for k in args.every:
        out = subprocess.run([sys.executable, __file__, "--robots", str(args.robots), "--steps", str(args.steps),
                              "--one", str(k)], capture_output=True, text=True)
        if out.returncode != 0:
            print(f"record_every={k}: failed: {out.stderr.strip().splitlines()[-1:]}")
            continue
        print(out.stdout.strip())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
