"""Draw 004's goal shapes at n robots and time the centralized optimum (Wang & Rubenstein 2020).

Usage (from the repository root)::

    .venv/bin/python benchmarks/wang2020/wang2020_shapes.py                      # docs/wang2020-shapes.png, n = 256
    .venv/bin/python benchmarks/wang2020/wang2020_shapes.py --robots 100 --plot out.png --seed 3

Draws every bundled shape (letter-n, letter-u of 004 Figs. 1 and 9; square-9,
letter-l) and one random connected shape (Figs. 10-12) scaled to ``--robots``
cells (models/shapes.py, :func:`scale_to`), and prints a Markdown table: the
scale factor, the resampling rule, the cells dropped to reach exactly n, and
the centralized distance-optimal total (004 Sec. V; scipy) from seeded random
starts in the default 32 x 32 arena, with its time.  Seeded: the same
command draws the same picture and prints the same numbers (timings vary).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from swarmproof.models.assignment import optimal_assignment
from swarmproof.models.shapes import (DEFAULT_ARENA, DEFAULT_SPACING, bundled_shape, centered_arena, random_shape,
                                      random_start_cells, scale_details)
from swarmproof.models.targets import target_names

SHAPES = ("letter-n", "letter-u", "square-9", "letter-l")


def shapes_at(n: int, seed: int) -> list:
    """``(name, GoalSet, factor, dropped, rule)`` for every bundled shape and one random shape."""
    out = []
    for name in SHAPES:
        cells, factor, dropped, rule = scale_details(bundled_shape(name).cells, n)
        out.append((name, bundled_shape(name).__class__(name, cells, DEFAULT_SPACING, (0.0, 0.0), 0.6),
                    factor, dropped, rule))
    g = random_shape(n, np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(4, 10))))
    out.append((f"random (seed {seed})", g, 1.0, 0, "grown"))
    return out


def table(n: int, seed: int, rows: list) -> str:
    optimal_assignment([(0, 0)], [(1, 0)])          # warm-up: scipy's import is not the solve time
    lines = [f"| shape (n = {n}) | scale | rule | dropped | optimal total (m) | per robot (m) | solve (ms) |",
             "|---|---|---|---|---|---|---|"]
    for k, (name, g, factor, dropped, rule) in enumerate(rows):
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(4, k)))
        arena = centered_arena(g.cells, *DEFAULT_ARENA)
        starts = random_start_cells(n, arena, rng)
        t0 = time.perf_counter()
        a = optimal_assignment(starts, sorted(g.cells), spacing=g.spacing)
        ms = 1000 * (time.perf_counter() - t0)
        lines.append(f"| {name} | {factor:.3f} | {rule} | {dropped} | {a.total:.1f} | {a.total / n:.3f} | {ms:.1f} |")
    return "\n".join(lines)


def plot(rows: list, path: str, n: int) -> str:
    from swarmproof.checkers.plotting import plt, save_png

    fig, axes = plt.subplots(1, len(rows), figsize=(3.2 * len(rows), 3.6), dpi=100)
    for ax, (name, g, factor, dropped, rule) in zip(axes, rows):
        xy = np.array(sorted(g.cells), dtype=float)
        ax.scatter(xy[:, 0], xy[:, 1], s=9, marker="s", color="#0072B2", linewidths=0)
        ax.set_aspect("equal")
        ax.set_title(f"{name}\n{len(g.cells)} cells" + (f", scale {factor:.2f}" if rule != "grown" else ""),
                     fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle(f"004 goal shapes scaled to n = {n} robots (grid length l = {DEFAULT_SPACING} m)", fontsize=10, y=1.06)
    return save_png(fig, path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, default=256)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--plot", default="docs/wang2020-shapes.png")
    args = ap.parse_args(argv)
    assert {n for k, n in target_names("shape")} >= set(SHAPES)
    rows = shapes_at(args.robots, args.seed)
    print(table(args.robots, args.seed, rows))
    if args.plot:
        print(f"wrote {plot(rows, args.plot, args.robots)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
