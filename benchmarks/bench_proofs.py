"""Timings of the z3 proof suite (issue 5: whole suite under 10 s, no lemma over 2 s).

Run: ``.venv/bin/python benchmarks/bench_proofs.py [--repeat N] [--trees N]``.
Prints per-lemma seconds (the best and worst of N runs), the suite total,
whether the targets are met, the direct tree confirmation (every tree shape
up to ``--trees`` robots) and the geometry-kernel oracle.  Figures go to
docs/performance.md ("Proof suite"), never into timed tests.
"""

from __future__ import annotations

import argparse
import platform
import sys
import time

import numpy as np


def main(argv=None) -> int:
    from swarmproof.checkers import proofs

    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--trees", type=int, default=5, help="max robots for the direct tree check (0: skip)")
    ap.add_argument("--tree-timeout", type=float, default=2.0)
    ap.add_argument("--oracle", type=int, default=200, help="kernel oracle instances (0: skip)")
    args = ap.parse_args(argv)

    print(f"python {platform.python_version()} on {platform.machine()}, z3 {proofs.z3.get_version_string()}")
    per = {lid: [] for lid in proofs.LEMMAS}
    totals = []
    ok = True
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        for r in proofs.run_suite():
            per[r.id].append(r.seconds)
            ok &= r.status == "proved"
        totals.append(time.perf_counter() - t0)
    print(f"{'lemma':<32} {'best s':>8} {'worst s':>8}")
    for lid, ts in per.items():
        print(f"{lid:<32} {min(ts):8.3f} {max(ts):8.3f}")
    worst = max(max(ts) for ts in per.values())
    print(f"suite total: best {min(totals):.2f} s, worst {max(totals):.2f} s over {args.repeat} runs; "
          f"all proved: {ok}")
    print(f"targets: suite < 10 s: {max(totals) < 10}; every lemma < 2 s: {worst < 2}")

    if args.trees >= 2:
        t0 = time.perf_counter()
        out = proofs.confirm_trees(args.trees, timeout_s=args.tree_timeout)
        dt = time.perf_counter() - t0
        print(f"direct tree confirmation up to {args.trees} robots "
              f"(timeout {args.tree_timeout} s per case): {out['counts']} in {dt:.1f} s")
        by_n = {}
        for n, *_rest, status, _why in out["not_proved"]:
            by_n[n] = by_n.get(n, 0) + 1
        print(f"  not proved, by robots: {dict(sorted(by_n.items()))}")

    if args.oracle:
        from swarmproof.models.geometry import nearest_point_in_disc_intersection as kernel
        rng = np.random.default_rng(0)
        counts = {}
        t0 = time.perf_counter()
        for _ in range(args.oracle):
            phi = rng.uniform(0.5, 2.0)
            vdt = rng.uniform(0.01, 0.49) * phi
            p = rng.uniform(-3, 3, 2)
            i = p + rng.uniform(-1, 1, 2) * phi / np.sqrt(2)
            st, _ = proofs.kernel_oracle_check(kernel, tuple(i), vdt, tuple(p), phi - vdt,
                                               tuple(i + rng.uniform(-3, 3, 2)))
            counts[st] = counts.get(st, 0) + 1
        print(f"kernel oracle: {args.oracle} instances {counts} in {time.perf_counter() - t0:.2f} s")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
