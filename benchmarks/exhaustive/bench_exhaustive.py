"""Exhaustive bounded checking (issue 33): the results of docs/exhaustive.md and docs/performance.md.

Usage (from the repository root)::

    .venv/bin/python benchmarks/exhaustive/bench_exhaustive.py jiang        # delays vs termination, teams 3..6
    .venv/bin/python benchmarks/exhaustive/bench_exhaustive.py wang2020     # clock phases, interleavings, the half swap
    .venv/bin/python benchmarks/exhaustive/bench_exhaustive.py song2014     # every schedule within K, n = 3, 4
    .venv/bin/python benchmarks/exhaustive/bench_exhaustive.py perf --plot docs/exhaustive-growth.png

Each mode runs a fixed list of cells (algorithm, start, bound, property) through
:func:`swarmproof.checkers.exhaustive.exhaustive` and prints a Markdown table: the verdict, the
fewest deviations of a counterexample, runs, distinct states (of the last level searched), the
prunes of state hashing and of symmetry, and the CPU seconds (``time.process_time``).  ``perf``
adds states and runs per CPU second, the pruning ratios (pruned / runs) with hashing and with
symmetry on and off, and the state count's growth with n and K (``--plot FILE``: a PNG).
Counterexamples are replayed (``swarmproof replay``'s :func:`replay_file`) and the table says
whether they reproduce.  ``--json FILE`` writes every cell's numbers.  Deterministic: the same
command prints the same verdicts, runs and states (the CPU column varies).  Every verdict is
"for the robots' draws of seed S" (the start's seed; the robots' own random draws are fixed by it).
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import sys
import tempfile
import time

from swarmproof.checkers.exhaustive import Bound, exhaustive
from swarmproof.models.fileio import atomic_write_text, dumps_json

#: A start whose robots mirror each other (used with --initial in the symmetry rows).
SYMMETRIC_STARTS = {
    # three anonymous robots on an isosceles triangle, mirrored about the y axis, headings mirrored
    3: ([0, 1, 2], [[-0.4, 0.0, 0.0], [0.4, 0.0, 3.141592653589793], [0.0, 0.6, -1.5707963267948966]]),
    # four on a square, each heading to the square's centre
    4: ([0, 1, 2, 3], [[-0.4, -0.4, 0.7853981633974483], [0.4, -0.4, 2.356194490192345],
                       [0.4, 0.4, -2.356194490192345], [-0.4, 0.4, -0.7853981633974483]]),
}


def cell(algorithm, prop, *, robots=3, seed=0, steps=20, k=1, kinds=("activate",), max_delay=1, max_crashes=1,
         target=None, invariant=None, symmetry=True, initial=None, max_runs=None, label=None, replay=True) -> dict:
    """One exhaustive search: its numbers as a row (and the counterexample replayed)."""
    bound = Bound(steps=steps, deviations=k, kinds=tuple(kinds), max_delay=max_delay, max_crashes=max_crashes)
    options = {"invariants": [invariant]} if invariant else None
    init = None
    if initial is not None:
        from swarmproof.models.trace import InitialConfiguration

        init = InitialConfiguration(*SYMMETRIC_STARTS[initial])
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.process_time()
        rep = exhaustive(algorithm, [prop], target=target, robots=robots, seed=seed, initial=init, bound=bound,
                         options=options, symmetry=symmetry, max_runs=max_runs, budget=None, out_dir=tmp)
        cpu = time.process_time() - t0
        v = rep.properties[prop]
        replayed = None
        if replay and v.counterexample_path:
            from swarmproof.checkers.replay import replay_file

            replayed = bool(replay_file(v.counterexample_path).reproduced)
    levels = [lv for st in v.levels for lv in st["levels"]]
    row = {"label": label or algorithm, "algorithm": algorithm, "property": prop + (f" ({invariant})" if invariant else ""),
           "robots": rep.robots, "start": "symmetric" if initial else f"seed {seed}", "bound": bound.as_dict(),
           "bound_text": f"{steps} st, K={k}, {'+'.join(bound.kinds)}" + (f", D={max_delay}" if "delay" in bound.kinds else ""),
           "symmetry": rep.symmetric, "status": v.status, "deviations": v.deviations, "runs": v.runs,
           "states": v.distinct_states, "states_all_levels": sum(lv["distinct_states"] for lv in levels),
           "pruned": v.pruned, "symmetric_pruned": v.symmetric_pruned, "complete": v.complete, "cpu": cpu,
           "message": v.message, "replayed": replayed, "levels": v.levels}
    return row


def table(rows, title) -> str:
    out = [f"\n### {title}\n",
           "| algorithm | property | n | start | bound | symmetry | verdict | fewest dev. | runs | states | pruned (hash) | pruned (sym.) | CPU s | replays |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['label']} | {r['property']} | {r['robots']} | {r['start']} | {r['bound_text']} | {'on' if r['symmetry'] else 'off'} | {r['status']} | "
                   f"{'' if r['deviations'] is None else r['deviations']} | {r['runs']:,} | {r['states']:,} | "
                   f"{r['pruned']:,} | {r['symmetric_pruned']:,} | {r['cpu']:.1f} | "
                   f"{'' if r['replayed'] is None else ('yes' if r['replayed'] else 'NO')} |")
    text = "\n".join(out)
    print(text, flush=True)
    return text


def messages(rows) -> None:
    for r in rows:
        if r["status"] != "held":
            print(f"- {r['label']} n={r['robots']} {r['start']} {r['property']}: {r['message']}", flush=True)


# ---------------------------------------------------------------------------------------------

def jiang(starts: int, k: int, max_delay: int, steps: int) -> list:
    """Delays against termination (liveness: no pruning), teams 3..6, seeded starts."""
    rows = []
    pat = "pattern:rhombus-triangles"
    for n in (3, 4, 5, 6):
        for s in range(starts if n > 3 else 2 * starts):
            rows.append(cell("jiang", "termination", robots=n, seed=s, steps=steps, k=k + (n == 3), kinds=("delay",),
                             max_delay=max_delay, target=pat))
            print(f"  jiang n={n} seed {s}: {rows[-1]['status']} ({rows[-1]['cpu']:.1f} s)", flush=True)
    # the smallest team's break: how late must the message be, and do 1-step delays ever break it?
    for d, kk in ((1, 3), (2, 1), (3, 1)):
        rows.append(cell("jiang", "termination", robots=4, seed=0, steps=steps, k=kk, kinds=("delay",), max_delay=d,
                         target=pat))
    table(rows, "jiang: delays vs termination (rhombus-triangles)")
    messages(rows)
    return rows


def wang2020(steps_long: int, steps_short: int) -> list:
    """Clock phases and interleavings vs collision and the invariants; the variant's half swap."""
    rows = []
    sq = "shape:square-9"
    for alg in ("wang2020", "wang2020-broadcast-handshake"):
        # every combination of clock phases (K = n: each robot's other behaviour costs one), to the run's end
        for n, s in ((3, 0), (3, 3), (4, 0)):
            for prop, inv in (("collision", None), ("invariants", None), ("invariants", "pairwise_swap")):
                rows.append(cell(alg, prop, robots=n, seed=s, steps=steps_long, k=n, kinds=("clock_phase",),
                                 target=sq, invariant=inv))
                print(f"  {alg} n={n} seed {s} {prop} {inv}: {rows[-1]['status']} ({rows[-1]['cpu']:.1f} s)", flush=True)
        # phases and asynchronous interleavings together, a short bound
        for prop, inv in (("collision", None), ("invariants", None), ("invariants", "pairwise_swap")):
            rows.append(cell(alg, prop, robots=3, seed=3, steps=steps_short, k=2, kinds=("clock_phase", "activate"),
                             target=sq, invariant=inv))
            print(f"  {alg} interleavings {prop} {inv}: {rows[-1]['status']} ({rows[-1]['cpu']:.1f} s)", flush=True)
    table(rows, "wang2020: every clock phase and interleaving within the bound (square-9)")
    messages(rows)
    return rows


