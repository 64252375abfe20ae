"""Lee & Chong (003) Tables 2-5: the paper's A-team / F-team data, its exceptions, and our re-run.

Usage (from the repository root)::

    MPLBACKEND=Agg .venv/bin/python benchmarks/leechong/leechong_tables.py                # all, both approaches
    MPLBACKEND=Agg .venv/bin/python benchmarks/leechong/leechong_tables.py --approach leader --testbeds 2 \\
        --json /tmp/t.json --plot-dir /tmp                                       # smaller
    .venv/bin/python benchmarks/leechong/leechong_tables.py --paper-only                  # the paper's exceptions

What it does (003 Secs. 3.7 and 4.6, Tables 2-5, Figs. 16 and 25):

* :data:`PAPER` holds Tables 2-5 exactly as printed in the seed
  (``../shared/seeds/003_8f3001202a798af8.txt``): per approach (leader / neighbor
  reference), per measure (distance / time in s), per pattern, five testbeds of
  ``(A, F)`` pairs.  :func:`paper_exceptions` lists every cell where the A-team's
  number is larger than the F-team's, against the paper's "A-team exhibits less
  distance moved [and] less pattern generation time for all patterns" (Secs. 3.7,
  4.6); :func:`paper_mean_exceptions` does the same for the per-pattern means.
* :func:`rerun` runs 12 robots on the 8 patterns of the tables, on 5 testbeds
  (seeded random starts, :func:`testbed`; the same start for every team and both
  approaches), with the columns of :data:`COLUMNS`: the A-team by default (Sec. 2.1's
  prose numbering, reading "2" since issue 31), with Alg. 1's printed formula (the
  ``-printed`` variants, the default up to 0.1.0), with ``id_order=leader-first``, with
  both, and the F-team (fixed labels, Sec. 3.7).  Distance
  is ``total_distance`` (the sum over robots, Sec. 3.7 "summing distance moved by
  all team members"); time is ``steps x dt`` of the run, which ends when the leader
  sees the pattern stand (it then stops and every follower is at its target);
  ``satisfied`` says whether the final positions *are* the pattern (up to a rigid
  motion, DESIGN.md section 5): a run whose IDs are not 0..n-1 ends at rest but not
  in the pattern, so its time is not a "time to form" and is marked.
* Writes a Markdown table on stdout, ``--json FILE`` the numbers, and
  ``--plot-dir DIR`` the PNGs ``leechong-tables-leader.png`` and
  ``leechong-tables-neighbor.png`` in the style of Figs. 16 / 25: bars per pattern
  (mean over the testbeds; grey A-team, hatched F-team) and lines for testbed-2
  (solid red A-team, dashed blue F-team), the paper's table above ours.

Deterministic: testbed k is ``random_connected(12, k, range=2.0)`` and the run's
seed is k; the same command writes the same numbers (timings vary).
"""

from __future__ import annotations

import argparse
import datetime
import platform
import statistics
import sys
import time

from swarmproof.models.errors import UsageError

__all__ = ["PAPER", "PATTERNS", "PAPER_PATTERNS", "COLUMNS", "TESTBEDS",
           "paper_exceptions", "paper_mean_exceptions", "paper_repeated_cells", "testbed", "run_cell", "rerun", "summarize",
           "our_exceptions", "markdown_paper", "markdown_ours", "plot_approach"]

#: The patterns of Tables 2-5, in the tables' order: (the paper's row name, our bundled name).
PAPER_PATTERNS = (("Three rows", "three-row"), ("Two columns", "two-column"), ("Wedge", "wedge"),
                  ("Triangle", "triangle"), ("Diamond", "diamond"), ("Hexagon", "hexagon"),
                  ("Arc", "arc"), ("Circle", "circle"))
PATTERNS = tuple(p for _, p in PAPER_PATTERNS)
#: Testbed k (1..5) is the seeded random start k.
TESTBEDS = (1, 2, 3, 4, 5)
N_ROBOTS = 12
START_RANGE = 2.0

