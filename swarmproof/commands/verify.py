"""``swarmproof verify``: the main job, every check over the bundled library as one property matrix."""

from __future__ import annotations

import sys

from swarmproof.commands import emit_json, human

NAME = "verify"
HELP = "run every check over the bundled library and print the property matrix"
DESCRIPTION = (HELP + ". Exit 0 when every row holds or is proved, 1 when a row is violated, "
               "3 when a row is inconclusive.")


def add_arguments(p) -> None:
    from swarmproof.checkers.report import SECTIONS

    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    p.add_argument("--section", action="append", choices=sorted(SECTIONS), metavar="NAME",
                   help=f"run only this section (repeatable): {', '.join(SECTIONS)}")


def run(args) -> int:
    from swarmproof.checkers.report import run_report

    def progress(name: str) -> None:
        if sys.stderr.isatty():
            print(f"verify: running {name} ...", file=sys.stderr, flush=True)

    report = run_report(args.section, progress=progress)
    if args.json:
        emit_json(report.to_json())
    else:
        human(args, report.format_table())
    return report.exit_code
