"""Jiang et al. (002) benchmarks: speed, and the experiments of Sec. V-A.

Usage (from the repository root)::

    .venv/bin/python benchmarks/jiang/bench_jiang.py perf                     # n = 300: run and epsilon times
    .venv/bin/python benchmarks/jiang/bench_jiang.py sec5 --seeds 5           # Fig. 7a/7b table + plot
    .venv/bin/python benchmarks/jiang/bench_jiang.py compare --seeds 5        # against song2016, same starts

``sec5``: the four patterns of Fig. 1 (bundled), n = 50..300 in steps of 50,
uniform starts in a 15 m x 15 m square (Sec. V-A), 10 cm/s; per cell the
formation quality epsilon (Def. 9, exact), Sec. V-A's alignment measure (and in how many
runs it is 1, whether n / |B| copies fill whole layers of the growth, and how many distinct
formations up to translation the runs of a cell ended in), the
total distance and the runs in which two robots came closer than 14 cm (the
PiBot's diameter).  ``compare``: jiang toward ``lattice:square`` (one point,
the square lattice's edges) and song2016 on the square lattice from the same
seeded connected starts (range 1.2, unit edges; 002 does not give song2016's
range); total distance of both.  Each mode prints a Markdown table; ``--json
FILE`` writes the numbers and ``--plot FILE`` a PNG (atomically).  Seeded:
the same command prints the same experiment numbers (timings vary).
"""

from __future__ import annotations

import argparse
import datetime
import platform
import statistics
import sys
import time
from pathlib import Path

from swarmproof.models.fileio import atomic_write_text, dumps_json
from swarmproof.models.repeating_pattern import load_pattern, resolve_pattern

# benchmarks/ is not a package: put it on sys.path so that ``jiang.experiments`` (this folder's
# benchmarks/jiang/experiments.py) imports both when this runs as ``python benchmarks/jiang/bench_jiang.py``
# (sys.path[0] is then benchmarks/jiang/) and when a test loads it by path (tests/testkit.py).
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from jiang.experiments import run_sec5, uniform_start  # noqa: E402

FIG1 = ("square-segments", "triangle-segments", "rhombus-triangles", "trapezoid-hexagons")
SIZES = (50, 100, 150, 200, 250, 300)


def _ms(xs) -> str:
    xs = [float(x) for x in xs if x is not None]
    if not xs:
        return ""
    return f"{statistics.mean(xs):.4g}" if len(xs) == 1 else f"{statistics.mean(xs):.4g} ± {statistics.stdev(xs):.2g}"


def perf() -> dict:
    from swarmproof.models.formation_quality import formation_quality

    pat = load_pattern("rhombus-triangles")
    out = {}
    for n in (150, 300):
        t0 = time.perf_counter()
        r = run_sec5("jiang", pat, n, 0)
        t_run = time.perf_counter() - t0
        pts = pat.formation(n)
        t0 = time.perf_counter()
        q = formation_quality(pts, pat.basic, pat.assembling, tol=pat.tol)
        t_eps = time.perf_counter() - t0
        out[n] = {"run_s": t_run, "steps": r["steps"], "status": r["status"], "epsilon_s": t_eps,
                  "epsilon": str(q.epsilon), "method": q.method}
        print(f"n={n}: run {t_run:.2f} s ({r['steps']} steps, {r['status']}), epsilon of the formation "
              f"{q.epsilon} in {t_eps * 1000:.1f} ms ({q.method})", flush=True)
    # the integer program: a formation with a few robots displaced (no perfect cover)
    pts = pat.formation(300).copy()
    pts[::37] += 0.11
    t0 = time.perf_counter()
    q = pat.quality(pts)
    out["milp_300"] = {"epsilon_s": time.perf_counter() - t0, "gamma": str(q.gamma), "method": q.method,
                       "size": q.size}
    print(f"n=300 with {len(pts[::37])} robots displaced: gamma {q.gamma} ({q.method}, {q.size}) in "
          f"{out['milp_300']['epsilon_s']:.2f} s", flush=True)
    return out


