"""Every output option of every command, checked in one place before any work.

:func:`swarmproof.cli.main` calls :func:`check_outputs` on the parsed command
line before it runs the command, so a long run never ends in an error about
where to write its result, and nothing is created for an option that is then
refused (``replay --gif /nonexistent/x.gif`` used to create ``/nonexistent/``).
A file option must name a file (not a folder) in a folder that exists and is
writable, with a suffix of the format the option writes (``--trace t.csv``
used to write JSON); a folder option (``--out``, ``--database``) must be a
folder or not exist yet (it is created), never a regular file.

The table is keyed by the option's ``dest``: an option with that ``dest`` is
an output in every command that has it (tests/cli/test_output_options.py
reads the parsers and checks each one).

Examples
--------
>>> import argparse
>>> check_outputs(argparse.Namespace(command="simulate", plot="run.txt"))
Traceback (most recent call last):
...
swarmproof.models.errors.UsageError: --plot='run.txt': the suffix '.txt' is not a format --plot writes; fix: end the name with .png (--plot writes a PNG image)
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from swarmproof.models.errors import UsageError

__all__ = ["OutputOption", "OUTPUT_OPTIONS", "check_output", "check_outputs"]


@dataclass(frozen=True)
class OutputOption:
    """What an output option writes: a ``file`` with one of ``suffixes``, or a ``folder``."""

    kind: str                         # "file" or "folder"
    suffixes: tuple[str, ...] = ()    # accepted suffixes (lower case) of a file
    writes: str = ""                  # what it writes, for the fix


#: ``dest`` -> what that output option writes, for every command that has it.
OUTPUT_OPTIONS: dict[str, OutputOption] = {
    "plot": OutputOption("file", (".png",), "a PNG image"),
    "gif": OutputOption("file", (".gif",), "an animated GIF"),
    "trace": OutputOption("file", (".json", ".npz"), "the trace as JSON, or as NPZ for .npz"),
    "junit": OutputOption("file", (".xml",), "JUnit XML"),
    "html": OutputOption("file", (".html", ".htm"), "one HTML page"),
    "markdown": OutputOption("file", (".md", ".markdown"), "a Markdown table"),
    "out": OutputOption("folder", (), "a folder of result files"),
    "database": OutputOption("folder", (), "Hypothesis's example database, a folder"),
    # a recorded-run log (docs/recorded-runs.md): a .csv or .mcap file, or a new rosbag2 bag's folder
    "export": OutputOption("log", (".csv", ".mcap"), "a .csv or .mcap log, or a rosbag2 bag (a new folder)"),
    "to": OutputOption("log", (".csv", ".mcap"), "a .csv or .mcap log, or a rosbag2 bag (a new folder)"),
}


def _option_name(dest: str) -> str:
    return "--" + dest.replace("_", "-")


def check_output(dest: str, value, option: str | None = None) -> str:
    """Check one output option's value (see the module docstring); return it as a string."""
    from swarmproof.models.fileio import check_output_dir, check_output_path

    spec = OUTPUT_OPTIONS[dest]
    option = option or _option_name(dest)
    if spec.kind == "folder":
        return check_output_dir(value, option)
    if spec.kind == "log":
        from swarmproof.models.recorded_io import export_format

        try:
            fmt = export_format(value)
        except UsageError as exc:
            text = exc.message if exc.message.startswith(f"{option}=") else \
                f"{option}={value!r}: {exc.message.split(': ', 1)[-1]}"
            raise UsageError(text, fix=exc.fix) from None
        if fmt != "rosbag2":
            return check_output_path(value, option)
        parent = os.path.dirname(os.path.abspath(value))
        if not os.path.isdir(parent) or not os.access(parent, os.W_OK):
            raise UsageError(f"{option}={value!r}: the folder {parent!r} " +
                             ("does not exist" if not os.path.isdir(parent) else "is not writable"),
                             fix="create the folder first, or write the bag elsewhere")
        return os.fspath(value)
    text = check_output_path(value, option)
    suffix = os.path.splitext(text)[1].lower()
    if suffix not in spec.suffixes:
        said = f"the suffix {suffix!r} is not a format {option} writes" if suffix else "the name has no suffix"
        raise UsageError(f"{option}={text!r}: {said}",
                         fix=f"end the name with {' or '.join(spec.suffixes)} ({option} writes {spec.writes})")
    return text


def check_outputs(args) -> None:
    """Check every output option given on the parsed command line ``args`` (before any work)."""
    for dest in OUTPUT_OPTIONS:
        value = getattr(args, dest, None)
        if value is not None:
            check_output(dest, value)
