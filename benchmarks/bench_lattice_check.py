"""Benchmark of the lattice-graph checker (issue 2: performance targets; issue 29 item 2).

Targets: a 20 x 20 supercell of the square lattice (400 roles, 1,600 edges)
decided in under 1 s beyond interpreter start-up; every bundled lattice in
under 0.2 s; a 100 x 100 supercell (10,000 roles, 40,000 edges) written as a
1.3 MB JSON file, read and checked as `swarmproof check-lattice FILE` does
(load + check + report), in under 3 s; the same as YAML is reported, with no
target (YAML parsing is slower: libyaml where installed); a file with 1,000
identical rows (one duplicate group) in under 1 s, 10,000 in under 3 s and 30,000 in under 9 s (linear).  Prints a table (best of ``--repeat`` runs, wall clock, after one
warm-up run that also pays numpy/scipy/networkx first-call costs) and exits 1
if a target is missed.  Figures go in docs/performance.md.

Run: ``.venv/bin/python benchmarks/bench_lattice_check.py [--repeat 5]`` (``--repeat`` is capped
at 3 for the file cases).
"""

from __future__ import annotations

import argparse
import platform
import sys
import time

import os
import tempfile

from swarmproof.checkers.lattice_check import check_lattice
from swarmproof.models import library
from swarmproof.models.lattice_io import load_lattice_file, save_lattice
from swarmproof.models.lattice import LatticeGraph
from swarmproof.models.se2 import SE2


def square_supercell(n: int) -> LatticeGraph:
    """The square lattice with an n x n supercell: n*n roles, 4 n*n edges (torus wiring)."""
    roles = [f"r{i}_{j}" for i in range(n) for j in range(n)]
    edges = []
    for i in range(n):
        for j in range(n):
            for dx, dy in ((1, 0), (0, 1), (-1, 0), (0, -1)):
                edges.append((f"r{i}_{j}", f"r{(i + dx) % n}_{(j + dy) % n}", SE2(dx, dy, 0.0)))
    return LatticeGraph(f"square-supercell-{n}x{n}", roles, edges, range=1.2)


def check_file(path: str):
    """What `swarmproof check-lattice FILE --json` does beyond start-up: read, check, report."""
    g = load_lattice_file(path)
    rep = check_lattice(g)
    rep.to_json()
    rep.format_human()
    return g, rep


def best_of(fn, repeat: int) -> tuple[float, object]:
    fn()  # warm-up
    best, out = float("inf"), None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    rows = []
    ok = True
    cases = [(name, library.load(name), None, 0.2) for name in library.names()]
    sc = square_supercell(20)
    cases.append((sc.name, sc, 1.2, 1.0))
    cases.append((sc.name + " @1.5 (1,600 missing edges)", sc, 1.5, 1.0))
    for label, g, phi, target in cases:
        secs, rep = best_of(lambda: check_lattice(g, phi), args.repeat)
        met = secs < target
        ok &= met
        rows.append((label, len(g.roles), len(g.edges), rep.verdict.value,
                     rep.classification["kind"], len(rep.defects), secs, target, met))
    with tempfile.TemporaryDirectory() as d:
        big = square_supercell(100)
        files = []
        for ext, target in ((".json", 3.0), (".yaml", None)):
            path = os.path.join(d, "supercell-100" + ext)
            save_lattice(big, path)
            files.append((f"file {big.name}{ext} ({os.path.getsize(path) / 1e6:.1f} MB)", path, target))
        # identical rows: one duplicate group, and each inverse found once (linear, issue 29 item 2:
        # 10,000 took 16.7 s and 30,000 177 s while every pair of rows was compared)
        for copies, target in ((1000, 1.0), (10000, 3.0), (30000, 9.0)):
            dup = os.path.join(d, f"dup{copies}.json")
            with open(dup, "w") as f:
                f.write('{"format": "lattice-graph/1", "range": 1.2, "roles": ["A"], "edges": ['
                        + ", ".join(['["A", "A", 1, 0, 0]'] * copies) + ', ["A", "A", -1, 0, 0]]}')
            files.append((f"file dup{copies}.json ({copies:,} identical rows)", dup, target))
        for label, path, target in files:
            secs, (g, rep) = best_of(lambda: check_file(path), max(1, min(args.repeat, 3)))
            met = target is None or secs < target
            ok &= met
            rows.append((label, len(g.roles), len(g.edges), rep.verdict.value, rep.classification["kind"],
                         len(rep.defects), secs, target, met))
    print(f"# lattice checker benchmark, {platform.machine()} {platform.system()}, "
          f"Python {platform.python_version()}, best of {args.repeat}")
    print(f"{'lattice':52} {'roles':>6} {'edges':>6} {'verdict':>8} {'kind':>8} "
          f"{'defects':>7} {'ms':>8} {'target':>7}  ok")
    for label, nr, ne, v, k, nd, secs, target, met in rows:
        tgt = "-" if target is None else f"{target * 1e3:.0f}ms"
        print(f"{label:52} {nr:6d} {ne:6d} {v:>8} {str(k):>8} {nd:7d} {secs * 1e3:8.1f} "
              f"{tgt:>7}  {'yes' if met else 'NO'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