# ---------------------------------------------------------------------------------------------
# The paper's tables (transcribed from the seed; rows: testbeds 1..5 as (A, F))
# ---------------------------------------------------------------------------------------------


def _rows(text: str) -> dict:
    out = {}
    for line, (_, name) in zip(text.strip().splitlines(), PAPER_PATTERNS):
        xs = [float(x) for x in line.split()]
        out[name] = tuple((xs[2 * k], xs[2 * k + 1]) for k in range(5))
    return out


#: 003 Tables 2-5 as printed: ``PAPER[approach][measure][pattern][testbed - 1] == (A, F)``.
#: Table 2: leader reference, distance; Table 3: leader, time (s); Table 4: neighbor, distance;
#: Table 5: neighbor, time (s).  Units as printed (distance: the simulation's units; time: s).
PAPER = {
    "leader": {
        "distance": _rows("""
            32.7 93.1 58.4 118.9 65.5 109.6 62.3 110.6 89.9 112.1
            71.4 124.1 115.1 141.1 118.9 167 117.4 132.3 144.4 152.2
            90.9 157.5 110.4 163.2 113.2 170.5 109.1 154.7 151.3 169.5
            49.3 107.8 41 116.7 37.7 113.5 38.1 111.8 80.9 107.9
            67.5 120.8 33.6 123.5 33.2 127.9 37.2 119.1 64.1 113.6
            46.8 120.7 50.3 119.6 49.3 124 46.6 124.8 89.6 119.3
            101.2 147.6 128.1 178.3 132.1 182.7 127.2 168.2 164.9 185.6
            48.9 120.2 55.6 124.5 52.4 139.8 49.8 128.2 93 121.5"""),
        "time": _rows("""
            11.9 15.27 5.08 19.81 4.47 13.68 5.45 12.24 11.9 9.66
            11.61 20.12 7.64 12.82 6.52 27.08 8.85 11.66 7.81 11.61
            12.15 12.11 6.98 9.64 8.3 12.31 9.6 7.39 10.15 8.93
            6.66 17.13 4.17 17.69 3.54 11.86 7.36 11.47 6.66 9.32
            6.31 16.86 3.53 14.94 4.24 15.27 4.6 13.15 6.31 9.68
            7.3 10.99 5.21 10.79 3.52 12.89 4.56 9.26 7.3 13.17
            11.46 14.45 8.36 11.45 8.15 12.44 9.37 7.89 11.46 10.34
            7.43 9.54 6.14 11.22 3.49 23.02 4.35 9.35 7.43 9.72"""),
    },
    "neighbor": {
        "distance": _rows("""
            152.9 159 162.7 197.2 141.7 207.3 182.9 197.8 174.1 218.2
            173.9 208.6 223.9 234.7 239 234.7 217 250.8 224.9 225.5
            102.4 206.1 125.2 225 142.3 227.6 126.6 218.5 179.7 235.2
            101.9 167.4 88.9 187.3 109.4 200 95.9 186.9 147.6 187.4
            82.7 189.3 90.7 189.7 121.3 209.8 94.6 203.2 152 187
            102.2 204.3 152.4 208.1 121.3 220.7 137.4 211.7 160.8 219.6
            150.4 255.4 175.5 271.3 184.9 273.9 164.1 287.2 229.1 278.5
            109.9 179.5 125.1 208 144.5 213.4 110.3 209.9 170.5 207.1"""),
        "time": _rows("""
            12.29 20.91 13.91 17.38 13.23 14.67 12.79 16.34 13.32 18.15
            10.83 15.65 14.96 18.01 14.86 12.24 14.93 18.79 16.28 17.48
            9.17 15.78 10.63 12.83 9.34 13.96 10.63 25.09 16.15 24.94
            12.26 18.59 11.47 14.92 12.72 18.15 15.34 17.75 17.66 15.62
            13.8 24.47 10.68 19.78 17.73 20.17 12.24 16.05 14.05 17.02
            13.8 24.39 14.92 15.24 11.2 14.45 16.75 13.95 25.23 23.18
            10.73 21.65 10.52 15.27 12.61 23.78 13.38 17.45 13.96 20.56
            11.23 22.64 10.91 18.12 13.79 15.43 8.74 24.08 15.57 34.06"""),
    },
}

