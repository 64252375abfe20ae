"""The ``swarmproof`` command line (DESIGN.md section 2).

Each subcommand lives in its own module of :mod:`swarmproof.commands` with
``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.

Exit codes, for every subcommand: 0 all requested checks hold, 1 a defect,
violation or counterexample was found, 2 usage error or unreadable input,
3 inconclusive.  ``--json`` prints one JSON document on stdout and nothing
else there; human text and progress go to stderr in that mode.

User mistakes (any :class:`~swarmproof.models.errors.UsageError`) become a
one-paragraph message on stderr and exit code 2, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from typing import Sequence

from swarmproof.models.errors import UsageError
from swarmproof.models.verdict import EXIT_USAGE

#: Subcommand modules, in the order ``--help`` lists them.
COMMAND_MODULES: tuple[str, ...] = (
    "check_lattice",
    "simulate",
    "prove",
    "verify",
    "explore",
    "replay",
)


class _Parser(argparse.ArgumentParser):
    """argparse that exits 2 with a fix hint, as every usage error does."""

    def error(self, message: str):  # pragma: no cover - exercised via CLI tests
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}; fix: see `{self.prog} --help`\n")


def build_parser() -> argparse.ArgumentParser:
    from swarmproof import __version__

    parser = _Parser(prog="swarmproof",
                     description="Machine-check the claims of multi-robot formation algorithms.")
    parser.add_argument("--version", action="version", version=f"swarmproof {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for modname in COMMAND_MODULES:
        mod = importlib.import_module(f"swarmproof.commands.{modname}")
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=getattr(mod, "DESCRIPTION", mod.HELP))
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args._run(args))
    except UsageError as exc:
        print(f"swarmproof {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(f"swarmproof {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `swarmproof ... | head`
        return 0


def run_main() -> None:  # pragma: no cover
    sys.exit(main())


if __name__ == "__main__":  # pragma: no cover
    run_main()
