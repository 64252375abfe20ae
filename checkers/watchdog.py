"""A time limit that holds against the algorithm under test.

The engine calls the algorithm's own code (``step``, ``state``, ``finished``)
and waits for it: a ``step`` that never returns would hang ``explore
--budget 5`` for ever.  :func:`time_limit` arms a wall-clock timer
(``signal.setitimer``, SIGALRM) around a run on the main thread; when the
limit passes, the handler raises :class:`Overstayed` inside whatever Python
code is running -- the algorithm's loop included -- and names where it was.
:class:`Overstayed` is a ``BaseException``, so neither the engine (which
turns the algorithm's ``Exception`` into a ``no_crash`` finding) nor an
algorithm's ``except Exception`` takes it; an algorithm that swallows even
that is interrupted again every :data:`REPEAT_S` seconds.

Limits (docs/explorer.md): the timer needs the main thread of a POSIX
process (elsewhere :func:`time_limit` sets no limit: :func:`supported`); a
``step`` blocked inside C code that never returns to Python (a C extension
looping for ever) is interrupted only when it does.

Examples
--------
>>> import time
>>> try:
...     with time_limit(0.05):
...         while True:
...             time.sleep(0.001)
... except Overstayed as exc:
...     print(exc.seconds)
0.05
>>> with time_limit(None):     # no limit
...     pass
"""

from __future__ import annotations

import functools
import os
import signal
import threading
import time
from contextlib import contextmanager

__all__ = ["MAX_LIMIT_S", "Overstayed", "REPEAT_S", "supported", "time_limit"]

#: Once the limit has passed, the timer fires again this often until the run gives up.
REPEAT_S = 0.25

#: The longest wall-clock limit the watchdog arms (seconds, about 115 days): the system timer
#: overflows far above it (1e10 s: "timestamp out of range for platform time_t").  A longer
#: ``--budget`` or ``--timeout`` is refused by the commands; "no limit" is ``none``/leaving it out.
MAX_LIMIT_S = 1e7


class Overstayed(BaseException):
    """The run did not return within ``seconds``; ``where`` names the code it was in."""

    def __init__(self, seconds: float, where: str) -> None:
        super().__init__(f"did not return within {seconds:g} s (it was in {where})")
        self.seconds = seconds
        self.where = where


def supported() -> bool:
    """Whether :func:`time_limit` can set a limit here (POSIX, main thread)."""
    return hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()


@functools.lru_cache(maxsize=1)
def _own_folders() -> tuple[str, ...]:
    """swarmproof's shared folders (the engine, checkers, invariants, models) and Python's own:
    code there is not the algorithm under test."""
    import sys
    import sysconfig

    import swarmproof.invariants as invariants
    import swarmproof.models as models
    import swarmproof.reference_impl.engine as engine

    facade = sys.modules["swarmproof"]     # the parent package of this one (no upward import)
    own = [os.path.dirname(os.path.abspath(m.__file__)) for m in (facade, invariants, models, engine)]
    own.append(os.path.dirname(os.path.abspath(__file__)))     # checkers/
    for key in ("stdlib", "platstdlib", "purelib", "platlib"):
        path = sysconfig.get_paths().get(key)
        if path:
            own.append(os.path.abspath(path))
    return tuple(p + os.sep for p in own)


def _where(frame, own: tuple[str, ...]) -> str:
    """The innermost frame outside ``own`` folders (swarmproof's shared code and Python's libraries:
    the algorithm's code, as ``module.qualname (file:line)``), else the innermost frame."""
    first = frame
    while frame is not None:
        path = os.path.abspath(frame.f_code.co_filename)
        if not path.startswith(own):
            break
        frame = frame.f_back
    frame = frame or first
    if frame is None:
        return "unknown code"
    code = frame.f_code
    name = getattr(code, "co_qualname", code.co_name)
    module = frame.f_globals.get("__name__", "?")
    return f"{module}.{name} ({os.path.basename(code.co_filename)}:{frame.f_lineno})"


@contextmanager
def time_limit(seconds: float | None):
    """Raise :class:`Overstayed` in the block once ``seconds`` of wall-clock time have passed.

    ``None`` (or where :func:`supported` is false): no limit.  A timer that was
    armed before (e.g. an enclosing limit) is put back afterwards, less the
    time spent in the block.
    """
    if seconds is None or not supported():
        yield
        return
    seconds = max(float(seconds), 1e-3)
    own = _own_folders()     # before the timer is armed: the handler must be quick

    def fire(signum, frame):   # noqa: ARG001 - signal handler signature
        raise Overstayed(seconds, _where(frame, own))

    t0 = time.monotonic()
    previous = signal.signal(signal.SIGALRM, fire)
    before = signal.setitimer(signal.ITIMER_REAL, seconds, REPEAT_S)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        if before[0] > 0:    # an enclosing timer: re-arm it with what is left of it
            left = max(before[0] - (time.monotonic() - t0), 1e-3)
            signal.setitimer(signal.ITIMER_REAL, left, before[1])
