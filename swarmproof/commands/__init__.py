"""One module per subcommand: ``NAME``, ``HELP``, ``add_arguments(parser)``, ``run(args) -> int``.

Shared helpers for the modules live here.
"""

from __future__ import annotations

import sys
from typing import Any

from swarmproof.models.fileio import dumps_json
from swarmproof.models.interrupt import raise_if_interrupted


_EMITTED = [False]


def emit_json(obj: Any, *, error: bool = False) -> None:
    """Print one deterministic JSON document on stdout (and nothing else there).

    A report (not an ``error`` document) is refused once Ctrl-C was pressed: it could look
    complete (:mod:`swarmproof.models.interrupt`)."""
    if not error:
        raise_if_interrupted()
    text = dumps_json(obj)
    _EMITTED[0] = True
    sys.stdout.write(text)
    sys.stdout.flush()


def reset_json_emitted() -> None:
    """Forget an earlier command's JSON document (the CLI runs several commands in one process in tests)."""
    _EMITTED[0] = False


def json_emitted() -> bool:
    """Whether this process already printed its JSON document (an error after it adds none)."""
    return _EMITTED[0]


def human(args, *lines: str) -> None:
    """Print human-readable lines: stdout normally, stderr when ``--json`` is on."""
    from swarmproof.models.citations import readable

    raise_if_interrupted()   # after Ctrl-C no report is printed (it could look complete)
    stream = sys.stderr if getattr(args, "json", False) else sys.stdout
    for line in lines:
        print(readable(line), file=stream)   # "Song & O'Kane 2016, Lemma 11", not the seed key


def add_tree_link_mode(p) -> None:
    """``--tree-link-mode MODE`` (simulate and explore): which links of the spanning tree must
    survive each step (:data:`swarmproof.invariants.connectivity.TREE_LINK_MODES`)."""
    from swarmproof.invariants.connectivity import TREE_LINK_MODES

    p.add_argument("--tree-link-mode", choices=TREE_LINK_MODES, metavar="MODE",
                   help="which links of the spanning tree must survive each step: decided (default: every link of the "
                        "tree the step decided, newly chosen ones included), standing (links held before the step) "
                        "or persistent (links held before and after it: does not see a link that breaks in the "
                        "step it was chosen)")


class StatusLine:
    """One self-overwriting status line on stderr, ``PREFIX: text`` cut to the terminal's width
    (commands create it only when stderr is a terminal)."""

    def __init__(self, stream, prefix: str) -> None:
        import shutil

        self.stream = stream
        self.prefix = prefix
        self.width = max(20, shutil.get_terminal_size((80, 24)).columns - 1)

    def __call__(self, text: str) -> None:
        self.stream.write("\r\033[K" + f"{self.prefix}: {text}"[: self.width])
        self.stream.flush()

    def clear(self) -> None:
        self.stream.write("\r\033[K")
        self.stream.flush()
