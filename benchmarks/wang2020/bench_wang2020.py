"""Wang & Rubenstein 2020 (004) benchmarks: speed, memory, and the experiments of Sec. V-A (Figs. 9-12).

Usage (from the repository root)::

    .venv/bin/python benchmarks/wang2020/bench_wang2020.py perf                       # 1,024 robots N -> U; a 529 trial
    .venv/bin/python benchmarks/wang2020/bench_wang2020.py fig10 --sizes 16,64,144 --trials 3 --plot docs/wang2020-fig10.png
    .venv/bin/python benchmarks/wang2020/bench_wang2020.py fig9 --plot docs/wang2020-fig9.png
    .venv/bin/python benchmarks/wang2020/bench_wang2020.py fig11 --robots 100 --shapes 3 --runs 2 --plot docs/wang2020-fig11.png
    .venv/bin/python benchmarks/wang2020/bench_wang2020.py fig12 --robots 100 --shapes 6 --plot docs/wang2020-fig12.png

Every run is seeded (the same command prints the same experiment numbers; timings vary).  The
experiments use ``experiment_params`` (dt = 0.1 s, f_comm = 10 Hz, Delta t = 0.2 s; Sec. V-A's
r, R, v and Sec. V-B3's l) and the centralized method [12] of
``swarmproof.reference_impl.wang2020.experiments.centralized_schedule`` (one grid edge per step,
l / v = 4 s).  ``--json FILE`` writes the numbers; ``--plot FILE`` a PNG.  docs/wang2020.md and
docs/performance.md hold the results.
"""

from __future__ import annotations

import argparse
import datetime
import json
import platform
import resource
import statistics
import sys
import time

import numpy as np

from swarmproof.models.shapes import random_shape, shape_for
from swarmproof.reference_impl.wang2020.experiments import (EDGE_S, GRID_LENGTH, centralized_schedule,
                                                            experiment_params, fig10_instance, fig10_task,
                                                            random_assignment_cells, start_cells, wang_trial)

L = GRID_LENGTH  # grid length l (004 Sec. V-B3); EDGE_S = l / v, one centralized step


def _peak_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _machine() -> str:
    return f"{platform.machine()} {platform.system()}, Python {platform.python_version()}, numpy {np.__version__}"


def _fig9_starts(n: int, seed: int, arena: int):
    goals = shape_for("letter-n", n)
    rng = np.random.default_rng(seed)
    return goals, start_cells(goals.cells, n, rng, arena=arena)


def fig9_run(n: int = 1024, seed: int = 0, arena: int = 48, max_steps: int | None = None) -> dict:
    """004 Fig. 9: n agents form "N", then "U" once they detect N complete (Sec. III-B)."""
    N, starts = _fig9_starts(n, seed, arena)
    U = shape_for("letter-u", n)
    snap = {}

    class Snap:
        name = "snap"

        def start(self, ids):
            pass

        def observe(self, t, poses, states, present):
            # the first step in which some agent detected "N" complete (Sec. III-B) and switched
            if "N" not in snap and len(states) and max(states.values_of("completed")) >= 1:
                snap["N"] = (t, np.array(poses[:, :2]))

        def result(self):
            return None

    from swarmproof.models.trace import InitialConfiguration
    from swarmproof.reference_impl.wang2020.algorithm import Wang2020, goal_cells
    from swarmproof.reference_impl.wang2020.experiments import ProgressObserver
    from swarmproof.reference_impl.wang2020.fast import simulate_fast as simulate

    p = experiment_params(n)
    alg = Wang2020(then=U)
    init = InitialConfiguration(list(range(n)), [[L * x, L * y, 0.0] for x, y in starts])
    obN = ProgressObserver(goal_cells(N, L), L, every=1000)
    obU = ProgressObserver(goal_cells(U, L), L, every=1000)
    obU.name = "u_progress"
    t0 = time.perf_counter()
    c0 = time.process_time()
    def progress(t, cap):
        if t % 1000 == 0:
            print(f"  step {t} ({t * p.dt:.0f} s): N goals occupied {obN.last and obN.last[1]}, "
                  f"N formed at {obN.formed_step}, switched at {snap.get('N', (None,))[0]}, U formed at "
                  f"{obU.formed_step}; {time.perf_counter() - t0:.0f} s wall, {time.process_time() - c0:.0f} s CPU, "
                  f"peak RSS {_peak_mib():.0f} MiB", flush=True)

    r = simulate(alg, N, init, p, seed=seed, record_every=2000, observers=[obN, obU, Snap()],
                 max_steps=max_steps, progress=progress)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    rn, ru = obN.result(), obU.result()
    return {"n": n, "seed": seed, "arena": arena, "status": r.status, "steps": r.steps, "dt": p.dt,
            "N_formed_s": None if rn["formed_step"] is None else rn["formed_step"] * p.dt,
            "N_detected_s": None if "N" not in snap else snap["N"][0] * p.dt,
            "U_formed_s": None if ru["formed_step"] is None else ru["formed_step"] * p.dt,
            "end_s": r.steps * p.dt, "distance_m": rn["distance"], "wall_s": wall, "cpu_s": cpu,
            "peak_rss_mib": _peak_mib(), "trace_frames": len(r.trace.poses),
            "_final": np.array(r.final_poses[:, :2]), "_N": snap.get("N", (None, None))[1],
            "_goals": (sorted(N.cells), sorted(U.cells))}


