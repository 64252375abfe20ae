"""Hashes of a fixed set of reference traces: the bit-identity check of a core change.

Issue 12 ("One algorithm, one module") requires song2014 and song2016 traces to stay
bit-identical across the engine's reshaping.  This script runs a fixed set of runs
(song2016 and song2014 on the acceptance lattices, several sizes and seeds; the example
algorithm under every fault hook; a run with messages recorded) and prints one sha256
per run, of the trace's substance: every step's poses (exact bytes), controller
states, events, presence, recorded messages, status and step count.

Usage::

    python benchmarks/trace_hashes.py > before.txt     # on the old commit
    python benchmarks/trace_hashes.py | diff before.txt -   # on the new one

The same set is pinned in tests/reference_impl/test_trace_identity.py
(tests/reference_impl/data/trace_hashes.json); `--write` refreshes that file,
which only a change that is meant to change traces may do (and must say so).
"""

from __future__ import annotations

import hashlib
import json
import sys

import numpy as np

from swarmproof.models.library import load
from swarmproof.models.trace import to_jsonable
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Params
from swarmproof.reference_impl.registry import get_algorithm


def _states_jsonable(states) -> list:
    """``to_jsonable([list(s) for s in states])``, computed once per state object: a robot's
    state object is shared by every step it stays unchanged (87,150 states, 6,670 objects in
    the n=30 run), and ``to_jsonable`` is a pure function of it (the same JSON, so the same
    digest, as converting each step afresh; 5 of the n=30 case's 7 s were this conversion)."""
    memo: dict[int, object] = {}
    out = []
    for step in states:
        row = []
        for x in step:
            k = id(x)
            v = memo.get(k)
            if v is None:
                v = memo[k] = to_jsonable(x)
            row.append(v)
        out.append(row)
    return out


def digest(result) -> str:
    tr = result.trace
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(tr.poses).tobytes())
    h.update(repr(tr.ids.tolist()).encode())
    h.update(json.dumps(_states_jsonable(tr.states), sort_keys=True).encode())
    h.update(json.dumps([e.as_dict() for e in tr.events], sort_keys=True).encode())
    if tr.present is not None:
        h.update(np.ascontiguousarray(tr.present).tobytes())
    if tr.messages is not None:
        h.update(json.dumps(to_jsonable(tr.messages), sort_keys=True).encode())
    h.update(f"{result.status}:{result.steps}".encode())
    return h.hexdigest()


def cases():
    """(label, thunk) pairs; each thunk returns a SimulationResult."""
    from swarmproof.reference_impl.engine import DropSet, FaultModel, TableSchedule, simulate

    for name in ("square", "hexagon", "octagon-square"):
        lat = load(name)
        for n in (10, 20):
            for seed in (0, 1, 2):
                init = random_connected(n, seed, range=lat.range, min_separation=0.3)
                yield (f"song2016 {name} n={n} seed={seed}",
                       lambda lat=lat, n=n, seed=seed, init=init: simulate(
                           get_algorithm("song2016", n_robots=n), lat, init,
                           Params(range=lat.range, v=0.05), seed=seed))
    lat = load("hexagon")
    init = random_connected(30, 0, range=lat.range, min_separation=0.3)
    yield ("song2016 hexagon n=30 seed=0 stable_first",
           lambda: simulate(get_algorithm("song2016", n_robots=30, parent_rule="stable_first"), lat, init,
                            Params(range=lat.range, v=0.05), seed=0))
    lat = load("square")
    init = random_connected(8, 3, range=lat.range, min_separation=0.3)
    yield ("song2016 square n=8 seed=3 messages",
           lambda: simulate(get_algorithm("song2016", n_robots=8), lat, init,
                            Params(range=lat.range, v=0.05), seed=3, record_messages=True))
    for name in ("square", "hexagon"):
        lat = load(name)
        for n in (10, 20):
            for seed in (0, 1):
                init = random_connected(n, seed, range=lat.range, min_separation=0.3)
                yield (f"song2014 {name} n={n} seed={seed}",
                       lambda lat=lat, n=n, seed=seed, init=init: simulate(
                           get_algorithm("song2014", n_robots=n), lat, init,
                           Params(range=lat.range, v=0.05), seed=seed))
    lat = load("square")
    init = random_connected(6, 4, range=1.2, min_separation=0.3)
    faults = {
        "schedule": FaultModel(schedule=TableSchedule({1: (0, 2), 3: (1,), 4: ()})),
        "crash+add": FaultModel(crashes={5: [2]}, additions={3: [(99, [0.3, 0.3, 0.0])]}),
        "drops": FaultModel(drop_message=DropSet({(1, 0, 1), (2, 1, 0)}), message_loss=0.2),
        "noise": FaultModel(noise_std=(0.01, 0.02)),
        # pinned on commit 2a774c5, before the engine's choice points (issue 33)
        "late": FaultModel(message_delay=2, message_duplication=0.3, message_reorder=True, message_loss=0.1),
    }
    for label, fm in faults.items():
        for alg in ("example-gather", "song2016"):
            yield (f"{alg} square n=6 seed=4 faults={label}",
                   lambda fm=fm, alg=alg: simulate(get_algorithm(alg, n_robots=6), lat, init,
                                                   Params(range=1.2, v=0.05), seed=4, faults=fm,
                                                   allow_violations=True, max_steps=400,
                                                   record_messages=True))
    # wang2020: grid motion, asynchronous clocks and point-to-point exchanges; plain and with
    # late and lost messages (pinned on commit 2a774c5, before the engine's choice points)
    from swarmproof.models.targets import resolve_target
    from swarmproof.reference_impl.initial import random_grid_connected

    shape = resolve_target("shape:square-9")
    grid_init = random_grid_connected(9, 0, range=0.6, spacing=0.2)
    for label, fm in (("none", None), ("late", FaultModel(message_delay=2, message_loss=0.1))):
        yield (f"wang2020 shape:square-9 n=9 seed=0 faults={label}",
               lambda fm=fm: simulate(get_algorithm("wang2020"), shape, grid_init,
                                      get_algorithm("wang2020").default_params(0.6, 9), seed=0, faults=fm,
                                      allow_violations=True, max_steps=3000))


def main(argv) -> int:
    out = {label: digest(thunk()) for label, thunk in cases()}
    if "--write" in argv:
        path = "tests/reference_impl/data/trace_hashes.json"
        with open(path, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=1, sort_keys=True)
            fh.write("\n")
        print(f"wrote {path} ({len(out)} traces)")
    else:
        for label, h in out.items():
            print(f"{h}  {label}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
