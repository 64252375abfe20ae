"""What wang2020's explorations run into: handshakes per run, and the Lemma IV-B.2 / Sec. III-A findings (issue 30).

Usage (from the repository root)::

    .venv/bin/python benchmarks/wang2020/bench_wang2020_handshake.py [--examples 200] [--latency-examples 30] [--seed 0]

For each reading (``wang2020``: the handshake as an exchange answered within the tick;
``wang2020-broadcast-handshake``: request and ACK in the broadcasts) and fault setting (none; the
explorer's ``latency`` fault kind), it runs the explorer's own scenarios -- ``swarmproof explore
READING --max-examples N --seed S [--fault latency]``, robots 3..8 on letter-l and square-9 -- with
a measuring property that always holds (so no search stops early; the scenarios are the
explorer's strategy's, though not in the order an ``invariants`` search, which Hypothesis steers
by its failures, meets them), and counts per run:

* ``handshakes``: handshakes completed (a server took its client's goal; state ``took``);
* ``half swaps``: servers that took a goal whose client's handshake then ended without the
  server's (the ``pairwise_swap`` invariant's finding);
* ``J2 rises`` and ``J1 rises while J2 = 0``: steps where Lemma IV-B.2's statements fail
  (``j2_monotone``, ``j1_monotone``).

It prints one table; docs/wang2020.md ("The handshake") quotes it with the date.  Every random
choice comes from the seed (Hypothesis derandomized, the engine's seeds).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from swarmproof.checkers.explore import explore
from swarmproof.invariants.registry import Property, register_property, unregister_property
from swarmproof.invariants.result import InvariantResult
from swarmproof.reference_impl.wang2020.algorithm import make_invariants

RUNS: list = []


def _measure(trace, ctx):
    """Count handshakes and the invariants' findings on one dense trace; always held."""
    checks = {i.name: i for i in make_invariants()}
    ids = np.asarray(trace.ids)
    seen_took: dict = {}
    hand = half = j2 = j1 = 0
    for k, states in enumerate(trace.states):
        if any(s is None for s in states):
            continue
        for r, s in zip(ids.tolist(), states):
            tk = dict(s).get("took")
            if tk is not None and tk != seen_took.get(r):
                seen_took[r] = tk
                hand += tk[0] == "server"
        t = int(trace.times[k]) if getattr(trace, "times", None) else k
        poses = trace.poses[k]
        for name in ("j2_monotone", "j1_monotone", "pairwise_swap"):
            msg = checks[name].check(t, ids, poses, states)
            if msg is not None:
                if name == "j2_monotone":
                    j2 += 1
                elif name == "j1_monotone":
                    j1 += 1
                else:
                    half += 1
    RUNS.append((trace.n, int(trace.steps), hand, half, j2, j1))
    return InvariantResult("handshake_count", "held", "measurement", None, f"{hand} handshakes")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=200)
    ap.add_argument("--latency-examples", type=int, default=30,
                    help="examples with the latency fault (its runs are long: most reach the step cap)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    register_property(Property("handshake_count", "safety", _measure, reads=("states",), cites="measurement"),
                      replace=True)
    try:
        print(f"{'reading':32} {'faults':8} {'runs':>5} {'steps/run':>9} {'handshakes/run':>14} "
              f"{'half swaps':>10} {'runs w/ J2 rise':>15} {'runs w/ J1 rise':>15} {'s':>6}")
        for name in ("wang2020", "wang2020-broadcast-handshake"):
            for faults in ((), ("latency",)):
                RUNS.clear()
                t0 = time.perf_counter()
                explore(name, ["handshake_count"], budget=None, seed=args.seed, draw_faults=faults,
                        max_examples=args.latency_examples if faults else args.examples)
                dt = time.perf_counter() - t0
                runs = len(RUNS)
                hs = sum(r[2] for r in RUNS)
                print(f"{name:32} {'+'.join(faults) or 'none':8} {runs:5d} "
                      f"{np.mean([r[1] for r in RUNS]):9.0f} {hs / max(runs, 1):14.2f} "
                      f"{sum(r[3] for r in RUNS):10d} {sum(1 for r in RUNS if r[4]):15d} "
                      f"{sum(1 for r in RUNS if r[5]):15d} {dt:6.1f}")
    finally:
        unregister_property("handshake_count")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