def sec5(seeds: int, sizes, patterns) -> list[dict]:
    rows = []
    for name in patterns:
        pat = load_pattern(name)
        for n in sizes:
            runs = [run_sec5("jiang", pat, n, s) for s in range(seeds)]
            row = {"pattern": name, "n": n, "runs": runs}
            rows.append(row)
            eps1 = sum(r["epsilon_exact"] == "1" for r in runs)
            print(f"  {name} n={n}: epsilon = 1 in {eps1}/{len(runs)}", file=sys.stderr, flush=True)
    print("| pattern | n | |B| divides n | whole layers | finished | epsilon = 1 | epsilon (mean) | "
          "alignment (mean ± sd) | alignment = 1 | formations | "
          "total distance, m (mean ± sd) | steps (mean ± sd) | runs with robots < 14 cm apart |")
    print("|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for row in rows:
        pat = load_pattern(row["pattern"])
        runs, b = row["runs"], len(pat.basic)
        k = len(runs)
        print(f"| {row['pattern']} | {row['n']} | {'yes' if row['n'] % b == 0 else 'no'} | "
              f"{'yes' if pat.fills_whole_layers(row['n']) else 'no'} | "
              f"{sum(r['status'] == 'finished' for r in runs)}/{k} | "
              f"{sum(r['epsilon_exact'] == '1' for r in runs)}/{k} | {_ms([r['epsilon'] for r in runs])} | "
              f"{_ms([r['alignment'] for r in runs])} | {sum(r['alignment'] == 1 for r in runs)}/{k} | "
              f"{len({r['shape'] for r in runs})} | {_ms([r['total_distance'] for r in runs])} | "
              f"{_ms([r['steps'] for r in runs])} | {sum(r['collides'] for r in runs)}/{k} |")
    return rows


def compare(seeds: int, sizes) -> list[dict]:
    from swarmproof.checkers.runs import run_and_check
    from swarmproof.models import library
    from swarmproof.reference_impl.initial import random_connected

    lat = library.load("square")
    pat = resolve_pattern("lattice:square")
    rows = []
    print("| n | runs | jiang total distance (mean ± sd) | song2016 total distance (mean ± sd) | "
          "jiang / song2016 | jiang epsilon = 1 | song2016 satisfies Def. 2 |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for n in sizes:
        js, ss = [], []
        for s in range(seeds):
            start = random_connected(n, s, range=1.2)
            j = run_and_check("jiang", pat, seed=s, initial=start, phi=1.2)
            g = run_and_check("song2016", lat, seed=s, initial=start, phi=1.2)
            js.append(j.doc)
            ss.append(g.doc)
        jd = [d["total_distance"] for d in js]
        sd = [d["total_distance"] for d in ss]
        rows.append({"n": n, "jiang": jd, "song2016": sd,
                     "jiang_eps1": sum(d["metrics"]["epsilon_exact"] == "1" for d in js),
                     "song_sat": sum(d["satisfied"] is True for d in ss)})
        print(f"| {n} | {seeds} | {_ms(jd)} | {_ms(sd)} | {statistics.mean(jd) / statistics.mean(sd):.3f} | "
              f"{rows[-1]['jiang_eps1']}/{seeds} | {rows[-1]['song_sat']}/{seeds} |", flush=True)
    return rows


def plot_sec5(rows, path) -> str:
    import matplotlib

    matplotlib.use("Agg")
    from swarmproof.checkers.plotting import new_figure, save_png

    fig, _ = new_figure(11.0, 4.0)
    fig.clf()
    a, b = fig.subplots(1, 2)
    for name in dict.fromkeys(r["pattern"] for r in rows):
        rs = [r for r in rows if r["pattern"] == name]
        ns = [r["n"] for r in rs]
        a.plot(ns, [statistics.mean(x["epsilon"] for x in r["runs"]) for r in rs], "o-", label=name)
        b.errorbar(ns, [statistics.mean(x["total_distance"] for x in r["runs"]) for r in rs],
                   yerr=[statistics.stdev(x["total_distance"] for x in r["runs"]) if len(r["runs"]) > 1 else 0
                         for r in rs], fmt="o-", capsize=3, label=name)
    a.set_xlabel("robots")
    a.set_ylabel("formation quality epsilon (Def. 9), mean")
    a.set_ylim(0, 1.05)
    b.set_xlabel("robots")
    b.set_ylabel("total distance, m (mean ± sd)")
    a.legend(fontsize=8)
    b.legend(fontsize=8)
    fig.suptitle("jiang, 002 Sec. V-A: uniform starts in 15 m x 15 m, 10 cm/s", fontsize=10)
    return save_png(fig, path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("mode", choices=("perf", "sec5", "compare"))
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--sizes", default=None, help="comma-separated team sizes")
    ap.add_argument("--patterns", default=",".join(FIG1))
    ap.add_argument("--json", default=None)
    ap.add_argument("--plot", default=None)
    args = ap.parse_args(argv)
    print(f"<!-- {platform.node()} {platform.machine()} Python {platform.python_version()} "
          f"{datetime.date.today().isoformat()} -->")
    if args.mode == "perf":
        out = perf()
    elif args.mode == "sec5":
        sizes = SIZES if args.sizes is None else tuple(int(x) for x in args.sizes.split(","))
        out = sec5(args.seeds, sizes, args.patterns.split(","))
        if args.plot:
            plot_sec5(out, args.plot)
    else:
        sizes = (10, 20, 40) if args.sizes is None else tuple(int(x) for x in args.sizes.split(","))
        out = compare(args.seeds, sizes)
    if args.json:
        atomic_write_text(args.json, dumps_json(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
