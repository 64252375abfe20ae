"""song2014 benchmarks: throughput, and the experiments of 000 Sec. V.

Usage (from the repository root)::

    .venv/bin/python benchmarks/song2014/bench_song2014.py perf              # robot-steps/s at 50 and 250
    .venv/bin/python benchmarks/song2014/bench_song2014.py figs --seeds 5    # Figs. 8-9 table
    .venv/bin/python benchmarks/song2014/bench_song2014.py robustness --seeds 3   # Fig. 10 numbers

Each mode prints a Markdown table (pasted into docs/song2014.md and
docs/performance.md) and, with ``--json FILE``, writes the raw numbers
atomically.  Every run is seeded; the same command prints the same
experiment numbers (timings vary with the machine's load).
"""

from __future__ import annotations

import argparse
import datetime
import math
import platform
import statistics
import sys
import time

import numpy as np

from swarmproof.invariants.connectivity import components_at, first_disconnection
from swarmproof.invariants.metrics import non_fulfillment_ratio
from swarmproof.invariants.satisfaction import satisfies_lattice
from swarmproof.models.fileio import atomic_write_text, dumps_json
from swarmproof.models.library import load
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.song2014.algorithm import ROLE_UNMATCHED, Song2014
from swarmproof.reference_impl.song2014.experiments import (
    default_params, execution_time, run_formation, run_robustness,
)


def ratio_of(result, lattice, phi):
    """Eq. 3 with each robot's own role (the paper's "its role vertex"); None if a
    robot has no role at the end."""
    ids = [int(i) for i in result.final_ids]
    roles = {i: dict(s)["role"] for i, s in zip(ids, result.final_states)}
    if any(r is None or r == ROLE_UNMATCHED for r in roles.values()):
        return None
    return non_fulfillment_ratio(ids, result.final_poses, lattice, phi, roles=roles)


def summary(result, lattice, phi, start=0):
    t = execution_time(result, start=start)
    states = [dict(s) for s in result.final_states]
    sat = satisfies_lattice([int(i) for i in result.final_ids], result.final_poses, lattice, phi)
    return {
        "status": result.status, "steps": result.steps,
        "t_exe": None if t is None else t - start,
        "ratio": ratio_of(result, lattice, phi),
        "roots": sum(1 for s in states if s["root"]),
        "satisfies": bool(sat.held),
        "first_split": None if (hit := first_disconnection(result.trace, phi)) is None else hit[0],
        "components_end": len(components_at(result.trace, result.steps, phi)),
    }


def _ms(xs):
    xs = [x for x in xs if x is not None]
    if not xs:
        return "-"
    if len(xs) == 1:
        return f"{xs[0]:.3g}"
    return f"{statistics.mean(xs):.3g} ± {statistics.stdev(xs):.2g}"


def mode_perf(args):
    rows = []
    for n in args.sizes:
        lat = load("square")
        params = default_params(lat)
        init = random_connected(n, 0, range=lat.range)
        steps = args.steps
        times, cpus = [], []
        for _ in range(args.repeats):
            t0, c0 = time.perf_counter(), time.process_time()
            res = simulate(Song2014(), lat, init, params, seed=0, max_steps=steps,
                           stop_when_static=False, record_clamps=False)
            times.append(time.perf_counter() - t0)
            cpus.append(time.process_time() - c0)
        el, cpu = min(times), min(cpus)   # best of N: the machine is shared, load only slows runs
        rows.append({"n": n, "steps": res.steps, "seconds": el, "robot_steps_per_s": n * res.steps / el,
                     "cpu_seconds": cpu, "robot_steps_per_cpu_s": n * res.steps / cpu,
                     "all_seconds": times})
    print(f"song2014 throughput, square lattice, {args.steps} steps, best of {args.repeats}, "
          f"{datetime.date.today().isoformat()}, {platform.node()}, Python {platform.python_version()}")
    print("| robots | steps | wall s | robot-steps/s (wall) | CPU s | robot-steps/s (CPU) |")
    print("|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['n']} | {r['steps']} | {r['seconds']:.2f} | {r['robot_steps_per_s']:,.0f} | "
              f"{r['cpu_seconds']:.2f} | {r['robot_steps_per_cpu_s']:,.0f} |")
    return rows


def mode_figs(args):
    rows = []
    for lname in args.lattices:
        lat = load(lname)
        for n in args.sizes:
            runs = []
            for seed in range(args.seeds):
                t0 = time.perf_counter()
                res = run_formation(lname, n, seed=seed, spread_factor=args.spread_factor)
                s = summary(res, lat, lat.range)
                s.update(lattice=lname, n=n, seed=seed, seconds=time.perf_counter() - t0)
                runs.append(s)
                print(f"  {lname} n={n} seed={seed}: {s}", file=sys.stderr, flush=True)
            rows.extend(runs)
            static = [r for r in runs if r["status"] == "static"]
            print(f"| {lname} | {n} | {len(static)}/{len(runs)} | {_ms([r['t_exe'] for r in static])} | "
                  f"{_ms([r['ratio'] for r in static])} | {_ms([r['roots'] for r in runs])} | "
                  f"{sum(r['satisfies'] for r in runs)}/{len(runs)} | "
                  f"{sum(r['first_split'] is not None for r in runs)}/{len(runs)} | "
                  f"{_ms([r['components_end'] for r in runs])} |", flush=True)
    return rows


def mode_robustness(args):
    rows = []
    lat = load("hexagon")
    for seed in range(args.seeds):
        t0 = time.perf_counter()
        r = run_robustness(seed, n=args.robots, remove=args.remove, spread_factor=args.spread_factor)
        b = summary(r.before, lat, lat.range)
        a = summary(r.after, lat, lat.range, start=r.removed_at)
        rows.append({"seed": seed, "removed_at": r.removed_at, "before": b, "after": a,
                     "seconds": time.perf_counter() - t0})
        print(f"| {seed} | {b['t_exe']} | {b['ratio']:.3f} | {b['components_end']} | {a['status']} | "
              f"{a['t_exe']} | {'-' if a['ratio'] is None else format(a['ratio'], '.3f')} | "
              f"{a['components_end']} |", flush=True)
    return rows


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("mode", choices=["perf", "figs", "robustness"])
    p.add_argument("--sizes", type=int, nargs="+", default=None)
    p.add_argument("--lattices", nargs="+", default=["square", "hexagon", "octagon-square"])
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--robots", type=int, default=150)
    p.add_argument("--remove", type=int, default=50)
    p.add_argument("--repeats", type=int, default=3, help="perf: best of this many runs")
    p.add_argument("--spread-factor", type=float, default=None,
                   help="start in a square of side F*sqrt(n)*phi (denser); default: unconfined")
    p.add_argument("--json", default=None)
    args = p.parse_args(argv)
    if args.sizes is None:
        args.sizes = [50, 250] if args.mode == "perf" else [50, 100, 150, 200, 250]
    if args.mode == "figs":
        print("| lattice | robots | static | t_exe (steps) | ratio (Eq. 3) | roots | satisfies Def. 2 "
              "| disconnected | components at end |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    if args.mode == "robustness":
        print("| seed | t_exe before | ratio before | components before | status after | "
              "t_exe after removal | ratio after | components after |")
        print("|---:|---:|---:|---:|---|---:|---:|---:|")
    rows = {"perf": mode_perf, "figs": mode_figs, "robustness": mode_robustness}[args.mode](args)
    if args.json:
        atomic_write_text(args.json, dumps_json({"mode": args.mode, "argv": sys.argv[1:], "rows": rows}))


if __name__ == "__main__":
    main()