def song2014(steps: int) -> list:
    """Every schedule within K (asynchronous activation) vs connectivity and oscillation."""
    rows = []
    for n in (3, 4):
        for k in (1, 2):
            for prop in ("connectivity", "oscillation"):
                rows.append(cell("song2014", prop, robots=n, seed=0, steps=steps, k=k, kinds=("activate",),
                                 target="square"))
                print(f"  song2014 n={n} K={k} {prop}: {rows[-1]['status']} ({rows[-1]['cpu']:.1f} s)", flush=True)
    table(rows, "song2014: asynchronous activation (square lattice)")
    messages(rows)
    return rows


def unpruned(algorithm, prop, *, robots, seed, steps, k, target, kinds=("activate",)) -> dict:
    """The same search with state hashing off (``search_start(prune=False)``): what hashing saves."""
    from swarmproof.checkers.exhaustive import _inputs, search_start

    bound = Bound(steps=steps, deviations=k, kinds=tuple(kinds))
    spec, algo, tgt, _label, params, _props, starts = _inputs(algorithm, [prop], target, robots, seed, None, 1, bound,
                                                              None, None, None)
    t0 = time.process_time()
    out = search_start(algo, tgt, starts[0][1], params, prop, bound, seed=seed, prune=False, factory=spec.factory)
    return {"status": out.status, "runs": out.runs, "states": out.distinct_states, "cpu": time.process_time() - t0}