TABLE_OF = {("leader", "distance"): "Table 2", ("leader", "time"): "Table 3",
            ("neighbor", "distance"): "Table 4", ("neighbor", "time"): "Table 5"}
CLAIM_OF = {"leader": "003 Sec. 3.7: 'A-team exhibits less distance moved for all patterns ... also requires less "
                      "pattern generation time for all patterns'",
            "neighbor": "003 Sec. 4.6: 'the proposed A-team exhibits less distance moved and less generation time "
                        "than the F-team for all patterns'"}


def paper_exceptions(table=None) -> list:
    """Every cell of 003 Tables 2-5 where the A-team's number exceeds the F-team's (or equals it).

    Returns dicts ``{table, approach, measure, pattern, testbed, A, F}`` in table order.

    >>> [(e["table"], e["pattern"], e["testbed"], e["A"], e["F"]) for e in paper_exceptions()][:2]
    [('Table 3', 'three-row', 5, 11.9, 9.66), ('Table 3', 'wedge', 1, 12.15, 12.11)]
    >>> len(paper_exceptions()), len(paper_exceptions(PAPER["leader"]["distance"]))
    (11, 0)
    """
    out = []
    items = TABLE_OF.items() if table is None else [(None, None)]
    for key, name in items:
        tab = table if key is None else PAPER[key[0]][key[1]]
        for pat in PATTERNS:
            for k, (a, f) in enumerate(tab[pat], start=1):
                if a >= f:
                    out.append({"table": name, "approach": None if key is None else key[0],
                                "measure": None if key is None else key[1], "pattern": pat, "testbed": k,
                                "A": a, "F": f})
    return out


def paper_repeated_cells() -> list:
    """Cells of the A-team's testbed-5 column that repeat testbed-1's exactly (Tables 2-5).

    Table 3 (leader reference, time) prints the same A-team time for testbeds 1 and 5 in six of
    its eight rows, where the starts differ (their distances in Table 2 differ): probably a copy
    error in the paper; no other table repeats a column.

    >>> [(e["table"], e["pattern"], e["A"]) for e in paper_repeated_cells()][:2]
    [('Table 3', 'three-row', 11.9), ('Table 3', 'triangle', 6.66)]
    >>> len(paper_repeated_cells())
    6
    """
    out = []
    for (app, meas), name in TABLE_OF.items():
        for pat in PATTERNS:
            cells = PAPER[app][meas][pat]
            if cells[0][0] == cells[4][0]:
                out.append({"table": name, "pattern": pat, "A": cells[0][0]})
    return out


def paper_mean_exceptions() -> list:
    """Patterns whose mean over the five testbeds is not smaller for the A-team (Tables 2-5).

    >>> paper_mean_exceptions()
    []
    """
    out = []
    for (app, meas), name in TABLE_OF.items():
        for pat in PATTERNS:
            cells = PAPER[app][meas][pat]
            a, f = statistics.mean(c[0] for c in cells), statistics.mean(c[1] for c in cells)
            if a >= f:
                out.append({"table": name, "pattern": pat, "A_mean": a, "F_mean": f})
    return out


# ---------------------------------------------------------------------------------------------
# Our re-run
# ---------------------------------------------------------------------------------------------


