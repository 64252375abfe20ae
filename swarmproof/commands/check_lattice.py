"""``swarmproof check-lattice FILE [--range PHI] [--json] [--plot PNG]``.

Checks a lattice graph (a ``lattice-graph/1`` file or a bundled library name)
against Definitions 1 and 4 of 001 (Song & O'Kane, IROS 2016, Sec. III-B)
with :func:`swarmproof.checkers.lattice_check.check_lattice`.

Exit codes (DESIGN.md section 2): 0 valid and self-consistent, 1 a defect,
2 usage error or unreadable input, 3 inconclusive.
"""

from __future__ import annotations

import argparse

NAME = "check-lattice"
HELP = "check a lattice graph: well-formed (001 Def. 1) and self-consistent (001 Def. 4)"
DESCRIPTION = (
    "Check a lattice graph file (or a bundled lattice name) for the range PHI: strongly "
    "connected, inverse edges, no zero-length or duplicate edges, every edge shorter than PHI "
    "(001 Def. 1), and self-consistency (001 Def. 4), decided completely. Exit 0 valid, "
    "1 a defect, 2 usage error, 3 inconclusive."
)


def _positive_float(name: str):
    """An argparse type for option ``name``: a finite number > 0, errors naming the option."""
    def parse(text: str) -> float:
        try:
            x = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}={text!r} is not a number") from None
        if not (x > 0 and x != float("inf")):
            raise argparse.ArgumentTypeError(f"{name}={text!r} must be a finite number > 0")
        return x
    parse.__name__ = name
    return parse


def _progress():
    """A progress line on stderr while a check runs, only when stderr is a terminal (the line
    is erased when the check ends; redirected output never sees it)."""
    import sys
    import time

    stream = sys.stderr
    try:
        tty = stream.isatty()
    except (AttributeError, ValueError):
        tty = False
    if not tty:
        return lambda text: None
    start = time.monotonic()

    def show(text) -> None:
        if text is None:
            stream.write("\r\033[K")
        else:
            stream.write(f"\r\033[Kcheck-lattice: {text} ({time.monotonic() - start:.0f} s)"[:200])
        stream.flush()
    return show


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("file", metavar="FILE",
                        help="a lattice-graph/1 file (YAML or JSON) or a bundled lattice name")
    parser.add_argument("--range", dest="range", type=_positive_float("--range"), default=None, metavar="PHI",
                        help="sensing range phi; overrides the file's `range:`")
    parser.add_argument("--json", action="store_true",
                        help="print one JSON document on stdout and nothing else there")
    parser.add_argument("--plot", metavar="PNG", default=None,
                        help="draw the unrolled pattern with any defect highlighted to PNG")
    parser.add_argument("--pos-tol", dest="pos_tol", type=_positive_float("--pos-tol"), default=None,
                        metavar="TOL", help="position tolerance (default 1e-7 x longest edge)")
    parser.add_argument("--ang-tol", dest="ang_tol", type=_positive_float("--ang-tol"), default=None,
                        metavar="RAD", help="angle tolerance in radians (default 1e-7)")


def run(args) -> int:
    # Lazy imports: the CLI must start even while optional parts are absent.
    from swarmproof.checkers.lattice_check import check_lattice, plot_lattice_check
    from swarmproof.commands import emit_json, human
    from swarmproof.models import library

    if args.plot is not None:
        from swarmproof.models.fileio import check_output_path

        check_output_path(args.plot, "--plot")
    show = _progress()
    show(f"reading {args.file}")
    graph = library.resolve(args.file)
    try:
        report = check_lattice(graph, args.range, pos_tol=args.pos_tol, ang_tol=args.ang_tol,
                               progress=lambda phase: show(f"{len(graph.roles)} roles, {len(graph.edges)} "
                                                           f"edges: {phase}"))
    finally:
        show(None)
    report.angle_unit = getattr(graph, "angle_unit", "deg")   # read with the file, once
    if args.plot is not None:
        plot_lattice_check(graph, report, args.plot)
    if args.json:
        emit_json(report.to_json())
    else:
        human(args, *report.format_human().splitlines())
    return report.verdict.exit_code
