"""``swarmproof verify``: the main job, every check over the bundled library as one property matrix.

Sections (:mod:`swarmproof.checkers.report`): ``lattices`` (the lattice-graph
checker on every bundled lattice), ``algorithms`` (seeded runs of each
reference implementation with its claims checked), ``lemmas`` (the z3 proof
suite) and ``exploration`` (the Hypothesis explorer, algorithm by property).

Exit codes (DESIGN.md section 2): 0 every claimed row proved or held, 1 a
claimed row violated, 2 usage error, 3 a claimed row inconclusive (and none
violated).  Rows of properties the paper does not claim are findings, marked
``*`` and not counted.  ``--json`` prints one document, bit-identical from run
to run (no wall-clock figures); progress goes to stderr, only on a terminal.
"""

from __future__ import annotations

import shutil
import sys

from swarmproof.commands import emit_json, human
from swarmproof.models.errors import UsageError

NAME = "verify"
HELP = "run every check over the bundled library and print the property matrix"
DESCRIPTION = (HELP + ": lattices, algorithm runs, the z3 lemmas and the explorer's rows. "
               "Exit 0 when every claimed row holds or is proved, 1 when a claimed row is violated, "
               "3 when a claimed row is inconclusive; rows marked * (not claimed by the paper) are "
               "findings and do not count.")


def add_arguments(p) -> None:
    from swarmproof.checkers import report

    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    p.add_argument("--section", action="append", choices=list(report.SECTIONS), metavar="NAME",
                   help=f"run only this section (repeatable): {', '.join(report.SECTIONS)}")
    p.add_argument("--out", metavar="DIR",
                   help="write the counterexamples of violated exploration and algorithm rows as "
                        "swarmproof-counterexample/1 files into DIR (default: none written; each violated "
                        "row names the command that repeats it)")
    p.add_argument("--max-examples", type=int, default=report.VERIFY_EXPLORE_MAX_EXAMPLES, metavar="N",
                   help="exploration: Hypothesis examples per algorithm and property "
                        f"(default {report.VERIFY_EXPLORE_MAX_EXAMPLES})")
    p.add_argument("--robots", default="{}..{}".format(*report.VERIFY_EXPLORE_ROBOTS), metavar="MIN..MAX",
                   help="exploration: number of robots (default {}..{})".format(*report.VERIFY_EXPLORE_ROBOTS))
    p.add_argument("--seed", type=int, default=report.VERIFY_EXPLORE_SEED, metavar="S",
                   help=f"exploration: Hypothesis seed (default {report.VERIFY_EXPLORE_SEED})")


class _TtyProgress:
    """One self-overwriting status line on stderr (only used when stderr is a terminal)."""

    def __init__(self, stream) -> None:
        self.stream = stream
        self.width = max(20, shutil.get_terminal_size((80, 24)).columns - 1)

    def __call__(self, text: str) -> None:
        self.stream.write("\r\033[K" + f"verify: {text}"[: self.width])
        self.stream.flush()

    def clear(self) -> None:
        self.stream.write("\r\033[K")
        self.stream.flush()


def run(args) -> int:
    from swarmproof.checkers.report import run_report
    from swarmproof.commands.explore import parse_robots

    if args.max_examples < 1:
        raise UsageError(f"--max-examples {args.max_examples!r} must be >= 1", fix="e.g. --max-examples 200")
    if args.seed < 0:
        raise UsageError(f"--seed {args.seed!r} must be >= 0", fix="e.g. --seed 0")
    if args.out is not None:
        from swarmproof.models.fileio import check_output_dir

        check_output_dir(args.out, "--out")
    explore_opts = {"max_examples": args.max_examples, "robots": parse_robots(args.robots),
                    "seed": args.seed, "out_dir": args.out}
    progress = _TtyProgress(sys.stderr) if sys.stderr.isatty() else None
    try:
        report = run_report(args.section, progress=progress,
                            options={"exploration": explore_opts, "algorithms": {"out_dir": args.out}})
    finally:
        if progress is not None:
            progress.clear()
    if args.json:
        emit_json(report.to_json())
    else:
        human(args, report.format_table())
    return report.exit_code
