"""Pictures of Lee & Chong's patterns (003 Table 1 with Alg. 2, and Alg. 3) at n = 12.

Usage (from the repository root)::

    MPLBACKEND=Agg .venv/bin/python benchmarks/leechong/leechong_patterns.py [--n 12] [--out docs/leechong-patterns.png]

Draws every bundled ``lines`` pattern of :data:`swarmproof.models.line_patterns.PATTERN_NAMES`
with its default parameters, d_u = 1 and u_l = 0, in the common frame (u to the right,
v up: 003 Sec. 2.1), each robot labelled with its ID, the leader (ID 0) a red star; for
the k-polygons also the regular polygon of the fixed-centre reading (grey, dashed) and for
the fan-shape the leader's own position (u_l, 0) (red ring), which Table 1 does not give
it.  Nothing is random; the PNG carries no software/version metadata, so the same command
writes the same bytes.  Also prints the exact distinctness summary for n <= 64
(:func:`swarmproof.reference_impl.leechong.patterns_check.check_all`).
"""

from __future__ import annotations

import argparse
import io
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from swarmproof.reference_impl.leechong.patterns_check import check_all, summarize  # noqa: E402
from swarmproof.models.fileio import atomic_write_bytes  # noqa: E402
from swarmproof.models.line_patterns import PATTERN_NAMES, pattern_info, target_points  # noqa: E402


def draw(n: int = 12) -> bytes:
    """The figure as PNG bytes."""
    cols = 6
    rows = math.ceil(len(PATTERN_NAMES) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols, 3.1 * rows))
    for ax, name in zip(axes.flat, PATTERN_NAMES):
        info = pattern_info(name)
        pts = target_points(name, n, 1.0)
        if info["family"] == "polygon":
            ref = target_points(name, 4 * info["k"], 1.0 * n / (4 * info["k"]), center="fixed")
            ax.plot(list(ref[::2, 0]) + list(ref[-1::-2, 0]) + [ref[0, 0]],
                    list(ref[::2, 1]) + list(ref[-1::-2, 1]) + [ref[0, 1]], ls="--", lw=0.7, color="0.6")
        if name == "fan-shape":
            ax.plot([0.0], [0.0], "o", mfc="none", mec="red", ms=11)
        ax.scatter(pts[1:, 0], pts[1:, 1], s=28, color="tab:blue", zorder=3)
        ax.scatter(pts[:1, 0], pts[:1, 1], s=110, marker="*", color="red", zorder=4)
        for i, (u, v) in enumerate(pts):
            ax.annotate(str(i), (u, v), textcoords="offset points", xytext=(4, 3), fontsize=7)
        ax.set_title(f"{name} ({info['type']}-line" + (f", k={info['k']}" if info["k"] else "") + ")", fontsize=9)
        ax.set_aspect("equal", adjustable="datalim")
        ax.margins(0.18)
        ax.tick_params(labelsize=6)
        ax.axhline(0, lw=0.4, color="0.8", zorder=0)
        ax.set_xlabel("u", fontsize=7, labelpad=1)
    for ax in list(axes.flat)[len(PATTERN_NAMES):]:
        ax.axis("off")
    fig.suptitle(f"003 Lee & Chong patterns, n = {n}, d_u = 1, u_l = 0 (red star: the leader, ID 0; "
                 "even IDs v > 0)", fontsize=11)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80, metadata={"Software": None})
    plt.close(fig)
    return buf.getvalue()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=12)
    ap.add_argument("--out", default="docs/leechong-patterns.png")
    ap.add_argument("--max-n", type=int, default=64)
    args = ap.parse_args(argv)
    atomic_write_bytes(args.out, draw(args.n))
    print(f"wrote {args.out}")
    for s in summarize(check_all(args.max_n)):
        print(f"{s['pattern']:>15}: held for n = 2..{args.max_n} except violated {s['violated']}, "
              f"undefined {s['undefined']}, undecided {s['inconclusive']}; notes at n = {s['noted']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