#: The columns of the re-run: (label, team, {approach: (algorithm, extra params)}).  A: the
#: defaults (Sec. 2.1's prose IDs); A-printed: Alg. 1's printed formula (the registered
#: ``-printed`` variants, issue 31); ``-leader-first``: Sec. 3.2's order (``id_order``).
COLUMNS = (
    ("A", "A", {"leader": ("leechong-leader", {}), "neighbor": ("leechong-neighbor", {})}),
    ("A-printed", "A", {"leader": ("leechong-leader-printed", {}), "neighbor": ("leechong-neighbor-printed", {})}),
    ("A-leader-first", "A", {"leader": ("leechong-leader", {"id_order": "leader-first"}),
                             "neighbor": ("leechong-neighbor", {"id_order": "leader-first"})}),
    ("A-printed-leader-first", "A", {"leader": ("leechong-leader-printed", {"id_order": "leader-first"}),
                                     "neighbor": ("leechong-neighbor-printed", {"id_order": "leader-first"})}),
    ("F", "F", {"leader": ("leechong-leader-fteam", {}), "neighbor": ("leechong-neighbor-fteam", {})}),
)
COLUMN_NAMES = tuple(c[0] for c in COLUMNS)


def testbed(k: int):
    """Testbed ``k``: 12 robots at a seeded random connected start (range 2: every robot at least
    0.5 intervals from the others, 003 Sec. 6.1's 600 mm at a 1000 mm interval).

    >>> t = testbed(1)
    >>> t.n, testbed(1).poses.tolist() == t.poses.tolist(), sorted(t.ids.tolist()) == list(range(12))
    (12, True, True)
    """
    from swarmproof.reference_impl.initial import random_connected

    import numpy as np

    from swarmproof.models.trace import InitialConfiguration

    if int(k) != k or k < 0:
        raise UsageError(f"testbed={k!r} must be an integer >= 0", fix="e.g. 1 (testbeds 1..5)")
    start = random_connected(N_ROBOTS, int(k), range=START_RANGE)
    # The F-team's fixed labels are the robots' IDs: a seeded permutation, so that they owe nothing
    # to the start's construction order (random_connected places each robot next to an earlier
    # one, so its order is spatially coherent).  The A-team never sees them (anonymous).
    labels = np.random.default_rng(np.random.SeedSequence(int(k), spawn_key=(7,))).permutation(N_ROBOTS)
    return InitialConfiguration(labels.tolist(), start.poses)


def run_cell(approach: str, column: str, pattern: str, k: int) -> dict:
    """One run: ``column`` of :data:`COLUMNS` on ``pattern`` from testbed ``k``.

    Returns ``{approach, column, pattern, testbed, algorithm, distance, steps, time, satisfied,
    status, ids_unique, seconds}``; ``time = steps x dt`` (simulated seconds).
    """
    from swarmproof.checkers.runs import run_and_check
    from swarmproof.models.targets import resolve_target

    cols = {c[0]: c for c in COLUMNS}
    if approach not in ("leader", "neighbor"):
        raise UsageError(f"approach={approach!r} is not 'leader' or 'neighbor'")
    if column not in cols:
        raise UsageError(f"column={column!r} is not one of {list(cols)!r}")
    if pattern not in PATTERNS:
        raise UsageError(f"pattern={pattern!r} is not a pattern of Tables 2-5", fix=f"use one of {list(PATTERNS)!r}")
    alg, extra = cols[column][2][approach]
    t0 = time.perf_counter()
    c = run_and_check(alg, resolve_target("lines:" + pattern), seed=int(k), initial=testbed(k), extra=extra)
    d = c.doc
    return {"approach": approach, "column": column, "pattern": pattern, "testbed": int(k),
            "algorithm": d["algorithm"] + "".join(f" {a}={b}" for a, b in extra.items()),
            "distance": float(d["total_distance"]), "steps": int(d["steps"]),
            "time": float(d["steps"]) * float(d["params"]["dt"]), "satisfied": d["satisfied"],
            "status": d["status"], "ids_unique": d["metrics"].get("ids_unique"),
            "seconds": time.perf_counter() - t0}


