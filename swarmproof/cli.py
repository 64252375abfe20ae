"""The ``swarmproof`` command line (DESIGN.md section 2).

Each subcommand lives in its own module of :mod:`swarmproof.commands` with
``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.

Exit codes, for every subcommand: 0 all requested checks hold, 1 a defect,
violation or counterexample was found, 2 usage error or unreadable input,
3 inconclusive, 4 internal error (a bug in swarmproof: one line on stderr
naming the file with the traceback), 130 stopped by Ctrl-C (no report
written).  ``--json`` prints one JSON document on stdout and nothing else
there; human text and progress go to stderr in that mode.

User mistakes (any :class:`~swarmproof.models.errors.UsageError`, or an
``OSError`` on a file the user named) become a one-paragraph message on
stderr and exit code 2, never a traceback; with ``--json`` also a JSON error
document ``{"command", "error": {"kind", "message"}, "exit_code"}`` on stdout.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from typing import Sequence

from swarmproof.models.citations import readable
from swarmproof.models.errors import ProtocolError, UsageError
from swarmproof.models.interrupt import EXIT_INTERRUPTED
from swarmproof.models.verdict import EXIT_INTERNAL, EXIT_USAGE

#: Subcommand modules, in the order ``--help`` lists them.
COMMAND_MODULES: tuple[str, ...] = (
    "check_lattice",
    "check_pattern",
    "simulate",
    "prove",
    "verify",
    "campaign",
    "explore",
    "replay",
    "check_run",
    "export",
    "list",
)


class _Parser(argparse.ArgumentParser):
    """argparse that exits 2 with a fix hint, as every usage error does."""

    #: Set by :func:`main` when the command line asks for ``--json``: argparse's own
    #: errors then print a JSON error document on stdout too.
    json_errors = False

    def error(self, message: str):  # pragma: no cover - exercised via CLI tests
        unknown = _unknown_command(message)
        if unknown is not None:        # `swarmproof simualte`: the closest command, not the usage
            message = unknown
        else:
            message = _closest_choice(message)
            self.print_usage(sys.stderr)
        if _Parser.json_errors:
            from swarmproof.commands import emit_json

            command = self.prog.split(" ", 1)[1] if " " in self.prog else None
            emit_json(_error_document(command, "usage", f"{message}; fix: see `{self.prog} --help`",
                                      EXIT_USAGE), error=True)
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}; fix: see `{self.prog} --help`\n")

    def format_help(self) -> str:
        return readable(super().format_help())   # --help cites papers by name too


def _unknown_command(message: str) -> str | None:
    """argparse's "invalid choice" of the subcommand as ``unknown command 'X'; did you mean 'Y'?``
    (None for any other message).

    >>> _unknown_command("argument COMMAND: invalid choice: 'simualte' (choose from 'simulate', 'prove')")
    "unknown command 'simualte'; did you mean 'simulate'?"
    """
    import re

    from swarmproof.models.errors import did_you_mean

    m = re.match(r"argument COMMAND: invalid choice: '(.*?)' \(choose from (.*)\)$", message)
    if m is None:
        return None
    choices = re.findall(r"'([^']*)'", m.group(2)) or [c.strip() for c in m.group(2).split(",")]
    hint = did_you_mean(m.group(1), choices) or f" (commands: {', '.join(choices)})"
    return f"unknown command {m.group(1)!r}{hint}"


def _closest_choice(message: str) -> str:
    """argparse's "invalid choice" of an option (``--section lemma``) with the closest choice
    appended (``; did you mean 'lemmas'?``); any other message unchanged.

    >>> _closest_choice("argument --section: invalid choice: 'lemma' (choose from 'lattices', 'lemmas')")
    "argument --section: invalid choice: 'lemma' (choose from 'lattices', 'lemmas'); did you mean 'lemmas'?"
    """
    import re

    from swarmproof.models.errors import did_you_mean

    m = re.match(r"argument .*: invalid choice: '(.*?)' \(choose from (.*)\)$", message)
    if m is None:
        return message
    return message + did_you_mean(m.group(1), re.findall(r"'([^']*)'", m.group(2)))


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


def _error_document(command: str | None, kind: str, message: str, exit_code: int, **extra) -> dict:
    """The JSON document ``--json`` prints on stdout for an error (exit 2 or 4)."""
    return {"command": command, "error": {"kind": kind, "message": message, **extra},
            "exit_code": exit_code}


def _write_traceback(command: str | None) -> str | None:
    """Write the current exception's traceback to a new file; its path, or None if that fails."""
    import os
    import tempfile
    import traceback

    from swarmproof import __version__

    try:
        fd, path = tempfile.mkstemp(prefix=f"swarmproof-{command or 'cli'}-crash-", suffix=".txt")
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(f"swarmproof {__version__}, command: {' '.join(sys.argv)}\n")
            traceback.print_exc(file=fh)
        return path
    except OSError:  # pragma: no cover - no writable temporary folder
        return None


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script; returns the exit code.

    One rule for every subcommand (docs/README.md, "Exit codes"): a user's
    mistake (:class:`~swarmproof.models.errors.UsageError`, or an ``OSError``
    reading or writing a file the user named) exits 2 with the cause and the
    fix; anything else is swarmproof's own bug and exits 4 with one line
    naming the file that holds the traceback.  With ``--json`` the error is
    also a JSON document on stdout.  No traceback reaches the terminal.
    """
    from swarmproof.commands import reset_json_emitted

    argv = list(sys.argv[1:] if argv is None else argv)
    _Parser.json_errors = "--json" in argv
    reset_json_emitted()
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: --help / --version (0) or a usage error (2), already printed
        return int(exc.code or 0) if not isinstance(exc.code, str) else EXIT_USAGE
    as_json = bool(getattr(args, "json", False))
    try:
        return _run_until_interrupted(args)
    except UsageError as exc:
        print(f"swarmproof {args.command}: error: {readable(str(exc))}", file=sys.stderr)
        if as_json:
            _emit_error(_error_document(args.command, "usage", str(exc), EXIT_USAGE))
        return EXIT_USAGE
    except ProtocolError as exc:
        # the algorithm broke the protocol (a malformed command, an unhashable state): the
        # user's contract error, not a crash of the algorithm nor swarmproof's bug
        msg = (f"the algorithm broke the protocol: {exc}; fix: follow swarmproof.reference_impl.protocol "
               "(a Command from step(), a hashable state(); docs/engine.md)")
        print(f"swarmproof {args.command}: error: {msg}", file=sys.stderr)
        if as_json:
            _emit_error(_error_document(args.command, "usage", msg, EXIT_USAGE))
        return EXIT_USAGE
    except KeyboardInterrupt:
        # Ctrl-C: stop at once, exit 130, no report that looks complete (nothing is printed or
        # written once it was pressed: swarmproof.models.interrupt)
        msg = "interrupted (Ctrl-C); no report was written"
        print(f"swarmproof {args.command}: {msg}", file=sys.stderr)
        if as_json:
            _emit_error(_error_document(args.command, "interrupted", msg, EXIT_INTERRUPTED))
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # e.g. `swarmproof ... | head`
        return 0
    except (MemoryError, RecursionError) as exc:
        msg = (f"{type(exc).__name__}: the input is too large for this machine; fix: use a smaller "
               "input, a smaller budget or fewer robots")
        path = _write_traceback(args.command)
        where = f" (traceback: {path})" if path else ""
        print(f"swarmproof {args.command}: internal error: {msg}{where}", file=sys.stderr)
        if as_json:
            _emit_error(_error_document(args.command, "internal", msg, EXIT_INTERNAL, traceback=path))
        return EXIT_INTERNAL
    except OSError as exc:
        name = getattr(exc, "filename", None)
        msg = (f"{type(exc).__name__}: {exc.strerror or exc}" + (f": path={name!r}" if name else "") +
               "; fix: check the path, its permissions and the free disk space")
        print(f"swarmproof {args.command}: error: {msg}", file=sys.stderr)
        if as_json:
            _emit_error(_error_document(args.command, "usage", msg, EXIT_USAGE))
        return EXIT_USAGE
    except Exception as exc:  # noqa: BLE001 - swarmproof's own bug: exit 4, never a traceback
        path = _write_traceback(args.command)
        where = f"the traceback is in {path}" if path else "no traceback file could be written"
        text = str(exc).splitlines()[0][:200] if str(exc) else ""
        msg = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
        print(f"swarmproof {args.command}: internal error (a bug in swarmproof, please report it): "
              f"{msg}; {where}", file=sys.stderr)
        if as_json:
            _emit_error(_error_document(args.command, "internal", msg, EXIT_INTERNAL, traceback=path))
        return EXIT_INTERNAL


def _run_until_interrupted(args) -> int:
    """Run the command with the Ctrl-C handler installed; a Ctrl-C that a library swallowed, or
    turned into another error, still ends the command as ``KeyboardInterrupt`` (exit 130)."""
    from swarmproof.commands.outputs import check_outputs
    from swarmproof.models.interrupt import installed, interrupted, raise_if_interrupted

    check_outputs(args)   # every output option of every command, before any work
    with installed():
        try:
            code = int(args._run(args))
        except KeyboardInterrupt:
            raise
        except BaseException:
            if interrupted():
                raise KeyboardInterrupt from None
            raise
        raise_if_interrupted()
        return code


def _emit_error(doc: dict) -> None:
    """Print the error document unless the command already printed its JSON."""
    from swarmproof.commands import emit_json, json_emitted

    if not json_emitted():
        emit_json(doc, error=True)


def run_main() -> None:  # pragma: no cover
    """The old console-script target; :mod:`swarmproof.entry` is the one installed now (it handles a
    Ctrl-C while this module loads)."""
    sys.exit(main())


if __name__ == "__main__":  # pragma: no cover
    run_main()
