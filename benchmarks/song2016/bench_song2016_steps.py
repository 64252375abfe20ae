"""song2016: where a run's steps go, term by term as Theorem 13 accounts for them (issue 31).

Usage (from the repository root)::

    MPLBACKEND=Agg .venv/bin/python benchmarks/song2016/bench_song2016_steps.py \\
        --sizes 10,20,30,40 --trials 10 --speeds 0.6,0.2,0.05 \\
        --table /tmp/song2016-steps.md --plot docs/song2016-steps.png
    .venv/bin/python benchmarks/song2016/bench_song2016_steps.py --sizes 10,20,30,40 --trials 10 \\
        --speeds 0.6,0.2 --reading subtree-clock

Song & O'Kane 2016, Thm. 13 (proof): ``T = sum_{i=1}^{n-1} T_i + O(n)`` with ``T_i = T_timeout +
T_wait + T_drive``, "the trailing O(n)" being "the communication timeout needed for the highest ID
robot to become stable"; Sec. VI: "we set both of the communication timeout and the movement
timeout as the same as the number of robots" and "every robot needs a communication timeout to
confirm the change of its states, and an movement timeout if it is supposed to move".  So the
paper's own accounting of a run is ``n + (n-1)(2n) + (wait + drive)``, and Table III minus
``2n^2 - n`` is what it leaves for waiting and driving.

This script runs the registered ``song2016`` unchanged (``Song2016(n_robots=n)``, timeouts = n;
with ``--reading subtree-clock`` the registered variant ``song2016-subtree-clock``), square lattice, range 1.2, omega = pi/4, dt = 1, ``random_connected`` starts with
min_separation 0.3, seeds 0..trials-1, as benchmarks/song2016/bench_song2016.py) and watches it
from outside with an engine observer (``simulate(observers=...)``): after every step t it reads
the controller states and poses.  Step t (1..T) is attributed to exactly one term, by the state
at the start of the step (which robots are stable) and the decision the step recorded:

* ``first``: no robot is stable yet -- the highest-ID robot's communication timeout (Thm. 13's
  trailing O(n));
* otherwise the relocation in progress is that of ``r``, the highest-ID unstable robot (the
  proof: "sequentially drive the robots, in decreasing order of their IDs"), and the step is

  - ``reform``: r's ``relocateID`` is not r yet -- the previous relocate robot's claim is still
    circulating (it turned stable; its stale relocateID dies out along the path lists,
    Algorithm 1 lines 12, 18) and the tree re-forms; not a term of Thm. 13;
  - ``t_comm``: r knows it is the highest unstable robot but its communication timeout (Def. 10)
    has not passed;
  - ``t_move``: r is the relocate robot but its movement timeout (Sec. VI) has not passed;
  - ``wait``: r may move and its pose does not change (it waits for a child farther than d_s,
    Fig. 11, or its safe region is empty: Thm. 13's T_wait);
  - ``turn``: r turns in place (heading changes, position does not: the 2 pi/omega of T_drive);
  - ``drive``: r's position changes (the phi/v of T_drive); the step in which r arrives and turns
    stable is counted here too;
* ``end``: every robot is stable at the start of the step (the run's own end, "upon discovering
  that no unstable robots remain").

The terms sum to the run's step count (tested: tests/benchmarks/test_bench_song2016_steps.py).
Output: a markdown table (mean per cell over the finished trials, with the paper's accounting
beside it; docs/song2016.md holds the one of the first command) and a PNG of the stacked terms
per relocation.  docs/song2016.md, "Where Table III's
steps go".
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np

from swarmproof.models.fileio import atomic_write_text
from swarmproof.models.library import load
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Params
from swarmproof.reference_impl.song2016.algorithm import Song2016, Song2016SubtreeClock

#: The terms, in the order of a relocation (Thm. 13 plus the rows it does not name).
TERMS = ("first", "reform", "t_comm", "t_move", "wait", "turn", "drive", "end")

#: What each term is, for the table.
LABELS = {
    "first": "highest-ID robot's timeout (Thm. 13 trailing O(n))",
    "reform": "tree re-forming: stale relocateID (not in Thm. 13)",
    "t_comm": "communication timeout, Def. 10 (T_timeout)",
    "t_move": "movement timeout, Sec. VI (T_timeout)",
    "wait": "T_wait: relocate robot may move, stands",
    "turn": "T_drive: turning in place (2 pi / omega)",
    "drive": "T_drive: translating (phi / v)",
    "end": "after the last relocation",
}

#: Song & O'Kane 2016, Table III, square lattice, new algorithm: steps for n = 10, 20, 30, 40
#: (as quoted in issue 31; the tables are withheld from the stored copy of the paper).
TABLE_III_SQUARE = {10: 236, 20: 841, 30: 1841, 40: 3497}


class StepBreakdown:
    """Engine observer: attributes every step of a song2016 run to one of :data:`TERMS`.

    Reads only what the engine hands every observer (``observe(t, poses, states, present)``):
    the controllers' state tuples (docs/song2016.md "State") and the poses.  It changes nothing.
    """

    name = "song2016-step-breakdown"

    def __init__(self, movement_timeout: int) -> None:
        self.t_m = int(movement_timeout)
        self.counts = dict.fromkeys(TERMS, 0)
        self.relocations = 0
        self._prev = None      # (stable flags, poses) after the previous step
        self._key = None

    def start(self, ids) -> None:
        self.ids = [int(i) for i in ids]
        self._order = sorted(range(len(self.ids)), key=lambda k: -self.ids[k])

    def _get(self, state, key):
        if self._key is None:
            self._key = {k: j for j, (k, _) in enumerate(state)}
        return state[self._key[key]][1]

    def observe(self, t, poses, states, present) -> None:
        poses = np.array(poses, copy=True)
        stable = [s is not None and bool(self._get(s, "stable")) for s in states]
        if t > 0:
            self.counts[self._term(t, poses, states)] += 1
        if self._prev is not None:
            self.relocations += sum(1 for a, b in zip(self._prev[0], stable) if b and not a)
        self._prev = (stable, poses)

    def _term(self, t, poses, states) -> str:
        was_stable, old = self._prev
        if not any(was_stable):
            return "first"
        k = next((k for k in self._order if not was_stable[k]), None)
        if k is None:
            return "end"
        s = states[k]
        if self._get(s, "stable"):
            return "drive"                       # the arrival step
        if self._get(s, "relocate_id") != self.ids[k]:
            return "reform"
        if not self._get(s, "relocate"):
            return "t_comm"
        # the decision of observer step t is made in controller step t - 1 (its clocks)
        if (t - 1) - self._get(s, "mover_since") < self.t_m:
            return "t_move"
        if not np.allclose(poses[k, :2], old[k, :2], rtol=0.0, atol=0.0):
            return "drive"
        if poses[k, 2] != old[k, 2]:
            return "turn"
        return "wait"

    def result(self):
        return dict(self.counts)


#: The readings this script can run, by ``--reading``: the default and the registered variant
#: ``song2016-subtree-clock`` (docs/song2016.md, "Where Table III's steps go").
READINGS = {"song2016": Song2016, "subtree-clock": Song2016SubtreeClock}


def run(n: int, seed: int, v: float, lattice_name: str = "square", reading: str = "song2016") -> dict:
    """One run of the registered song2016 (or of ``song2016-subtree-clock``: ``reading="subtree-clock"``);
    its status, steps and breakdown."""
    lattice = load(lattice_name)
    init = random_connected(n, seed, range=lattice.range, min_separation=0.3)
    p = Params(range=lattice.range, v=v, omega=math.pi / 4, dt=1.0)
    alg = READINGS[reading](n_robots=n)
    ob = StepBreakdown(alg.config(p, 1.0, n).movement_timeout)
    r = simulate(alg, lattice, init, p, seed=seed, observers=[ob], record_every=10 ** 9)
    return {"n": n, "seed": seed, "v": v, "status": r.status, "steps": int(r.steps),
            "relocations": ob.relocations - 1 if ob.relocations else 0, **ob.result()}


def paper_accounting(n: int) -> dict:
    """Table III (square) split as Thm. 13 + Sec. VI count it: n, (n-1) n twice, the rest."""
    total = TABLE_III_SQUARE.get(n)
    out = {"first": n, "reform": 0, "t_comm": (n - 1) * n, "t_move": (n - 1) * n, "end": 0}
    out["wait+drive"] = None if total is None else total - (2 * n * n - n)
    out["total"] = total
    return out


def cell_means(rows: list[dict]) -> dict:
    ok = [r for r in rows if r["status"] == "finished"]
    m = {t: float(np.mean([r[t] for r in ok])) for t in TERMS} if ok else {}
    if ok:
        m["steps"] = float(np.mean([r["steps"] for r in ok]))
        m["relocations"] = float(np.mean([r["relocations"] for r in ok]))
    m["finished"] = len(ok)
    m["trials"] = len(rows)
    return m


def markdown(cells: dict, sizes, speeds) -> str:
    """One table per n: the paper's accounting beside the measured mean of every speed."""
    out = []
    for n in sizes:
        pa = paper_accounting(n)
        head = "| term | paper (Table III, Thm. 13 + Sec. VI) | " + " | ".join(
            f"v = {v} (mean, per relocation)" for v in speeds) + " |"
        out += [f"**n = {n}** (square; finished/trials: " + ", ".join(
            f"v = {v}: {cells[(n, v)]['finished']}/{cells[(n, v)]['trials']}" for v in speeds) + ")", "",
            head, "|" + "---|" * (2 + len(speeds))]

        def fmt(v, term):
            c = cells[(n, v)]
            if not c.get("finished"):
                return "--"
            x = c[term] if term != "wait+drive" else c["wait"] + c["turn"] + c["drive"]
            per = x / c["relocations"] if term not in ("first", "end") and c["relocations"] else None
            return f"{x:,.1f}" + ("" if per is None else f" ({per:.1f})")

        for term in ("first", "reform", "t_comm", "t_move", "wait", "turn", "drive", "end"):
            p = pa.get(term)
            if term in ("wait", "turn", "drive"):
                p = "" if term != "wait" else "(T_wait + T_drive together below)"
            out.append(f"| {term}: {LABELS[term]} | {p} | " + " | ".join(fmt(v, term) for v in speeds) + " |")
        wd = pa["wait+drive"]
        wd_s = "--" if wd is None else f"{wd:,} ({wd / (n - 1):.1f})"
        out.append(f"| T_wait + T_drive | {wd_s} | " + " | ".join(fmt(v, "wait+drive") for v in speeds) + " |")
        tot = pa["total"]
        out.append(f"| **total steps** | {tot if tot is not None else '--'} | " + " | ".join(
            (f"{cells[(n, v)]['steps']:,.1f} ({cells[(n, v)]['steps'] / tot:.2f}x)" if tot and cells[(n, v)].get('finished')
             else f"{cells[(n, v)].get('steps', float('nan')):,.1f}") for v in speeds) + " |")
        out.append("")
    return "\n".join(out)


