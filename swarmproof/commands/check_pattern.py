"""``swarmproof check-pattern FILE [--copies N] [--json] [--plot PNG]`` and ``check-pattern --list``.

Checks a repeating pattern (a ``repeating-pattern/1`` file, a bundled name or
``lattice:NAME`` for a one-role bundled lattice) of Jiang et al. (002): the
file is well-formed (B's points distinct, the first at the origin, Def. 3;
A's vectors distinct, Def. 7), and N copies of B assembled by A (layer by
layer from the origin, as Algorithm 2 grows its formation) put no two points
on one place and have formation quality 1 (Def. 9), computed exactly.

Exit codes (DESIGN.md section 2): 0 the pattern is sound, 1 the assembled
copies overlap, 2 a bad file or option (file, line, field and fix),
3 inconclusive.
"""

from __future__ import annotations

import argparse

NAME = "check-pattern"
HELP = "check a repeating pattern (002 Defs. 3, 7, 9): well-formed, assembles without overlap"
DESCRIPTION = __doc__.split("\n\n", 1)[1] if __doc__ else HELP


def _copies(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--copies={text!r} is not an integer") from None
    if not 1 <= n <= 10_000:
        raise argparse.ArgumentTypeError(f"--copies={text!r} must be in 1..10000")
    return n


def add_arguments(p) -> None:
    p.add_argument("file", metavar="FILE", nargs="?",
                   help="a repeating-pattern/1 file (YAML or JSON), a bundled name, or lattice:NAME")
    p.add_argument("--list", action="store_true", help="print the bundled pattern names, one a line, and exit")
    p.add_argument("--copies", type=_copies, default=64, metavar="N",
                   help="copies of B to assemble for the overlap check (default 64)")
    p.add_argument("--json", action="store_true", help="print one JSON document on stdout and nothing else there")
    p.add_argument("--plot", metavar="PNG", default=None,
                   help="draw the assembled copies (an overlap in red) to PNG")


def run(args) -> int:
    from swarmproof.commands import emit_json, human
    from swarmproof.models.errors import UsageError
    from swarmproof.models.repeating_pattern import check_pattern, pattern_names, resolve_pattern

    if args.list:
        if args.file is not None:
            raise UsageError(f"--list takes no name (got FILE={args.file!r})",
                             fix=f"run `swarmproof check-pattern --list` for the names, or "
                                 f"`swarmproof check-pattern {args.file}` to check that pattern")
        if args.json:
            emit_json({"patterns": pattern_names()})
        else:
            print("\n".join(pattern_names()))
        return 0
    if args.file is None:
        raise UsageError("check-pattern needs FILE (or --list)",
                         fix="e.g. swarmproof check-pattern rhombus-triangles; --list names the bundled ones")
    if args.plot is not None:
        from swarmproof.models.fileio import check_output_path

        check_output_path(args.plot, "--plot")
    pattern = resolve_pattern(args.file)
    result = check_pattern(pattern, args.copies)
    if args.plot is not None:
        from swarmproof.checkers.plotting import plot_pattern_check

        plot_pattern_check(result, args.plot)
    if args.json:
        emit_json(result.to_json())
    else:
        q = result.quality or {}
        human(args, f"pattern {pattern.name!r}: {len(pattern.basic)} point(s) in B, "
                    f"{len(pattern.assembling)} vector(s) in A, tol {pattern.tol:.3g}",
              f"{result.status.upper()}: {result.message}",
              *([f"  epsilon {q.get('epsilon_exact')} (gamma {q.get('basic_fulfillment_exact')}, delta "
                 f"{q.get('assembling_fulfillment_exact')}; method {q.get('method')})"] if q else []),
              f"  cites: {pattern.cites}")
    from swarmproof.models.verdict import Verdict

    return Verdict(result.status).exit_code