def _random_baseline(n: int, seed: int, arena: int, optimum_m: float) -> dict:
    """The arena's random-assignment baseline of trial ``(n, seed)`` (as ``fig10_task`` gives it),
    for trials recorded before the columns existed."""
    goals, starts = fig10_instance(n, seed, arena)
    rand = random_assignment_cells(starts, sorted(goals.cells)) * L
    return {"random_assignment_m": rand, "random_ratio": rand / optimum_m if optimum_m else None}


def fig10_trial(n: int, seed: int, arena: int = 32) -> dict:
    """One Fig. 10 trial (``fig10_task``: a random connected shape of n cells, n random starts in
    the arena; the decentralized run to formation and the centralized schedule from the same
    starts), with the machine's wall and CPU time for it."""
    t0, c0 = time.perf_counter(), time.process_time()
    out = fig10_task(n, seed, arena)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return {"n": n, "seed": seed, "arena": arena, **out, "wall_s": wall, "cpu_s": cpu,
            "load_avg": list(__import__("os").getloadavg())}


def perf(n_big: int = 1024, n_trial: int = 529) -> dict:
    out = {"machine": _machine(), "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="minutes")}
    t0 = time.perf_counter()
    tr = fig10_trial(n_trial, 0)
    out["trial"] = {**tr, "wall_total_s": time.perf_counter() - t0}
    print(f"fig10 trial n={n_trial}: {tr['wall_s']:.1f} s wall, {tr['cpu_s']:.1f} s CPU for the run ({tr['status']}, {tr['steps']} steps, "
          f"formed at {tr['formed_s']} s simulated), peak RSS {_peak_mib():.0f} MiB", flush=True)
    big = fig9_run(n_big)
    out["big"] = {k: v for k, v in big.items() if not k.startswith("_")}
    print(f"fig9 n={n_big} N -> U: {big['wall_s']:.1f} s wall ({big['cpu_s']:.1f} s CPU), {big['status']}, "
          f"{big['steps']} steps; N formed {big['N_formed_s']} s, detected {big['N_detected_s']} s, U formed "
          f"{big['U_formed_s']} s simulated; peak RSS {big['peak_rss_mib']:.0f} MiB", flush=True)
    return out


def _box(ax, data, pos, color):
    b = ax.boxplot(data, positions=pos, widths=0.35, patch_artist=True, manage_ticks=False)
    for patch in b["boxes"]:
        patch.set_facecolor(color)
        patch.set_alpha(0.5)


def fig10(sizes, trials: int, plot: str | None, trials_large: int | None = None, jsonl: str | None = None,
          run: bool = True, arena: int = 32, large_from: int = 200) -> dict:
    done = {}
    if jsonl:
        try:
            with open(jsonl) as f:
                for line in f:
                    if line.strip():
                        tr = json.loads(line)
                        if tr.get("arena", 32) != arena:
                            raise SystemExit(f"{jsonl}: holds a trial of arena {tr.get('arena', 32)}, not {arena}: "
                                             "use one file per arena")
                        if "random_ratio" not in tr:   # trials written before the column: the same instance's
                            tr.update(_random_baseline(tr["n"], tr["seed"], arena, tr["central_distance_m"]))
                        done[(tr["n"], tr["seed"])] = tr
        except FileNotFoundError:
            pass
    rows = []
    for n in sizes:
        for s in range(trials if trials_large is None or n < large_from else trials_large):
            if (n, s) in done:
                rows.append(done[(n, s)])
                continue
            if not run:
                continue
            tr = fig10_trial(n, s, arena)
            rows.append(tr)
            if jsonl:
                with open(jsonl, "a") as f:
                    f.write(json.dumps(tr) + "\n")
            print(f"n={n} seed={s}: {tr['status']} formed {tr['formed_s']} s (centralized {tr['central_s']:.0f} s, "
                  f"bound {tr['central_bound_s']:.0f} s), distance {tr['distance_m']:.1f} m vs {tr['central_distance_m']:.1f} m "
                  f"(ratio {tr['ratio']:.3f}); {tr['wall_s']:.1f} s wall, {tr['cpu_s']:.1f} s CPU", flush=True)
    sizes = [n for n in sizes if any(r["n"] == n for r in rows)]
    print(f"\n{arena} x {arena} arena\n")
    print("| n | trials | formed | time, ours (s) | time, centralized (s) | [12] bound (s) | distance per robot, ours (m) | "
          "centralized (m) | ratio | random assignment / optimum | CPU a trial (s, mean) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    summary = []
    for n in sizes:
        rs = [r for r in rows if r["n"] == n]
        ok = [r for r in rs if r["formed_s"] is not None]

        def med(key, rr=ok):
            xs = [r[key] for r in rr if r[key] is not None]
            return statistics.median(xs) if xs else float("nan")

        row = {"n": n, "trials": len(rs), "formed": len(ok), "time": med("formed_s"), "central": med("central_s", rs),
               "bound": med("central_bound_s", rs), "dist": med("distance_m") / n,
               "cdist": med("central_distance_m", rs) / n, "ratio": med("ratio"),
               "ratio_min": min((r["ratio"] for r in ok), default=float("nan")),
               "ratio_max": max((r["ratio"] for r in ok), default=float("nan")),
               "random": med("random_ratio", rs),
               "random_min": min(r["random_ratio"] for r in rs), "random_max": max(r["random_ratio"] for r in rs),
               "cpu": statistics.mean(r["cpu_s"] for r in rs)}
        summary.append(row)
        print(f"| {n} | {row['trials']} | {row['formed']} | {row['time']:.0f} | {row['central']:.0f} | {row['bound']:.0f} | "
              f"{row['dist']:.2f} | {row['cdist']:.2f} | {row['ratio']:.2f} ({row['ratio_min']:.2f}-{row['ratio_max']:.2f}) | "
              f"{row['random']:.2f} ({row['random_min']:.2f}-{row['random_max']:.2f}) | {row['cpu']:.1f} |")
    if plot:
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
        x = np.arange(len(sizes))
        by = {n: [r for r in rows if r["n"] == n] for n in sizes}
        _box(axes[0], [[r["formed_s"] for r in by[n] if r["formed_s"] is not None] or [np.nan] for n in sizes], x - 0.2, "red")
        _box(axes[0], [[r["central_s"] for r in by[n]] for n in sizes], x + 0.2, "blue")
        axes[0].set_ylabel("convergence time (s)")
        _box(axes[1], [[r["distance_m"] / n for r in by[n]] for n in sizes], x - 0.2, "red")
        _box(axes[1], [[r["central_distance_m"] / n for r in by[n]] for n in sizes], x + 0.2, "blue")
        axes[1].set_ylabel("distance travelled per robot (m)")
        _box(axes[2], [[r["ratio"] for r in by[n] if r["ratio"] is not None] for n in sizes], x - 0.2, "red")
        _box(axes[2], [[r["random_ratio"] for r in by[n]] for n in sizes], x + 0.2, "0.6")
        axes[2].plot([], [], color="red", lw=6, alpha=0.5, label="ours / optimum")
        axes[2].plot([], [], color="0.6", lw=6, alpha=0.5, label="random assignment / optimum")
        axes[2].axhline(1.2, color="gray", ls="--", lw=1, label="paper: about 1.2")
        axes[2].set_ylabel("distance ratio, ours / centralized")
        axes[2].legend()
        for ax in axes:
            ax.set_xticks(x)
            ax.set_xticklabels([str(n) for n in sizes])
            ax.set_xlabel("number of agents")
        fig.suptitle(f"004 Fig. 10 reproduced: wang2020 (red) vs centralized [12] (blue), "
                     f"{'/'.join(str(len(by[n])) for n in sizes)} trials, {arena} x {arena} arena")
        fig.tight_layout()
        fig.savefig(plot, dpi=90)
        print(f"wrote {plot}")
    return {"rows": rows, "summary": summary}


def _draw(ax, cells_xy, goals, title):
    g = np.array(goals, dtype=float) * L
    ax.scatter(g[:, 0], g[:, 1], s=14, marker="s", color="0.85")
    ax.scatter(cells_xy[:, 0], cells_xy[:, 1], s=5, color="red")
    ax.set_aspect("equal")
    ax.set_title(title)
    ax.set_xticks([])
    ax.set_yticks([])


def _goals_held(xy, goals) -> int:
    """Goal cells with an agent resting on them (positions in metres): the progress observer's count."""
    from swarmproof.reference_impl.wang2020.experiments import ProgressObserver

    return ProgressObserver(goals, L).occupied(np.asarray(xy, dtype=float))


def fig9(n: int, seed: int, plot: str | None, max_steps: int | None, arena: int = 48) -> dict:
    r = fig9_run(n, seed, arena=arena, max_steps=max_steps)
    print({k: v for k, v in r.items() if not k.startswith("_")})
    if plot:
        import matplotlib.pyplot as plt

        gN, gU = r["_goals"]
        if r["_N"] is not None:
            fig, axes = plt.subplots(1, 2, figsize=(10, 5))
            _draw(axes[0], r["_N"], gN, f"N detected complete, T = {r['N_detected_s']:.0f} s")
            _draw(axes[1], r["_final"], gU, f"end ({r['status']}), T = {r['end_s']:.0f} s")
        else:
            # "N" never detected complete: the agents never left it, so draw them on N's goals
            fig, ax = plt.subplots(1, 1, figsize=(7, 6.5))
            held = _goals_held(r["_final"], gN)
            _draw(ax, r["_final"], gN, f"N not formed: {held} of {len(gN)} goals held\n"
                                       f"at T = {r['end_s']:.0f} s ({r['status']})")
        fig.suptitle(f"004 Fig. 9 reproduced: {n} agents form N, then U\n(seed {seed}, {r['arena']} x {r['arena']} start arena)",
                     fontsize=11)
        fig.tight_layout()
        fig.savefig(plot, dpi=90)
        print(f"wrote {plot}")
    return {k: v for k, v in r.items() if not k.startswith("_")}


def _mean_band(series_list, horizon, every, key):
    t = np.arange(0, horizon + 1, every)
    rows = []
    for s in series_list:
        steps = np.array([x[0] for x in s])
        vals = np.array([x[key] for x in s], dtype=float)
        idx = np.clip(np.searchsorted(steps, t, side="right") - 1, 0, len(steps) - 1)
        rows.append(vals[idx])
    a = np.array(rows)
    return t, a.mean(axis=0), a.std(axis=0)


def _bands(ax_pair, runs, n, dt, color, label):
    horizon = max(s[-1][0] for s in runs)
    for ax, key, scale in ((ax_pair[0], 1, 100.0 / n), (ax_pair[1], 2, 1.0)):
        t, m, sd = _mean_band(runs, horizon, 10, key)
        ax.plot(t * dt, m * scale, color=color, label=label)
        ax.fill_between(t * dt, (m - 2 * sd) * scale, (m + 2 * sd) * scale, color=color, alpha=0.2)


def fig11(n: int, shapes: int, runs: int, plot: str | None, max_steps: int | None = 6000) -> dict:
    """004 Fig. 11 at reduced scale: gradient-based (p_random = 0.1, Alg. 4) vs random selector
    (p_random = 1)."""
    out = {"gradient": [], "random": []}
    for k in range(shapes):
        rng = np.random.default_rng([11, n, k])
        goals = random_shape(n, rng)
        for run in range(runs):
            starts = start_cells(goals.cells, n, rng)
            for name, pr in (("gradient", 0.1), ("random", 1.0)):
                w = wang_trial(goals, starts, 1000 * k + run, params=experiment_params(n, p_random=pr),
                               max_steps=max_steps)
                out[name].append(w["series"])
                print(f"shape {k} run {run} {name}: formed {w['formed_s']} s, {w['distance_m']:.1f} m", flush=True)
    summary = {name: {"end_s": [s[-1][0] * 0.1 for s in out[name]],
                      "formed": [s[-1][1] == n for s in out[name]],
                      "distance_m": [s[-1][2] for s in out[name]]} for name in out}
    for name in out:
        xs = summary[name]["end_s"]
        print(f"{name}: {sum(summary[name]['formed'])} of {len(xs)} formed within {max_steps} ticks; end at "
              f"{statistics.mean(xs):.0f} s mean (min {min(xs):.0f}, max {max(xs):.0f}); distance "
              f"{statistics.mean(summary[name]['distance_m']):.0f} m mean")
    if plot:
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2, figsize=(11, 4))
        _bands(axes, out["gradient"], n, 0.1, "red", "gradient-based selector")
        _bands(axes, out["random"], n, 0.1, "blue", "random selector")
        axes[0].set_ylabel("goals occupied (%)")
        axes[1].set_ylabel("distance travelled, all agents (m)")
        for ax in axes:
            ax.set_xlabel("time (s)")
            ax.legend()
        fig.suptitle(f"004 Fig. 11 at reduced scale: {n} agents, {shapes} shapes x {runs} runs (mean, 2 sigma; "
                     f"cap {max_steps} ticks)")
        fig.tight_layout()
        fig.savefig(plot, dpi=90)
        print(f"wrote {plot}")
    return summary


def _largest_drop(runs, n) -> dict:
    """How far the mean "goals occupied" curve of ``runs`` falls below its running maximum (% of n),
    the time of its lowest point and its value there, and how far it falls after that point (Sec.
    V-B4: in the paper's simulations the curve "monotonically increase[s] over time")."""
    horizon = max(s[-1][0] for s in runs)
    t, m, _ = _mean_band(runs, horizon, 10, 1)
    pct = m * 100.0 / n
    drop = np.maximum.accumulate(pct) - pct
    low = int(np.argmin(pct))
    after = pct[low:]
    return {"start_pct": float(pct[0]), "largest_drop_pct": float(drop.max()), "lowest_pct": float(pct[low]),
            "lowest_at_s": float(t[low] * 0.1), "monotone": bool(drop.max() == 0.0),
            # from its lowest point on: how far it still falls (0: monotone after the first dip)
            "drop_after_lowest_pct": float((np.maximum.accumulate(after) - after).max())}


def fig12(n: int, shapes: int, plot: str | None, arena: int = 32) -> dict:
    """004 Fig. 12 at reduced scale: ours vs centralized over time (starts in an ``arena`` square)."""
    ours, cent = [], []
    for k in range(shapes):
        rng = np.random.default_rng([12, n, k])
        goals = random_shape(n, rng)
        starts = start_cells(goals.cells, n, rng, arena=arena)
        w = wang_trial(goals, starts, k)
        c = centralized_schedule(starts, sorted(goals.cells))
        ours.append(w["series"])
        # the centralized series on the same clock: a step every l / v = 40 ticks of 0.1 s
        ticks = int(round(EDGE_S / 0.1))
        cent.append([(i * ticks, c.reached[i], c.travelled[i] * L) for i in range(len(c.reached))])
        print(f"shape {k}: ours formed {w['formed_s']} s, {w['distance_m']:.1f} m; centralized "
              f"{c.steps * EDGE_S:.0f} s, {c.total_cells * L:.1f} m", flush=True)
    if plot:
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2, figsize=(11, 4))
        _bands(axes, ours, n, 0.1, "red", "ours (wang2020)")
        _bands(axes, cent, n, 0.1, "blue", "centralized [12]")
        axes[0].set_ylabel("goals occupied (%)")
        axes[1].set_ylabel("distance travelled, all agents (m)")
        for ax in axes:
            ax.set_xlabel("time (s)")
            ax.legend()
        fig.suptitle(f"004 Fig. 12 at reduced scale: {n} agents, {shapes} random shapes, {arena} x {arena} arena "
                     f"(mean, 2 sigma)")
        fig.tight_layout()
        fig.savefig(plot, dpi=90)
        print(f"wrote {plot}")
    out = {"arena": arena, "ours_formed_s": [s[-1][0] * 0.1 for s in ours], "central_s": [s[-1][0] * 0.1 for s in cent],
           "ours_distance_m": [s[-1][2] for s in ours], "central_distance_m": [s[-1][2] for s in cent],
           "ours_curve": _largest_drop(ours, n), "central_curve": _largest_drop(cent, n)}
    print(out)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("perf")
    p.add_argument("--robots", type=int, default=1024)
    p.add_argument("--trial-robots", type=int, default=529)
    p = sub.add_parser("fig10")
    p.add_argument("--sizes", default="16,64,144,256,400,529")
    p.add_argument("--trials", type=int, default=3)
    p.add_argument("--trials-large", type=int, default=None, help="trials for n >= 200 (default: --trials)")
    p.add_argument("--jsonl", default=None, help="append each trial here; trials already there are not re-run")
    p.add_argument("--no-run", action="store_true", help="only table and plot the trials in --jsonl")
    p.add_argument("--arena", type=int, default=32, help="side of the start arena (one --jsonl file per arena)")
    p.add_argument("--large-from", type=int, default=200, help="sizes from this on run --trials-large trials")
    p = sub.add_parser("fig9")
    p.add_argument("--robots", type=int, default=1024)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--max-steps", type=int, default=None)
    p.add_argument("--arena", type=int, default=48, help="side of the start arena, centred on the N")
    p = sub.add_parser("fig11")
    p.add_argument("--robots", type=int, default=100)
    p.add_argument("--shapes", type=int, default=3)
    p.add_argument("--runs", type=int, default=2)
    p.add_argument("--max-steps", type=int, default=6000, help="cap per run (ticks of 0.1 s)")
    p = sub.add_parser("fig12")
    p.add_argument("--robots", type=int, default=100)
    p.add_argument("--shapes", type=int, default=6)
    p.add_argument("--arena", type=int, default=32, help="side of the start arena, centred on the shape")
    for q in sub.choices.values():
        q.add_argument("--json", default=None)
        q.add_argument("--plot", default=None)
    a = ap.parse_args(argv)
    if a.cmd == "perf":
        out = perf(a.robots, a.trial_robots)
    elif a.cmd == "fig10":
        out = fig10([int(x) for x in a.sizes.split(",")], a.trials, a.plot, a.trials_large, a.jsonl, not a.no_run, a.arena,
                    a.large_from)
    elif a.cmd == "fig9":
        out = fig9(a.robots, a.seed, a.plot, a.max_steps, a.arena)
    elif a.cmd == "fig11":
        out = fig11(a.robots, a.shapes, a.runs, a.plot, a.max_steps)
    else:
        out = fig12(a.robots, a.shapes, a.plot, a.arena)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1, default=lambda o: None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
