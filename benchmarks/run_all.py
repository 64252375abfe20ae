"""Run every benchmark (``bench_*.py`` here and in each paper's folder) in sequence, small settings (``make bench``).

Usage (from the repository root)::

    .venv/bin/python benchmarks/run_all.py            # every bench_*.py, small settings
    .venv/bin/python benchmarks/run_all.py --only proofs --only engine
    .venv/bin/python benchmarks/run_all.py --full     # each benchmark's own defaults (long)
    .venv/bin/python benchmarks/run_all.py --list

The benchmarks are found by the globs ``bench_*.py`` (the shared tools at
benchmarks/ top level) and ``*/bench_*.py`` (a folder per paper:
benchmarks/song2014/, song2016/, jiang/, leechong/, wang2020/) when this
runs, so a new one is picked up without a change here; a benchmark is named
by its file stem, which must be unique across the folders.  Each runs in its own process, one
after the other (the machine has 2 cores; timings of parallel benchmarks
would be noise).  ``SMALL_ARGS`` holds the arguments that keep a benchmark
short; a benchmark not listed there runs with no arguments (its defaults).
Its output is passed through; a closing summary gives each benchmark's exit
code, wall and CPU seconds (``resource.getrusage(RUSAGE_CHILDREN)``: the
child's user + system time) and the section of docs/performance.md its
figures go to.  Figures are recorded there by hand with the machine, the
date and whether the machine was shared; no timed figure goes into a test.

Exit code: 0 when every benchmark exited 0, else 1 (a benchmark that misses
its target exits non-zero, e.g. bench_lattice_check.py), 2 for bad arguments.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: Arguments that keep each benchmark small (``--full`` drops them).
SMALL_ARGS: dict[str, list[str]] = {
    "bench_engine": ["--quick"],
    "bench_engine_compare": ["--repeat", "2"],
    "bench_lattice_check": ["--repeat", "3"],
    "bench_proofs": ["--repeat", "1", "--trees", "3"],   # trees up to 5 robots: about 500 s
    "bench_song2014": ["perf", "--repeats", "1", "--sizes", "50"],
    "bench_song2016": ["--quick"],
    "bench_song2016_steps": ["--sizes", "10", "--trials", "2", "--speeds", "0.2"],
    "bench_mutations": ["--budget", "10"],
    "bench_jiang": ["perf", "--seeds", "1", "--sizes", "10,20"],
    "bench_wang2020": ["perf", "--robots", "64", "--trial-robots", "16"],
    "bench_wang2020_ratio": ["decompose", "--n", "16", "--seeds", "0"],
    "bench_exhaustive": ["jiang", "--starts", "1", "--deviations", "1"],   # about 20 s
    "bench_check_run": ["--quick"],          # 20 robots for a minute in four formats: about 20 s
}

#: Arguments a benchmark needs even with ``--full`` (it has no default mode).
REQUIRED_ARGS: dict[str, list[str]] = {
    "bench_song2014": ["perf"],
    "bench_jiang": ["perf"],
    "bench_wang2020": ["perf"],
    "bench_wang2020_ratio": ["decompose", "--n", "144"],   # the ratio study's own instance (docs/wang2020.md)
    "bench_exhaustive": ["perf"],
}

#: Where each benchmark's figures are recorded (docs/performance.md sections).
FIGURES: dict[str, str] = {
    "bench_engine": 'docs/performance.md "Simulation engine and song2016" > "Engine alone"',
    "bench_engine_compare": 'docs/performance.md "Simulation engine and song2016" > "Engine loop split into phases '
                            '(issue 28)"',
    "bench_lattice_check": 'docs/performance.md "Lattice checker"',
    "bench_proofs": 'docs/performance.md "Proof suite"',
    "bench_song2014": 'docs/performance.md "song2014" (experiments: docs/song2014.md)',
    "bench_song2016": 'docs/performance.md "Simulation engine and song2016" > "song2016"',
    "bench_song2016_steps": 'docs/song2016.md "Where Table III\'s steps go" (issue 31)',
    "bench_mutations": 'docs/performance.md (mutation benchmark section) and docs/explorer.md',
    "bench_jiang": 'docs/performance.md "Jiang et al. (issue 16)" (experiments: docs/jiang.md)',
    "bench_wang2020": 'docs/performance.md "Wang & Rubenstein 2020 (issue 15)" (experiments: docs/wang2020.md)',
    "bench_wang2020_ratio": 'docs/wang2020.md (the distance-ratio study)',
    "bench_exhaustive": 'docs/performance.md "Exhaustive checking (issue 33)" (results: docs/exhaustive.md "Results")',
    "bench_check_run": 'docs/performance.md "Recorded runs (check-run)"',
}


def locate(folder: Path = HERE) -> dict[str, Path]:
    """Each benchmark's name (its file stem) and file: ``folder/bench_*.py`` and ``folder/*/bench_*.py``.

    >>> locate()["bench_song2016"].relative_to(HERE).as_posix()
    'song2016/bench_song2016.py'
    """
    found: dict[str, Path] = {}
    for p in sorted([*folder.glob("bench_*.py"), *folder.glob("*/bench_*.py")]):
        if p.stem in found:
            raise SystemExit(f"run_all: error: two benchmarks are named {p.stem!r}: {found[p.stem]} and {p}; "
                             "fix: rename one (benchmarks are named by file stem)")
        found[p.stem] = p
    return found


def discover(folder: Path = HERE) -> list[str]:
    """The benchmark names (file stems) in ``folder`` and its paper folders, sorted.

    >>> "bench_proofs" in discover() and "bench_jiang" in discover()
    True
    """
    return sorted(locate(folder))


def command(name: str, full: bool = False) -> list[str]:
    """The command line that runs benchmark ``name``.

    >>> command("bench_engine")[1:]
    ['benchmarks/bench_engine.py', '--quick']
    >>> command("bench_song2014", full=True)[1:]
    ['benchmarks/song2014/bench_song2014.py', 'perf']
    """
    args = REQUIRED_ARGS.get(name, []) if full else SMALL_ARGS.get(name, [])
    return [sys.executable, locate()[name].relative_to(HERE.parent).as_posix(), *args]


def _child_cpu() -> float:
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", action="append", metavar="NAME",
                    help="run only this benchmark (repeatable; 'proofs' or 'bench_proofs')")
    ap.add_argument("--full", action="store_true", help="each benchmark's own default settings (long)")
    ap.add_argument("--list", action="store_true", help="list the benchmarks and their commands")
    args = ap.parse_args(argv)

    names = discover()
    if args.only:
        wanted = [n if n.startswith("bench_") else f"bench_{n}" for n in args.only]
        unknown = [n for n in wanted if n not in names]
        if unknown:
            print(f"run_all: error: --only {unknown!r} is not a benchmark; fix: use some of {names!r}",
                  file=sys.stderr)
            return 2
        names = [n for n in names if n in wanted]
    if args.list:
        for n in names:
            print(f"{n}: {' '.join(command(n, args.full)[1:])}  -> {FIGURES.get(n, 'docs/performance.md')}")
        return 0

    root = HERE.parent
    env = dict(os.environ, MPLBACKEND=os.environ.get("MPLBACKEND", "Agg"))
    load0 = os.getloadavg()[0]
    print(f"# make bench: {len(names)} benchmarks in sequence, {'full' if args.full else 'small'} settings; "
          f"{os.cpu_count()}-core {platform.machine()}, Python {platform.python_version()}, "
          f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, "
          f"load average {load0:.2f} at start", flush=True)
    summary = []
    for n in names:
        cmd = command(n, args.full)
        print(f"\n## {n}: {' '.join(cmd[1:])}", flush=True)
        w0, c0 = time.perf_counter(), _child_cpu()
        rc = subprocess.run(cmd, cwd=root, env=env).returncode
        summary.append((n, rc, time.perf_counter() - w0, _child_cpu() - c0))
    print(f"\n# summary (load average {os.getloadavg()[0]:.2f} at the end; "
          "CPU = the benchmark process's user + system seconds)")
    for n, rc, wall, cpu in summary:
        status = f"exit {rc:<3}" if rc >= 0 else f"SIGNAL {-rc:<2}"  # killed from outside, e.g. -9
        print(f"{n:22} {status} wall {wall:7.1f} s  CPU {cpu:7.1f} s  figures: "
              f"{FIGURES.get(n, 'docs/performance.md (add a section)')}")
    print("Record figures by hand in docs/performance.md with the machine, the date and whether the "
          "machine was shared with other jobs; never in timed tests.")
    return 0 if all(rc == 0 for _, rc, _, _ in summary) else 1


if __name__ == "__main__":
    sys.exit(main())