def plot(cells: dict, sizes, speeds, path: str) -> str:
    """Stacked bars: mean steps per relocation by term, per n and v, with the paper's bar."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from swarmproof.checkers.plotting import save_png

    colors = {"reform": "tab:red", "t_comm": "tab:blue", "t_move": "tab:cyan", "wait": "tab:orange",
              "turn": "tab:olive", "drive": "tab:green", "paper": "0.6"}
    fig, ax = plt.subplots(figsize=(10, 5), dpi=100)
    labels, x = [], 0
    seen = set()
    for n in sizes:
        pa = paper_accounting(n)
        bars = [("paper", None)] + [(f"v={v}", v) for v in speeds]
        for name, v in bars:
            bottom = 0.0
            if v is None:
                if pa["total"] is None:
                    continue
                per = {"t_comm": n, "t_move": n, "paper": pa["wait+drive"] / (n - 1)}
            else:
                c = cells[(n, v)]
                if not c.get("finished") or not c["relocations"]:
                    continue
                per = {t: c[t] / c["relocations"] for t in ("reform", "t_comm", "t_move", "wait", "turn", "drive")}
            for t, h in per.items():
                lab = {"paper": "paper: T_wait + T_drive left by Table III"}.get(t, LABELS.get(t, t))
                ax.bar(x, h, bottom=bottom, color=colors[t], label=None if t in seen else lab,
                       hatch="//" if v is None else None, edgecolor="k", linewidth=0.3)
                seen.add(t)
                bottom += h
            labels.append((x, f"n={n}\n{name}"))
            x += 1
        x += 0.6
    ax.set_xticks([p for p, _ in labels], [s for _, s in labels], fontsize=7)
    ax.set_ylabel("steps per relocation (mean over finished trials)")
    ax.set_title("song2016, square: a relocation's steps by term (Song & O'Kane 2016, Thm. 13; Sec. VI)")
    ax.legend(fontsize=7, loc="upper left")
    return save_png(fig, path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10,20,30,40", help="comma-separated n (Sec. VI: 10..40)")
    ap.add_argument("--trials", type=int, default=10, help="starts per cell, seeds 0.. (Sec. VI: 10)")
    ap.add_argument("--speeds", default="0.6,0.2,0.05", help="comma-separated v")
    ap.add_argument("--lattice", default="square")
    ap.add_argument("--reading", default="song2016", choices=sorted(READINGS),
                    help="song2016 (the default) or subtree-clock (the registered variant "
                         "song2016-subtree-clock)")
    ap.add_argument("--table", default=None, help="write the markdown table here")
    ap.add_argument("--plot", default=None, help="write the PNG here")
    args = ap.parse_args(argv)
    sizes = tuple(int(s) for s in args.sizes.split(","))
    speeds = tuple(float(s) for s in args.speeds.split(","))
    print(f"{args.reading} step breakdown on {args.lattice}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"load average {os.getloadavg()[0]:.1f}")
    print("n seed v status steps relocations " + " ".join(TERMS))
    cells = {}
    for n in sizes:
        for v in speeds:
            rows = []
            for seed in range(args.trials):
                r = run(n, seed, v, args.lattice, args.reading)
                assert sum(r[t] for t in TERMS) == r["steps"], r
                print(n, seed, v, r["status"], r["steps"], r["relocations"], *(r[t] for t in TERMS), flush=True)
                rows.append(r)
            cells[(n, v)] = cell_means(rows)
    table = markdown(cells, sizes, speeds)
    print(table)
    if args.table:
        print("wrote", atomic_write_text(args.table, table + "\n"))
    if args.plot:
        print("wrote", plot(cells, sizes, speeds, args.plot))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
