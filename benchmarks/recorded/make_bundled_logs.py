"""Make the recorded runs swarmproof ships (verify's default ``recorded`` rows; docs/recorded-runs.md).

Run from the repository's root: ``.venv/bin/python benchmarks/recorded/make_bundled_logs.py``
writes them into ``models/recorded/``.  Same bytes every time (seeded).

* ``eight-robots-split.csv``: what a hardware log looks like -- eight robots in a 2 x 4 grid
  1 m apart, sampled at 10 Hz each on its own clock (start offsets, +-5 ms jitter, a 5 mm
  position noise), a spanning tree along the rows (``parent`` column).  At 12 s robot 7 starts
  to drive away at 0.25 m/s; with range 1.5 m its last link (to robot 3 and 6, 1 m away) breaks
  when it is 1.5 m from both: the graph splits at about 12 + (sqrt(1.5^2 - 0.5^2)... ) s, the
  time check-run reports.  Written with Python's csv module, not swarmproof's exporter.
* ``song2016-square.mcap``: ``swarmproof simulate song2016 --lattice square --robots 6 --seed 1``
  exported with ``swarmproof export`` (a run of the reference implementation as a ROS 2 user's
  tools see it).
"""

import csv
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "models", "recorded")


def eight_robots_split(path: str) -> None:
    rng = np.random.default_rng(34)
    home = {k: (float(k % 4), float(k // 4)) for k in range(8)}
    parent = {0: -1, 1: 0, 2: 1, 3: 2, 4: 0, 5: 4, 6: 5, 7: 6}
    rows = []
    for rid in range(8):
        t = 0.01 * rid                       # each robot's own start
        while t <= 30.0:
            x, y = home[rid]
            if rid == 7 and t > 12.0:
                x += 0.25 * (t - 12.0) * math.cos(math.radians(30))
                y += 0.25 * (t - 12.0) * math.sin(math.radians(30))
            rows.append((round(t, 4), rid, x + rng.normal(0, 0.005), y + rng.normal(0, 0.005),
                         math.radians(30) if rid == 7 and t > 12.0 else 0.0, parent[rid]))
            t += 0.1 + rng.uniform(-0.005, 0.005)
    rows.sort(key=lambda r: (r[0], r[1]))
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["t", "id", "x", "y", "theta", "parent"])
        for t, rid, x, y, th, par in rows:
            w.writerow([f"{t:.4f}", rid, f"{x:.4f}", f"{y:.4f}", f"{th:.4f}", "" if par < 0 else par])
    os.replace(tmp, path)


def song2016_square(path: str) -> None:
    exe = os.path.join(os.path.dirname(sys.executable), "swarmproof")
    trace = path + ".trace.json"
    subprocess.run([exe, "simulate", "song2016", "--lattice", "square", "--robots", "6", "--seed", "1",
                    "--trace", trace], check=True, stdout=subprocess.DEVNULL)
    if os.path.exists(path):
        os.remove(path)
    subprocess.run([exe, "export", trace, "--to", path], check=True, stdout=subprocess.DEVNULL)
    os.remove(trace)


if __name__ == "__main__":
    eight_robots_split(os.path.join(HERE, "eight-robots-split.csv"))
    song2016_square(os.path.join(HERE, "song2016-square.mcap"))
