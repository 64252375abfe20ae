"""wang2020's vectorised path at two revisions, side by side on a loaded machine.

Usage (from the repository root)::

    .venv/bin/python benchmarks/wang2020/bench_wang2020_turns.py --base main fig10 529 0
    .venv/bin/python benchmarks/wang2020/bench_wang2020_turns.py --base main fig9 1024 0 --max-steps 2000

The same trial runs twice in one process: ``reference_impl/wang2020/fast.py`` and
``experiments.py`` (its ``ProgressObserver``) as of ``--base`` (extracted with ``git archive``)
against the working tree's, in two threads that take turns tick by tick.  Each thread's own CPU
time (``time.thread_time``) is its run's, and both runs see the same machine load, so the ratio
holds where repeated runs' CPU times move by tens of per cent (other jobs beside them); the base
against itself gives 1.00 within 1 %.  The two traces (and ticks, distance) must be identical.
``fig10 N SEED``: a Fig. 10 trial (32 x 32 arena, to formation); ``fig9 N SEED``: Fig. 9's "N"
then "U" from its 48 x 48 start.  Prints one JSON line.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np


def _load(path: str, name: str):
    spec = importlib.util.spec_from_file_location("swarmproof.reference_impl.wang2020." + name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--base", default="main", help="git revision to compare the working tree with")
    ap.add_argument("mode", choices=("fig10", "fig9"))
    ap.add_argument("n", type=int)
    ap.add_argument("seed", type=int)
    ap.add_argument("--max-steps", type=int, default=None)
    a = ap.parse_args(argv)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    tmp = tempfile.mkdtemp(prefix="wang2020-turns-")
    archive = subprocess.run(["git", "-C", root, "archive", a.base, "reference_impl/wang2020"],
                             check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
    sides = []
    for tag, base in (("base", os.path.join(tmp, "reference_impl", "wang2020")),
                      ("tree", os.path.join(root, "reference_impl", "wang2020"))):
        sides.append((_load(os.path.join(base, "fast.py"), "fast_" + tag),
                      _load(os.path.join(base, "experiments.py"), "experiments_" + tag)))

    from swarmproof.models.shapes import shape_for
    from swarmproof.models.trace import InitialConfiguration
    from swarmproof.reference_impl.wang2020.algorithm import Wang2020, goal_cells
    from swarmproof.reference_impl.wang2020.experiments import experiment_params, fig10_instance, start_cells

    n, seed = a.n, a.seed
    if a.mode == "fig10":
        goals, starts = fig10_instance(n, seed, 32)
        then = ()
    else:
        goals = shape_for("letter-n", n)
        starts = start_cells(goals.cells, n, np.random.default_rng(seed), arena=48)
        then = shape_for("letter-u", n)
    cond = threading.Condition()
    st = {"who": 0, "done": [False, False]}
    out = [None, None]

    class Turn:
        """An observer that hands the turn to the other run after every tick."""
        name = "turn"

        def __init__(self, me: int) -> None:
            self.me = me

        def start(self, ids) -> None:
            pass

        def observe(self, t, poses, states, present) -> None:
            with cond:
                st["who"] = 1 - self.me
                cond.notify_all()
                cond.wait_for(lambda: st["who"] == self.me or st["done"][1 - self.me])

        def result(self):
            return None

    def run(me: int) -> None:
        with cond:
            cond.wait_for(lambda: st["who"] == me)
        fast, X = sides[me]
        p = experiment_params(n)
        l = float(p.extra["grid_spacing"])
        init = InitialConfiguration(list(range(n)), [[l * x, l * y, 0.0] for x, y in starts])
        obs = [X.ProgressObserver(goal_cells(goals, l), l, every=10 if a.mode == "fig10" else 1000)]
        if then:
            obs.append(X.ProgressObserver(goal_cells(then, l), l, every=1000))
        stop = (lambda t, po, s, pr: obs[0].formed_step is not None) if a.mode == "fig10" else None
        try:
            c0 = time.thread_time()
            r = fast.simulate_fast(Wang2020(then=then), goals, init, p, seed=seed,
                                   record_every=1000 if a.mode == "fig10" else 2000,
                                   observers=obs + [Turn(me)], stop_when=stop, max_steps=a.max_steps)
            out[me] = (time.thread_time() - c0, r.steps, obs[0].result()["distance"], fast.trace_json(r))
        finally:
            with cond:
                st["done"][me] = True
                st["who"] = 1 - me
                cond.notify_all()

    threads = [threading.Thread(target=run, args=(k,)) for k in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    (ca, sa, da, ja), (cb, sb, db, jb) = out
    if (sa, da, ja) != (sb, db, jb):
        raise SystemExit("the two revisions' runs differ (ticks, distance or trace)")
    res = {"mode": a.mode, "n": n, "seed": seed, "ticks": sa, "base": a.base,
           "base_ms_per_tick": round(1000 * ca / sa, 3), "tree_ms_per_tick": round(1000 * cb / sb, 3),
           "tree/base": round(cb / ca, 3), "base_cpu_s": round(ca, 1), "tree_cpu_s": round(cb, 1),
           "load_avg": round(os.getloadavg()[0], 1)}
    print(json.dumps(res), flush=True)
    return res


if __name__ == "__main__":
    main()
