"""The one exception tree of swarmproof.

Every error swarmproof raises on purpose is a :class:`SwarmproofError`.
Errors caused by what a *user* gave us (a file, a command-line value, a
parameter outside a paper's assumptions) also subclass :class:`ValueError`;
the command line turns them into a one-paragraph message and exit code 2,
never a traceback.

Messages follow one shape (Hypothesis ``errors.py`` habit, DESIGN.md
section 3): what was wrong as ``name=value!r``, where (file, line, field),
what was expected, and how to fix it.  Input checks live in small
``check_*`` helpers, never in ``assert``.

Examples
--------
>>> err = InputFileError("angle_unit='grad' is not a known unit",
...                      file="sq.yaml", line=4, field="angle_unit",
...                      fix="use 'deg' or 'rad'")
>>> print(err)
sq.yaml:4: field 'angle_unit': angle_unit='grad' is not a known unit; fix: use 'deg' or 'rad'
>>> isinstance(err, ValueError)
True
"""

from __future__ import annotations

import math
from typing import Any

__all__ = [
    "SwarmproofError",
    "UsageError",
    "InputFileError",
    "AssumptionError",
    "ProtocolError",
    "check_finite",
    "check_positive",
    "check_type",
]


class SwarmproofError(Exception):
    """Base of every error swarmproof raises deliberately."""


class UsageError(SwarmproofError, ValueError):
    """A user-facing mistake: bad value, bad option, unreadable input.

    Parameters
    ----------
    message : str
        What was wrong, naming it as ``name=value!r``.
    fix : str, optional
        How to fix it, appended as ``; fix: ...``.
    """

    def __init__(self, message: str, *, fix: str | None = None) -> None:
        self.message = message
        self.fix = fix
        super().__init__(self._render())

    def _render(self) -> str:
        text = self.message
        if self.fix:
            text += f"; fix: {self.fix}"
        return text


class InputFileError(UsageError):
    """An input file is missing, malformed or invalid.

    Parameters
    ----------
    message : str
        What was wrong (``name=value!r``).
    file : str, optional
        The file's path as the user gave it.
    line : int, optional
        1-based line number (known for YAML and JSON sources).
    field : str, optional
        The dotted/indexed field, e.g. ``edges[3][2]``.
    fix : str, optional
        How to fix it.
    """

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        line: int | None = None,
        field: str | None = None,
        fix: str | None = None,
    ) -> None:
        self.file = file
        self.line = line
        self.field = field
        super().__init__(message, fix=fix)

    def _render(self) -> str:
        where = ""
        if self.file is not None:
            where = str(self.file)
            if self.line is not None:
                where += f":{self.line}"
            where += ": "
        elif self.line is not None:
            where = f"line {self.line}: "
        if self.field:
            where += f"field {self.field!r}: "
        return where + super()._render()


class AssumptionError(UsageError):
    """Parameters outside the assumptions a paper makes.

    Parameters
    ----------
    assumption : str
        The assumption's name, e.g. ``'v_dt_below_range'``.
    message : str
        What was wrong (``name=value!r``) and the paper's citation.
    fix : str, optional
        How to fix it (usually: change the value, or pass
        ``allow_violations=True`` to break the assumption on purpose).
    """

    def __init__(self, assumption: str, message: str, *, fix: str | None = None) -> None:
        self.assumption = assumption
        super().__init__(f"assumption {assumption!r} broken: {message}", fix=fix)


class ProtocolError(SwarmproofError):
    """An algorithm broke the algorithm protocol (a programming error in the
    algorithm, not a user input mistake), e.g. returned a malformed command."""


def check_type(name: str, value: Any, types: type | tuple[type, ...], *, fix: str | None = None) -> None:
    """Raise :class:`UsageError` unless ``isinstance(value, types)``.

    >>> check_type("robots", "ten", int)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: robots='ten' must be int, got str; fix: pass a whole number
    """
    if isinstance(value, bool) and bool not in (types if isinstance(types, tuple) else (types,)):
        ok = False
    else:
        ok = isinstance(value, types)
    if not ok:
        names = (
            " or ".join(t.__name__ for t in types) if isinstance(types, tuple) else types.__name__
        )
        if fix is None and (types is int or types == (int,)):
            fix = "pass a whole number"
        raise UsageError(f"{name}={value!r} must be {names}, got {type(value).__name__}", fix=fix)


def check_finite(name: str, value: Any, *, fix: str | None = None) -> float:
    """Return ``float(value)``; raise :class:`UsageError` if it is not a finite real.

    >>> check_finite("range", 1.5)
    1.5
    >>> check_finite("range", float("nan"))
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: range=nan must be a finite number; fix: give a finite real number
    """
    if isinstance(value, bool):
        raise UsageError(f"{name}={value!r} must be a finite number, not a boolean",
                         fix=fix or "give a finite real number")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise UsageError(f"{name}={value!r} must be a finite number",
                         fix=fix or "give a finite real number") from None
    if not math.isfinite(x):
        raise UsageError(f"{name}={value!r} must be a finite number",
                         fix=fix or "give a finite real number")
    return x


def check_positive(name: str, value: Any, *, fix: str | None = None) -> float:
    """Return ``float(value)``; raise :class:`UsageError` unless finite and > 0.

    >>> check_positive("dt", 0)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: dt=0 must be > 0; fix: give a positive number
    """
    x = check_finite(name, value, fix=fix)
    if not x > 0:
        raise UsageError(f"{name}={value!r} must be > 0", fix=fix or "give a positive number")
    return x


def did_you_mean(name: Any, choices) -> str:
    """``"; did you mean 'X'?"`` for the choice closest to a mistyped ``name`` (difflib's ratio
    of at least 0.6), else ``""``: appended to a "not known" message before its fix.

    >>> did_you_mean("song2061", ["song2014", "song2016", "wang2020"])
    "; did you mean 'song2016'?"
    >>> did_you_mean("algorithm", ["algorithms", "lemmas"])
    "; did you mean 'algorithms'?"
    >>> did_you_mean("zzz", ["square", "hexagon"])
    ''
    """
    import difflib

    close = difflib.get_close_matches(str(name), [str(c) for c in choices], n=1)
    return f"; did you mean {close[0]!r}?" if close else ""
