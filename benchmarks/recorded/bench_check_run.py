"""Recorded runs (issue 34): the cost of ``swarmproof check-run`` per log format, in docs/performance.md.

Usage (from the repository root)::

    .venv/bin/python benchmarks/recorded/bench_check_run.py            # 100 robots, 10 min, 10 Hz: 600,000 poses
    .venv/bin/python benchmarks/recorded/bench_check_run.py --quick    # 20 robots, 1 min (12,000 poses)
    .venv/bin/python benchmarks/recorded/bench_check_run.py --dir /tmp/logs --formats csv mcap

The target (issue 34): a 100-robot, 10-minute, 10 Hz log (600,000 poses) checked for connectivity
and collision in under 10 s of CPU from CSV (reading and checking together); for the bags (rosbag2
with sqlite3 storage, rosbag2 with mcap storage, plain MCAP) the decoding measured apart and the
checking after it under 10 s; memory bounded.

The log is generated, deterministic (seeded): a 10 x 10 grid of robots 0.6 m apart (range 1.0 m,
disc radius 0.1 m) whose centre drives a smooth Lissajous curve at about 0.2 m/s while the grid
turns slowly, each robot wobbling a few centimetres about its slot, heading along its velocity.
Each robot samples at 10 Hz from its own phase (uniform in one period) with a seeded jitter of
2 ms (clipped to 8 ms), so the robots' samples interleave as a real log's do; times start at
2026-01-01 00:00 UTC (epoch stamps, as ROS records them).  The same samples are written as CSV, MCAP and rosbag2 (sqlite3 and mcap storage) by swarmproof's own exporter
(:func:`swarmproof.models.recorded_io.write_log`: ``geometry_msgs/msg/PoseStamped`` on
``/robot_{id}/pose``, header stamp = log time), not by ROS; writing is not timed against the
target (its wall time is printed for information).  ``--parents`` adds a parent per robot (its
grid neighbour towards robot 0: a CSV column, ``std_msgs/msg/Int32`` topics in the bags).

Each measurement runs in a fresh process: ``read`` times
:func:`~swarmproof.models.recorded_io.read_log` (CPU seconds, ``time.process_time``); ``check``
reads the log untimed, then times :func:`~swarmproof.checkers.recorded.check_recorded` with
``properties=["connectivity", "collision"]`` at ``pos_tol`` 0 (two monitors) and 0.01 m (six: each
property's nominal monitor and both margins).  Memory is the process's peak resident set
(``VmHWM`` of /proc/self/status: ``ru_maxrss`` of a child starts from its parent's peak, here the
log generator's), interpreter and libraries included: the ``base`` column is the peak after the
imports.  The check's own peak of Python and numpy allocations above the held log is measured once
more under ``tracemalloc`` (``--no-tracemalloc`` skips it).  Exit 1 when a target is missed (at
the full size).
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time

FORMATS = ("csv", "mcap", "rosbag2-sqlite3", "rosbag2-mcap")
TARGET_S = 10.0
PHI = 1.0
SPACING = 0.6
#: The log's first instant: 2026-01-01 00:00 UTC (a ROS clock's stamps are epoch times).
EPOCH_NS = 1_767_225_600 * 10**9
#: Bumped when :func:`samples` changes (a kept --dir is then written anew).
GENERATOR = 1


def _rss_mib() -> float:
    """This process's peak resident memory so far, MiB: ``VmHWM`` of /proc/self/status (``ru_maxrss`` of
    a child process on Linux starts from its parent's peak at the fork, here the log generator's)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


# ---------------------------------------------------------------------------------------------
# the log