def perf(plot: str | None) -> dict:
    """Speed, pruning ratios and growth."""
    pruning = []
    line = "lines:line"
    for sym in (True, False):
        pruning.append(cell("example-anonymous-line", "collision", robots=3, seed=0, steps=12, k=2, target=line,
                            symmetry=sym))
        pruning.append(cell("example-anonymous-line", "collision", initial=3, steps=12, k=2, target=line,
                            symmetry=sym))
        pruning.append(cell("leechong-neighbor", "collision", robots=3, seed=0, steps=25, k=1, kinds=("crash",),
                            target="lines:wedge", symmetry=sym))
        pruning.append(cell("leechong-neighbor", "collision", initial=3, steps=25, k=1, kinds=("crash",),
                            target="lines:wedge", symmetry=sym))
        print(f"  symmetry {sym}: done", flush=True)
    pruning.append(cell("leechong-neighbor", "collision", robots=4, seed=0, steps=25, k=1, kinds=("crash",),
                        target="lines:wedge"))
    pruning.append(cell("leechong-neighbor", "collision", robots=3, seed=0, steps=25, k=1,
                        kinds=("crash", "activate"), target="lines:wedge"))
    table(pruning, "pruning: hashing and symmetry")
    growth = []
    for n in (3, 4, 5):
        for k in (0, 1, 2):
            growth.append(cell("song2014", "connectivity", robots=n, seed=0, steps=20, k=k, target="square"))
            print(f"  growth n={n} K={k}: {growth[-1]['states']} states, {growth[-1]['runs']} runs "
                  f"({growth[-1]['cpu']:.1f} s)", flush=True)
    table(growth, "growth: song2014, connectivity, 20 steps, activation")
    print("\n| hashing | n | K | verdict | runs | distinct states | CPU s |\n|---|---|---|---|---|---|---|")
    hashing = []
    for n, k in ((3, 1), (3, 2), (4, 1)):
        on = next(r for r in growth if r["robots"] == n and r["bound"]["deviations"] == k)
        off = unpruned("song2014", "connectivity", robots=n, seed=0, steps=20, k=k, target="square")
        hashing.append({"robots": n, "k": k, "on": {x: on[x] for x in ("status", "runs", "states", "cpu")}, "off": off})
        for name, r in (("on", on), ("off", off)):
            print(f"| {name} | {n} | {k} | {r['status']} | {r['runs']:,} | {r['states']:,} | {r['cpu']:.1f} |", flush=True)
    rows = pruning + growth
    print("\n| cell | states / CPU s | runs / CPU s | hash pruned / runs | sym. pruned / runs |\n|---|---|---|---|---|")
    for r in rows:
        c = max(r["cpu"], 1e-9)
        print(f"| {r['label']} n={r['robots']} {r['start']} {r['bound_text']} sym={'on' if r['symmetry'] else 'off'} | "
              f"{r['states_all_levels'] / c:,.0f} | {r['runs'] / c:,.1f} | {r['pruned'] / max(r['runs'], 1):.2f} | "
              f"{r['symmetric_pruned'] / max(r['runs'], 1):.2f} |")
    if plot:
        plot_growth(growth, plot)
    return {"pruning": pruning, "growth": growth, "hashing": hashing}


def plot_growth(growth, path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.6))
    for n in sorted({r["robots"] for r in growth}):
        rs = sorted((r for r in growth if r["robots"] == n), key=lambda r: r["bound"]["deviations"])
        ks = [r["bound"]["deviations"] for r in rs]
        a.semilogy(ks, [max(r["states"], 1) for r in rs], "o-", label=f"n = {n}")
        b.semilogy(ks, [max(r["runs"], 1) for r in rs], "o-", label=f"n = {n}")
    a.set_title("distinct states (level K)")
    b.set_title("runs (levels 0..K)")
    for ax in (a, b):
        ax.set_xlabel("deviation budget K")
        ax.set_xticks(sorted({r["bound"]["deviations"] for r in growth}))
        ax.legend(fontsize=8)
    fig.suptitle("exhaustive checking: song2014, connectivity, 20 steps, activation choices", fontsize=10)
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=90)
    os.replace(tmp, path)
    print(f"plot: {path}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    p = sub.add_parser("jiang")
    p.add_argument("--starts", type=int, default=3, help="seeded starts per team of 4..6 (twice as many of 3)")
    p.add_argument("--deviations", type=int, default=2, help="K for teams 4..6 (K + 1 for 3 robots)")
    p.add_argument("--max-delay", type=int, default=4)
    p.add_argument("--max-steps", type=int, default=150, help="long enough for a delayed run to end (6 robots: 60 is not)")
    p = sub.add_parser("wang2020")
    p.add_argument("--long-steps", type=int, default=400, help="the clock-phase rows' bound (runs end before it)")
    p.add_argument("--short-steps", type=int, default=30, help="the interleaving rows' bound")
    p = sub.add_parser("song2014")
    p.add_argument("--max-steps", type=int, default=60)
    p = sub.add_parser("perf")
    p.add_argument("--plot", default=None)
    for q in sub.choices.values():
        q.add_argument("--json", default=None)
    a = ap.parse_args(argv)
    print(f"<!-- {platform.node()} {platform.machine()} Python {platform.python_version()} "
          f"{datetime.date.today().isoformat()} cpus {os.cpu_count()} load {os.getloadavg()[0]:.1f} -->", flush=True)
    t0 = time.process_time()
    if a.mode == "jiang":
        out = jiang(a.starts, a.deviations, a.max_delay, a.max_steps)
    elif a.mode == "wang2020":
        out = wang2020(a.long_steps, a.short_steps)
    elif a.mode == "song2014":
        out = song2014(a.max_steps)
    else:
        out = perf(a.plot)
    print(f"\ntotal CPU {time.process_time() - t0:.1f} s")
    if a.json:
        atomic_write_text(a.json, dumps_json(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
