"""Ctrl-C: the first press stops every command, whoever else listens for it.

A library the command runs may catch ``KeyboardInterrupt`` and go on (a Dask
client counting a lost task, an algorithm's ``except BaseException``), or
replace the SIGINT handler while it works (z3 cancels its solver and returns
``unknown``).  So the command line installs :func:`handler`, which *remembers*
the press before it raises: :func:`raise_if_interrupted` raises again at the
next safe point, every file write (:mod:`swarmproof.models.fileio`) and every
report printed refuses to run once Ctrl-C was pressed, and the command exits
130 -- never with a report that looks complete (docs/README.md, "Exit codes").

Examples
--------
>>> reset(); interrupted()
False
>>> note()
>>> try:
...     raise_if_interrupted()
... except KeyboardInterrupt:
...     print("stopped")
stopped
>>> reset()
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager

__all__ = ["EXIT_INTERRUPTED", "deferred", "handler", "installed", "interrupted", "note", "raise_if_interrupted",
           "reset"]

#: The exit code of a command stopped by Ctrl-C (128 + SIGINT, as shells report it).
EXIT_INTERRUPTED = 130

_PRESSED = [False]


def interrupted() -> bool:
    """Whether Ctrl-C was pressed since :func:`reset`."""
    return _PRESSED[0]


def note() -> None:
    """Remember a Ctrl-C that arrived another way (e.g. z3 answered ``unknown``: ``canceled``)."""
    _PRESSED[0] = True


def reset() -> None:
    """Forget an earlier press (the CLI runs several commands in one process in tests)."""
    _PRESSED[0] = False


def raise_if_interrupted() -> None:
    """Raise ``KeyboardInterrupt`` if Ctrl-C was pressed, even when someone swallowed the first."""
    if _PRESSED[0]:
        raise KeyboardInterrupt


def handler(signum, frame) -> None:   # noqa: ARG001 - signal handler signature
    """The SIGINT handler the command line installs: remember the press, then raise."""
    _PRESSED[0] = True
    raise KeyboardInterrupt


@contextmanager
def _sigint(new_handler, on_start=None):
    """``new_handler`` for SIGINT while the block runs, then the previous one again; the block
    gets True, or False where no handler can be set (another thread than the main one, or no
    signals here) and nothing changed."""
    if threading.current_thread() is not threading.main_thread():
        yield False
        return
    if on_start is not None:
        on_start()
    try:
        previous = signal.signal(signal.SIGINT, new_handler)
    except (ValueError, OSError):   # pragma: no cover - no signals here
        yield False
        return
    try:
        yield True
    finally:
        signal.signal(signal.SIGINT, previous)


@contextmanager
def installed():
    """Install :func:`handler` for SIGINT while the block runs (main thread only; elsewhere a no-op),
    then put the previous handler back."""
    with _sigint(handler, on_start=reset):
        yield


_DEFERRING = [False]


@contextmanager
def deferred(on_press=None):
    """Hold Ctrl-C while the block runs (main thread only; elsewhere, or nested, a no-op): a
    press is remembered and ``on_press()`` is called (e.g. to cancel a solver), but nothing is
    raised where the press lands; the block calls :func:`raise_if_interrupted` at its safe points,
    and the press is raised when the block ends at the latest.

    For code whose objects free native memory in ``__del__`` (z3's terms, solvers and contexts):
    a ``KeyboardInterrupt`` raised inside a ``__del__`` is not an exception anyone can catch --
    Python prints "Exception ignored in ..." with a traceback and goes on.

    >>> reset()
    >>> with deferred():
    ...     interrupted()
    False
    """
    if _DEFERRING[0]:
        yield
        return

    def hold(signum, frame) -> None:   # noqa: ARG001 - signal handler signature
        _PRESSED[0] = True
        if on_press is not None:
            on_press()

    with _sigint(hold) as held:
        if not held:
            yield
            return
        _DEFERRING[0] = True
        try:
            yield
        finally:
            _DEFERRING[0] = False
    raise_if_interrupted()
