"""``swarmproof verify``: the main job, every check over the bundled library as one property matrix.

Sections (:mod:`swarmproof.checkers.report`): ``lattices`` (the lattice-graph
checker on every bundled lattice), ``algorithms`` (seeded runs of each
reference implementation with its claims checked), ``lemmas`` (the z3 proof
suite) and ``exploration`` (the Hypothesis explorer, algorithm by property).
``--algorithm REF`` (repeatable) verifies just those algorithms -- a registry
name or ``module:qualname`` of a user's class, with its own claims, plan and
scenarios -- in the ``algorithms`` and ``exploration`` sections.

Exit codes (DESIGN.md section 2): without a baseline, 0 every claimed row
proved or held, 1 a claimed row violated, 3 a claimed row inconclusive (and
none violated); rows of properties the paper does not claim are findings,
marked ``*`` and not counted; rows marked ``n/a`` (the algorithm cannot give what the property
needs: no range graph, no parent field, ...) have no verdict, are counted apart and never run.  With ``--baseline FILE``
(:mod:`swarmproof.checkers.baseline`): 0 every row as the baseline says or
better, 1 a regression (or a new claimed violation, or a new kind of failure
in a known-violated row), 3 a row inconclusive; improvements fail only with
``--strict``.  2 usage error or unreadable input.  ``--json`` prints one
document, bit-identical from run to run (no wall-clock figures); progress goes
to stderr, only on a terminal.  ``--junit``, ``--markdown`` and ``--html``
write the matrix for CI systems (:mod:`swarmproof.checkers.ci_outputs`).
"""

from __future__ import annotations

import sys

from swarmproof.commands import StatusLine, emit_json, human

NAME = "verify"
HELP = "run every check over the bundled library (or your algorithms) and print the property matrix"
DESCRIPTION = (HELP + ": lattices, algorithm runs, the z3 lemmas and the explorer's rows. "
               "Exit 0 when every claimed row holds or is proved, 1 when a claimed row is violated, "
               "3 when a claimed row is inconclusive; rows marked * (not claimed) are "
               "findings and do not count; rows marked n/a (not applicable) have no verdict. With --baseline FILE: 0 as the baseline says or better, "
               "1 a regression, 3 a row inconclusive (improvements fail only with --strict).")


def _workers(text: str) -> int:
    """``--workers N|auto``: a count >= 1, or the number of cores."""
    import argparse
    import os

    if text == "auto":
        return os.cpu_count() or 1
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--workers {text!r} is not a whole number or auto (e.g. --workers 2)") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"--workers {n!r} must be >= 1 (e.g. --workers 2, or auto)")
    return n


def add_arguments(p) -> None:
    from swarmproof.checkers import report

    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    p.add_argument("--section", action="append", choices=list(report.SECTIONS), metavar="NAME",
                   help=f"run only this section (repeatable): {', '.join(report.SECTIONS)} (default: all; "
                        "with --algorithm: algorithms and exploration)")
    p.add_argument("--algorithm", action="append", metavar="REF", dest="algorithms",
                   help="verify just this algorithm (repeatable): a registry name or module:qualname of your "
                        "class, with its own claims, verify plan and scenarios")
    p.add_argument("--recorded", action="append", metavar="FOLDER", default=None,
                   help="judge the recorded runs of FOLDER (its recorded-runs.yaml; repeatable) in the recorded "
                        "section instead of the bundled ones (docs/recorded-runs.md)")
    p.add_argument("--property", action="append", metavar="NAME", dest="properties",
                   help="only this property in the algorithms and exploration rows (repeatable)")
    p.add_argument("--baseline", metavar="FILE",
                   help="compare every row with this baseline of expected verdicts (swarmproof-baseline/1): "
                        "exit 0 as the baseline says or better, 1 a regression, 3 a row inconclusive")
    p.add_argument("--update-baseline", action="store_true",
                   help="write this run's verdicts into the --baseline FILE (atomically; rows outside this "
                        "run's sections, algorithms and properties are kept)")
    p.add_argument("--strict", action="store_true",
                   help="with --baseline: an improvement or another counterexample size fails (exit 1), and a "
                        "baseline row this run no longer produces is an error (exit 2)")
    p.add_argument("--junit", metavar="FILE", help="write the matrix as JUnit XML (one test case per row)")
    p.add_argument("--markdown", metavar="FILE", help="write a Markdown summary table (for a CI job page)")
    p.add_argument("--html", metavar="FILE",
                   help="write one self-contained HTML report: the matrix, and each violated row's "
                        "counterexample steps, picture and animation")
    p.add_argument("--out", metavar="DIR",
                   help="write the counterexamples of violated exploration and algorithm rows as "
                        "swarmproof-counterexample/1 files into DIR (default: none written; each violated "
                        "row names the command that repeats it)")
    p.add_argument("--max-examples", type=int, default=None, metavar="N",
                   help="exploration: Hypothesis examples per algorithm and property "
                        f"(default: the baseline's gate, else {report.VERIFY_EXPLORE_MAX_EXAMPLES})")
    p.add_argument("--robots", default=None, metavar="MIN..MAX",
                   help="exploration: number of robots (default: the baseline's gate, else {}..{})".format(
                       *report.VERIFY_EXPLORE_ROBOTS))
    p.add_argument("--workers", default=None, metavar="N|auto", type=_workers,
                   help="exploration: run the rows on N local processes (Dask, as campaigns do; auto: one per "
                        "core): the same rows, sooner (default: 1, in this process)")
    p.add_argument("--seed", type=int, default=None, metavar="S",
                   help=f"exploration: Hypothesis seed (default: the baseline's gate, else {report.VERIFY_EXPLORE_SEED})")


def run(args) -> int:
    from swarmproof.checkers.gate import check_gone, verify
    from swarmproof.commands.explore import parse_robots
    from swarmproof.models.fileio import check_output_path

    for opt in ("junit", "markdown", "html"):
        if getattr(args, opt) is not None:
            check_output_path(getattr(args, opt), f"--{opt}")
    progress = StatusLine(sys.stderr, "verify") if sys.stderr.isatty() else None
    try:
        report = verify(algorithms=args.algorithms, sections=args.section, properties=args.properties,
                        baseline=args.baseline, update_baseline=args.update_baseline, strict=args.strict,
                        max_examples=args.max_examples, seed=args.seed,
                        robots=None if args.robots is None else parse_robots(args.robots),
                        out_dir=args.out, progress=progress, workers=args.workers, recorded=args.recorded)
    finally:
        if progress is not None:
            progress.clear()
    from swarmproof.checkers import ci_outputs

    if args.junit is not None:
        ci_outputs.write_junit(report, args.junit)
    if args.markdown is not None:
        ci_outputs.write_markdown(report, args.markdown)
    if args.html is not None:
        from swarmproof.checkers.html_report import write_html

        write_html(report, args.html)
    if args.json:
        emit_json(report.to_json())
    else:
        human(args, report.format_table())
    if report.updated:
        human(args, report.updated)
    check_gone(report, args.strict, args.baseline)
    return report.exit_code