def rerun(approaches=("leader", "neighbor"), patterns=PATTERNS, testbeds=TESTBEDS, columns=COLUMN_NAMES,
          progress=None) -> list:
    """Every run of the re-run as :func:`run_cell` dicts (approach, pattern, testbed, column order)."""
    out = []
    for app in approaches:
        for pat in patterns:
            for k in testbeds:
                for col in columns:
                    r = run_cell(app, col, pat, k)
                    out.append(r)
                    if progress is not None:
                        progress(r)
    return out


def summarize(runs) -> dict:
    """``{(approach, pattern, column): {distance, time (means), satisfied (count), runs}}``."""
    groups: dict = {}
    for r in runs:
        groups.setdefault((r["approach"], r["pattern"], r["column"]), []).append(r)
    return {key: {"distance": statistics.mean(r["distance"] for r in rs), "time": statistics.mean(r["time"] for r in rs),
                  "satisfied": sum(r["satisfied"] is True for r in rs), "runs": len(rs)}
            for key, rs in groups.items()}


def our_exceptions(runs, a_column: str = "A") -> list:
    """Cells of our re-run where the A-team column ``a_column`` is not below the F-team:
    ``{approach, measure, pattern, testbed, A, F, A_satisfied, F_satisfied}``."""
    by = {(r["approach"], r["pattern"], r["testbed"], r["column"]): r for r in runs}
    out = []
    for (app, pat, k, col), a in sorted(by.items(), key=lambda kv: (kv[0][0], PATTERNS.index(kv[0][1]), kv[0][2])):
        if col != a_column or (app, pat, k, "F") not in by:
            continue
        f = by[(app, pat, k, "F")]
        for meas in ("distance", "time"):
            if a[meas] >= f[meas]:
                out.append({"approach": app, "measure": meas, "pattern": pat, "testbed": k, "A": a[meas],
                            "F": f[meas], "A_satisfied": a["satisfied"], "F_satisfied": f["satisfied"]})
    return out


# ---------------------------------------------------------------------------------------------
# Output
# ---------------------------------------------------------------------------------------------


def markdown_paper() -> str:
    """The paper's four tables as one Markdown table per approach and measure, the cells where
    A >= F in bold."""
    lines = []
    for (app, meas), name in TABLE_OF.items():
        lines.append(f"**{name}** (003, {app} reference, {meas}{' in s' if meas == 'time' else ''}); "
                     "bold: A >= F, against the paper's claim")
        lines.append("")
        lines.append("| pattern | " + " | ".join(f"TB{k} A | TB{k} F" for k in TESTBEDS) + " | mean A | mean F |")
        lines.append("|---|" + "---:|---:|" * len(TESTBEDS) + "---:|---:|")
        for paper_name, pat in PAPER_PATTERNS:
            cells = PAPER[app][meas][pat]
            row = []
            for a, f in cells:
                row += [f"**{a:g}**" if a >= f else f"{a:g}", f"{f:g}"]
            ma, mf = statistics.mean(c[0] for c in cells), statistics.mean(c[1] for c in cells)
            lines.append(f"| {paper_name} | " + " | ".join(row) + f" | {ma:.4g} | {mf:.4g} |")
        lines.append("")
    return "\n".join(lines)