def samples(robots: int, minutes: float, hz: float, seed: int = 0, parents: bool = False):
    """``(t_ns, id, x, y, theta, parent)`` in time order: the formation described in the module doc."""
    import numpy as np

    rng = np.random.default_rng(seed)
    side = int(math.ceil(math.sqrt(robots)))
    slot = np.array([((i % side) - (side - 1) / 2, (i // side) - (side - 1) / 2) for i in range(robots)]) * SPACING
    period = 1.0 / hz
    count = int(round(minutes * 60 * hz))
    phase = rng.uniform(0.0, period, robots)
    jitter = np.clip(rng.normal(0.0, 0.002, (robots, count)), -0.008, 0.008)
    t = np.arange(count)[None, :] * period + phase[:, None] + jitter                    # (robots, count) s
    w_amp = rng.uniform(0.01, 0.05, robots)[:, None]
    w_freq = rng.uniform(0.05, 0.3, robots)[:, None]
    w_ph = rng.uniform(0.0, 2 * math.pi, (robots, 2))

    def position(tt):
        cx, cy = 20.0 * np.sin(0.01 * tt), 12.0 * np.sin(0.016 * tt)                     # about 0.2 m/s
        rot = 0.004 * tt                                                                  # the grid turns
        c, s = np.cos(rot), np.sin(rot)
        sx, sy = slot[:, 0:1], slot[:, 1:2]
        x = cx + c * sx - s * sy + w_amp * np.sin(2 * math.pi * w_freq * tt + w_ph[:, 0:1])
        y = cy + s * sx + c * sy + w_amp * np.cos(2 * math.pi * w_freq * tt + w_ph[:, 1:2])
        return x, y

    t = t + period                                                                      # after the epoch
    x, y = position(t)
    x2, y2 = position(t + 1e-3)
    theta = np.arctan2(y2 - y, x2 - x)
    t_ns = EPOCH_NS + np.round(t * 1e9).astype(np.int64)
    par = None
    if parents:        # towards robot 0 along the grid: left neighbour, or the one below in column 0
        par = [(-1 if i == 0 else (i - 1 if i % side else i - side)) for i in range(robots)]
    order = np.argsort(t_ns, axis=None, kind="stable")
    rid, k = np.unravel_index(order, t_ns.shape)
    ids = rid.tolist()
    tl, xl, yl, hl = t_ns[rid, k].tolist(), x[rid, k].tolist(), y[rid, k].tolist(), theta[rid, k].tolist()
    for n in range(len(ids)):
        i = ids[n]
        yield tl[n], i, xl[n], yl[n], hl[n], (None if par is None or par[i] < 0 else par[i])


def log_path(folder: str, fmt: str) -> str:
    if fmt in ("csv", "mcap"):
        return os.path.join(folder, f"run.{fmt}")
    return os.path.join(folder, f"run-{fmt.split('-')[1]}")          # a rosbag2 bag's folder


def write_logs(folder: str, formats, robots: int, minutes: float, hz: float, seed: int, parents: bool) -> dict:
    """Write the log in each format (skipped when ``folder`` already holds it with the same settings)."""
    from swarmproof.models.recorded_io import write_log

    os.makedirs(folder, exist_ok=True)
    settings = {"generator": GENERATOR, "robots": robots, "minutes": minutes, "hz": hz, "seed": seed, "parents": parents}
    manifest = os.path.join(folder, "settings.json")
    same = os.path.exists(manifest) and json.load(open(manifest)) == settings
    if not same:
        import shutil

        for fmt in FORMATS:
            p = log_path(folder, fmt)
            if os.path.isdir(p):
                shutil.rmtree(p)
            elif os.path.exists(p):
                os.remove(p)
        with open(manifest, "w") as fh:
            json.dump(settings, fh)
    out = {}
    for fmt in formats:
        p = log_path(folder, fmt)
        if not os.path.exists(p):
            w0 = time.perf_counter()
            write_log(samples(robots, minutes, hz, seed, parents), p, ids=range(robots), has_parent=parents,
                      storage=fmt.split("-")[1] if fmt.startswith("rosbag2") else None)
            print(f"  wrote {fmt}: {p} ({time.perf_counter() - w0:.0f} s wall, swarmproof's exporter)", flush=True)
        out[fmt] = p
    return out


def size_of(path: str) -> int:
    if os.path.isdir(path):
        return sum(os.path.getsize(os.path.join(r, f)) for r, _, fs in os.walk(path) for f in fs)
    return os.path.getsize(path)


# ---------------------------------------------------------------------------------------------
# one measurement, in its own process


def measure(what: str, path: str, pos_tol: float, traced: bool) -> dict:
    import gc

    from swarmproof.checkers.recorded import check_recorded
    from swarmproof.models.recorded_io import read_log

    try:                                   # the bag readers' imports: part of the base, not of the read
        import mcap_ros2.decoder  # noqa: F401
        import rosbags.rosbag2  # noqa: F401
        import rosbags.typesys  # noqa: F401
        from mcap.reader import make_reader  # noqa: F401
    except ImportError:
        pass
    base = _rss_mib()
    c0 = time.process_time()
    log = read_log(path)
    read_cpu = time.process_time() - c0
    out = {"what": what, "format": log.format, "samples": log.samples, "robots": len(log.robots),
           # a CSV row holds a pose and its parent; a bag has a message for each
           "messages": log.samples + (sum(len(p.t) for p in log.parents.values())
                                      if log.parents and log.format != "csv" else 0),
           "held_mib": (sum(r.t.nbytes + r.xyt.nbytes for r in log.robots.values())
                        + sum(p.t.nbytes + p.parent.nbytes for p in (log.parents or {}).values())) / 2**20,
           "base_rss_mib": base, "read_cpu": read_cpu, "read_rss_mib": _rss_mib()}
    if what == "check":
        gc.collect()
        if traced:
            import tracemalloc

            tracemalloc.start()
        c0 = time.process_time()
        rep = check_recorded(log, phi=PHI, properties=["connectivity", "collision"], pos_tol=pos_tol)
        out["check_cpu"] = time.process_time() - c0
        if traced:
            out["check_traced_peak_mib"] = tracemalloc.get_traced_memory()[1] / 2**20
            tracemalloc.stop()
        out.update(pos_tol=pos_tol, instants=rep.clock.instants, judged=rep.judged_instants,
                   verdicts={k: r.status for k, r in rep.results.items()},
                   sensitive=rep.sensitive, check_rss_mib=_rss_mib())
    return out


def run_one(what: str, path: str, pos_tol: float = 0.0, traced: bool = False) -> dict:
    cmd = [sys.executable, os.path.abspath(__file__), "--one", what, path, "--pos-tol", repr(pos_tol)]
    if traced:
        cmd.append("--traced")
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"bench_check_run: the {what} of {path} failed:\n{out.stderr}")
    return json.loads(out.stdout.strip().splitlines()[-1])


# ---------------------------------------------------------------------------------------------


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="20 robots, 1 minute (12,000 poses)")
    ap.add_argument("--robots", type=int)
    ap.add_argument("--minutes", type=float)
    ap.add_argument("--hz", type=float, default=10.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--parents", action="store_true", help="log a parent per robot too")
    ap.add_argument("--formats", nargs="+", choices=FORMATS, default=list(FORMATS))
    ap.add_argument("--pos-tol", type=float, nargs="+", default=[0.0, 0.01], dest="pos_tols")
    ap.add_argument("--dir", help="where the logs are written (kept and reused; default: a temporary folder)")
    ap.add_argument("--no-tracemalloc", action="store_true", help="skip the check's traced peak")
    ap.add_argument("--json", help="write every measurement to this file")
    ap.add_argument("--one", nargs=2, metavar=("WHAT", "PATH"), help=argparse.SUPPRESS)
    ap.add_argument("--traced", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        print(json.dumps(measure(args.one[0], args.one[1], args.pos_tols[0], args.traced)))
        return 0
    robots = args.robots or (20 if args.quick else 100)
    minutes = args.minutes or (1.0 if args.quick else 10.0)
    tmp = None
    if args.dir is None:
        tmp = tempfile.TemporaryDirectory(prefix="bench-check-run-")
    folder = args.dir or tmp.name
    print(f"# check-run: {robots} robots, {minutes:g} min, {args.hz:g} Hz "
          f"({int(robots * minutes * 60 * args.hz):,} poses){', with parents' if args.parents else ''}; "
          f"{os.cpu_count()}-core {platform.machine()}, Python {platform.python_version()}, "
          f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, "
          f"load average {os.getloadavg()[0]:.2f}", flush=True)
    paths = write_logs(folder, args.formats, robots, minutes, args.hz, args.seed, args.parents)
    rows = []
    for fmt in args.formats:
        p = paths[fmt]
        r = run_one("read", p)
        r["file_mib"] = size_of(p) / 2**20
        checks = [run_one("check", p, pt) for pt in args.pos_tols]
        rows.append((fmt, r, checks))
        print(f"  {fmt}: read {r['read_cpu']:.2f} s" + "".join(f", check(pos_tol={c['pos_tol']:g}) "
                                                             f"{c['check_cpu']:.2f} s" for c in checks), flush=True)
    traced = [] if args.no_tracemalloc else [run_one("check", paths[args.formats[0]], pt, traced=True)
                                             for pt in args.pos_tols]

    print("\n| format | file MiB | messages (CSV: rows) | read CPU s | per message | peak RSS after read MiB (base) | "
          + " | ".join(f"check CPU s, pos_tol {pt:g}" for pt in args.pos_tols)
          + " | read + check CPU s (worst) | peak RSS, whole run MiB | verdicts |")
    print("|---|---|---|---|---|---|" + "---|" * len(args.pos_tols) + "---|---|---|")
    missed = []
    for fmt, r, checks in rows:
        worst = max(c["check_cpu"] for c in checks)
        total = r["read_cpu"] + worst
        verdicts = checks[0]["verdicts"]
        sens = checks[-1]["sensitive"]
        vtext = ", ".join(f"{k} {v}" + (" (tolerance-sensitive)" if sens.get(k) else "") for k, v in verdicts.items())
        print(f"| {fmt} | {r['file_mib']:.1f} | {r['messages']:,} | {r['read_cpu']:.2f} | "
              f"{1e6 * r['read_cpu'] / r['messages']:.1f} us | {r['read_rss_mib']:.0f} ({r['base_rss_mib']:.0f}) | "
              + " | ".join(f"{c['check_cpu']:.2f}" for c in checks)
              + f" | {total:.2f} | {max(c['check_rss_mib'] for c in checks):.0f} | {vtext} |")
        if fmt == "csv" and total > TARGET_S:
            missed.append(f"CSV read + check {total:.1f} s > {TARGET_S:g} s")
        if worst > TARGET_S:
            missed.append(f"{fmt} check {worst:.1f} s > {TARGET_S:g} s")
    c = rows[0][2][0]
    print(f"\nclock: {c['instants']:,} instants, {c['judged']:,} judged; samples held: "
          f"{rows[0][1]['held_mib']:.1f} MiB ({rows[0][1]['samples']:,} poses)")
    for t in traced:
        print(f"check's traced peak (tracemalloc, above the held log), pos_tol {t['pos_tol']:g}: "
              f"{t['check_traced_peak_mib']:.1f} MiB")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"robots": robots, "minutes": minutes, "hz": args.hz, "rows": rows, "traced": traced}, fh,
                      indent=1)
    if tmp is not None:
        tmp.cleanup()
    if missed and robots * minutes * 60 * args.hz >= 600_000:
        print("target missed: " + "; ".join(missed))
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
