"""Campaign speed on this machine (issue 18): 1 vs 2 workers on an 8-cell explorer campaign, and
Dask's per-task overhead against a typical task.  Numbers go to docs/performance.md "Campaigns".

    python benchmarks/bench_campaign.py            # about 2 minutes on 2 cores

Prints one JSON document: wall seconds for --workers 1 and 2 and their ratio, the tasks'
own seconds (median, from the results store's timings table), and the round-trip time per
trivial task through a 2-worker LocalCluster (submit, run, gather).
"""

from __future__ import annotations

import json
import os
import sqlite3
import statistics
import sys
import tempfile
import time

SPEC = """\
format: swarmproof-campaign/1
name: bench-8
explore:
""" + "".join(f"""  - algorithm: {algo}
    properties: [{prop}]
    robots: [3, 8]
    seeds: [0]
    max_examples: 60
""" for algo in ("song2016", "song2014") for prop in ("termination", "formation", "deadlock", "oscillation"))


def _noop(x):
    return x


def main() -> None:
    from swarmproof.checkers.campaign import _client, run_campaign
    from swarmproof.models.campaign_spec import loads_campaign

    spec = loads_campaign(SPEC)
    out = {"cells": len(spec.explore), "machine": f"{os.cpu_count()} cores", "python": sys.version.split()[0]}
    with tempfile.TemporaryDirectory() as tmp:
        for workers in (1, 2):
            t0 = time.perf_counter()
            res = run_campaign(spec, out_dir=os.path.join(tmp, f"w{workers}"), workers=workers)
            out[f"wall_workers_{workers}"] = round(time.perf_counter() - t0, 2)
            assert len(res.results) == 8
        con = sqlite3.connect(os.path.join(tmp, "w1", "results.sqlite"))
        secs = [s for (s,) in con.execute("SELECT seconds FROM timings")]
        con.close()
        out["task_seconds_median"] = round(statistics.median(secs), 3)
        out["task_seconds"] = sorted(round(s, 2) for s in secs)
    out["speedup_2_over_1"] = round(out["wall_workers_1"] / out["wall_workers_2"], 2)
    client, cluster = _client(None, 2)
    try:
        client.gather(client.map(_noop, range(20)))          # warm up
        n = 400
        t0 = time.perf_counter()
        client.gather(client.map(_noop, range(n), pure=False))
        per = (time.perf_counter() - t0) / n
        t0 = time.perf_counter()
        for i in range(50):                                    # one at a time: the latency bound
            client.submit(_noop, i, pure=False).result()
        latency = (time.perf_counter() - t0) / 50
    finally:
        client.close()
        cluster.close()
    out["dask_seconds_per_trivial_task"] = round(per, 5)
    out["dask_round_trip_seconds"] = round(latency, 5)
    out["overhead_share_of_median_task"] = round(per / out["task_seconds_median"], 4)
    out["round_trip_share_of_median_task"] = round(latency / out["task_seconds_median"], 4)
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