def markdown_ours(runs) -> str:
    """Our re-run: per approach, pattern and column the mean distance and time over the testbeds
    and how many runs ended in the pattern."""
    s = summarize(runs)
    cols = [c for c in COLUMN_NAMES if any(k[2] == c for k in s)]
    lines = []
    for app in dict.fromkeys(k[0] for k in s):
        nb = max(v["runs"] for k, v in s.items() if k[0] == app)
        lines.append(f"**Ours, {app} reference** (12 robots, {nb} testbeds; distance in intervals d_u, "
                     "time = steps x dt; 'formed' = runs whose final positions are the pattern)")
        lines.append("")
        lines.append("| pattern | " + " | ".join(f"{c} distance | {c} time | {c} formed" for c in cols) + " |")
        lines.append("|---|" + "---:|---:|---:|" * len(cols))
        for pat in PATTERNS:
            cells = []
            for c in cols:
                v = s.get((app, pat, c))
                cells += ["", "", ""] if v is None else [f"{v['distance']:.1f}", f"{v['time']:.1f}",
                                                           f"{v['satisfied']}/{v['runs']}"]
            if any(cells):
                lines.append(f"| {pat} | " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


def plot_approach(runs, approach: str, path) -> str:
    """Figs. 16 / 25 style: (a) distance and (b) time per pattern; bars = mean over the testbeds
    (grey A-team default, dotted A-team printed formula, cross-hatched default + leader-first, hatched
    F-team), lines = testbed-2 (solid red A, dashed
    blue F); top row the paper's table, bottom row ours.  A bar whose runs did not all end in the
    pattern is labelled with the count that did."""
    import numpy as np

    from swarmproof.checkers.plotting import new_figure, save_png

    s = summarize(runs)
    fig, _ = new_figure(13.0, 8.0)
    fig.clf()
    axes = fig.subplots(2, 2)
    x = np.arange(len(PATTERNS))
    for j, meas in enumerate(("distance", "time")):
        ax = axes[0, j]
        tab = PAPER[approach][meas]
        a = [statistics.mean(c[0] for c in tab[p]) for p in PATTERNS]
        f = [statistics.mean(c[1] for c in tab[p]) for p in PATTERNS]
        ax.bar(x - 0.2, a, 0.4, color="0.6", edgecolor="black", label="A-team (mean of 5)")
        ax.bar(x + 0.2, f, 0.4, color="white", edgecolor="black", hatch="///", label="F-team (mean of 5)")
        ax.plot(x, [tab[p][1][0] for p in PATTERNS], "-o", color="red", ms=3, label="A, testbed-2")
        ax.plot(x, [tab[p][1][1] for p in PATTERNS], "--s", color="blue", ms=3, label="F, testbed-2")
        ax.set_title(f"003 {TABLE_OF[(approach, meas)]}: {meas} ({approach} reference)", fontsize=10)
        ax = axes[1, j]
        cols = [("A", "0.6", None, -0.3), ("A-printed", "0.85", "..", -0.1), ("A-leader-first", "0.95", "xx", 0.1),
                ("F", "white", "///", 0.3)]
        for col, color, hatch, dx in cols:
            vals = [s.get((approach, p, col), {}).get(meas, np.nan) for p in PATTERNS]
            bars = ax.bar(x + dx, vals, 0.2, color=color, edgecolor="black", hatch=hatch,
                          label=f"{col} (mean)")
            for b, p in zip(bars, PATTERNS):
                v = s.get((approach, p, col))
                if v is not None and v["satisfied"] < v["runs"]:
                    ax.annotate(f"{v['satisfied']}/{v['runs']}", (b.get_x() + b.get_width() / 2, b.get_height()),
                                ha="center", va="bottom", fontsize=6, color="darkred")
        by = {(r["pattern"], r["column"]): r for r in runs if r["approach"] == approach and r["testbed"] == 2}
        if by:
            ax.plot(x, [by.get((p, "A"), {}).get(meas, np.nan) for p in PATTERNS], "-o", color="red", ms=3,
                    label="A, testbed-2")
            ax.plot(x, [by.get((p, "F"), {}).get(meas, np.nan) for p in PATTERNS], "--s", color="blue", ms=3,
                    label="F, testbed-2")
        unit = "d_u" if meas == "distance" else "steps x dt"
        ax.set_title(f"ours: {meas} ({unit}); red n/5: runs that formed the pattern", fontsize=10)
        for ax in axes[:, j]:
            ax.set_xticks(x)
            ax.set_xticklabels(PATTERNS, rotation=30, fontsize=8)
            ax.set_aspect("auto")
            ax.legend(fontsize=7)
    fig.suptitle(f"Lee & Chong (003) A-team vs F-team, {approach}-referenced control, 12 robots", fontsize=11)
    fig.tight_layout()
    return save_png(fig, path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--approach", choices=("leader", "neighbor", "both"), default="both")
    ap.add_argument("--testbeds", type=int, default=len(TESTBEDS), help="how many testbeds (1..5)")
    ap.add_argument("--patterns", default=",".join(PATTERNS))
    ap.add_argument("--json", default=None)
    ap.add_argument("--plot-dir", default=None)
    ap.add_argument("--paper-only", action="store_true")
    args = ap.parse_args(argv)
    try:
        if not 1 <= args.testbeds <= len(TESTBEDS):
            raise UsageError(f"testbeds={args.testbeds!r} must be in 1..{len(TESTBEDS)}")
        patterns = tuple(p.strip() for p in args.patterns.split(",") if p.strip())
        bad = [p for p in patterns if p not in PATTERNS]
        if bad:
            raise UsageError(f"patterns={bad!r} are not patterns of Tables 2-5", fix=f"use some of {list(PATTERNS)!r}")
    except UsageError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(f"<!-- {platform.node()} {platform.machine()} Python {platform.python_version()} "
          f"{datetime.date.today().isoformat()} -->")
    print(markdown_paper())
    print("Cells where the paper's own data has A >= F:")
    for e in paper_exceptions():
        print(f"- {e['table']} ({e['approach']}, {e['measure']}): {e['pattern']}, testbed-{e['testbed']}: "
              f"A {e['A']:g} vs F {e['F']:g}")
    print(f"Per-pattern means with A >= F: {paper_mean_exceptions() or 'none'}")
    if args.paper_only:
        return 0
    approaches = ("leader", "neighbor") if args.approach == "both" else (args.approach,)
    t0 = time.perf_counter()

    def show(r):
        print(f"  {r['approach']} {r['pattern']} TB{r['testbed']} {r['column']}: distance {r['distance']:.2f}, "
              f"time {r['time']:.1f}, satisfied {r['satisfied']} ({r['seconds']:.2f} s)", file=sys.stderr, flush=True)

    runs = rerun(approaches, patterns, TESTBEDS[: args.testbeds], progress=show)
    wall = time.perf_counter() - t0
    print()
    print(markdown_ours(runs))
    for col in COLUMN_NAMES[:-1]:
        exc = our_exceptions(runs, col)
        formed = [e for e in exc if e["A_satisfied"] and e["F_satisfied"]]
        print(f"Our cells with {col} >= F: {len(exc)} of {2 * sum(r['column'] == col for r in runs)} "
              f"({len(formed)} of them with both runs formed)")
    ex = our_exceptions(runs)
    print(f"Our cells with A >= F (default A-team, prose IDs, {len(ex)} of {2 * sum(r['column'] == 'A' for r in runs)}):")
    for e in ex:
        print(f"- {e['approach']} {e['measure']}: {e['pattern']}, testbed-{e['testbed']}: A {e['A']:.2f} "
              f"(formed {e['A_satisfied']}) vs F {e['F']:.2f} (formed {e['F_satisfied']})")
    print(f"\n{len(runs)} runs in {wall:.1f} s wall ({sum(r['seconds'] for r in runs):.1f} s in runs)")
    if args.json:
        from swarmproof.models.fileio import atomic_write_text, dumps_json

        atomic_write_text(args.json, dumps_json({"paper": PAPER, "paper_exceptions": paper_exceptions(),
                                                 "runs": runs, "our_exceptions": our_exceptions(runs),
                                                 "wall_seconds": wall}))
    if args.plot_dir:
        import os

        for app in approaches:
            print("wrote", plot_approach(runs, app, os.path.join(args.plot_dir, f"leechong-tables-{app}.png")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
