"""Timings of the z3 proof suite (issue 5: whole suite under 10 s, no lemma over 2 s).

Run: ``.venv/bin/python benchmarks/bench_proofs.py [--repeat N] [--trees N] [--no-symmetry]``.
Prints per-lemma seconds (CPU time of this process, ``time.process_time``, which includes
z3's work, and wall-clock, the best and worst of N runs), the suite total, whether the
targets are met, the direct tree confirmation (every tree shape up to ``--trees`` robots;
with ``--no-symmetry`` also without the symmetry reduction) and the geometry-kernel
oracle.  Figures go to docs/performance.md ("Proof suite"), never into timed tests.
"""

from __future__ import annotations

import argparse
import platform
import sys
import time

import numpy as np


def _timed(fn, *args, **kwargs):
    """(result, CPU seconds, wall seconds) of one call."""
    c0, w0 = time.process_time(), time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.process_time() - c0, time.perf_counter() - w0


def _trees(proofs, n: int, rlimit: int, symmetry: bool) -> None:
    out, cpu, wall = _timed(proofs.confirm_trees, n, rlimit=rlimit, symmetry=symmetry)
    print(f"direct tree confirmation up to {n} robots, symmetry={symmetry} "
          f"(rlimit {rlimit} per z3 problem): {out['cases']} cases {out['counts']}, "
          f"{out['classes']} z3 problems {out['class_counts']}; CPU {cpu:.1f} s, wall {wall:.1f} s")
    by_n = {}
    for k, *_rest, status, _why in out["not_proved"]:
        by_n[k] = by_n.get(k, 0) + 1
    print(f"  not proved, by robots: {dict(sorted(by_n.items()))}")


def main(argv=None) -> int:
    from swarmproof.checkers import proofs

    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--trees", type=int, default=5, help="max robots for the direct tree check (0: skip)")
    ap.add_argument("--tree-rlimit", type=int, default=None,
                    help="z3's work budget per tree problem (default: confirm_trees' own)")
    ap.add_argument("--no-symmetry", action="store_true",
                    help="also run the tree check without the symmetry reduction")
    ap.add_argument("--oracle", type=int, default=200, help="kernel oracle instances (0: skip)")
    args = ap.parse_args(argv)

    print(f"python {platform.python_version()} on {platform.machine()}, z3 {proofs.z3.get_version_string()}")
    per = {lid: [] for lid in proofs.LEMMAS}
    used = {}
    totals = []
    ok = True
    for _ in range(args.repeat):
        cpu_total = wall_total = 0.0
        for lem in proofs.LEMMAS.values():
            r, cpu, wall = _timed(proofs.prove, lem)
            per[lem.id].append((cpu, wall))
            used[lem.id] = r.rlimit["used"]
            cpu_total, wall_total = cpu_total + cpu, wall_total + wall
            ok &= r.status == "proved"
        totals.append((cpu_total, wall_total))
    print(f"{'lemma':<36} {'CPU best':>9} {'CPU worst':>9} {'wall best':>9} {'wall worst':>10} {'rlimit used':>12}")
    for lid, ts in per.items():
        cpus, walls = [c for c, _ in ts], [w for _, w in ts]
        print(f"{lid:<36} {min(cpus):9.3f} {max(cpus):9.3f} {min(walls):9.3f} {max(walls):10.3f} {used[lid]:>12}")
    worst_cpu = max(c for ts in per.values() for c, _ in ts)
    worst_wall = max(w for ts in per.values() for _, w in ts)
    cpu_t, wall_t = [c for c, _ in totals], [w for _, w in totals]
    print(f"suite total over {args.repeat} runs: CPU {min(cpu_t):.2f}-{max(cpu_t):.2f} s, "
          f"wall {min(wall_t):.2f}-{max(wall_t):.2f} s; all proved: {ok}")
    print(f"target (issue 32): suite < 30 s: CPU {max(cpu_t) < 30}, wall {max(wall_t) < 30}; "
          f"slowest lemma: CPU {worst_cpu:.2f} s, wall {worst_wall:.2f} s")

    if args.trees >= 2:
        rlimit = args.tree_rlimit or proofs.CASE_RLIMIT
        _trees(proofs, args.trees, rlimit, True)
        if args.no_symmetry:
            _trees(proofs, args.trees, rlimit, False)

    if args.oracle:
        from swarmproof.models.geometry import nearest_point_in_disc_intersection as kernel
        rng = np.random.default_rng(0)
        counts = {}
        c0 = time.process_time()
        for _ in range(args.oracle):
            phi = rng.uniform(0.5, 2.0)
            vdt = rng.uniform(0.01, 0.49) * phi
            p = rng.uniform(-3, 3, 2)
            i = p + rng.uniform(-1, 1, 2) * phi / np.sqrt(2)
            st, _ = proofs.kernel_oracle_check(kernel, tuple(i), vdt, tuple(p), phi - vdt,
                                               tuple(i + rng.uniform(-3, 3, 2)))
            counts[st] = counts.get(st, 0) + 1
        print(f"kernel oracle: {args.oracle} instances {counts}, CPU {time.process_time() - c0:.2f} s")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
