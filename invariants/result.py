"""The small result object every invariant returns.

Three statuses, never two (DESIGN.md section 1 "Verdicts"): ``"held"`` (over
the trace or state checked; never a proof), ``"violated"`` (with a
``witness`` a person can read), ``"inconclusive"`` (the data cannot decide,
e.g. the run stopped before the bound).  ``applicable`` is False when the
claim's premise is false (e.g. connectivity when the start was already
disconnected): the result is then vacuously ``"held"`` and says so.

Examples
--------
>>> r = InvariantResult("connectivity", "violated", "001 Lemma 11", {"step": 3}, "split at step 3")
>>> r.held, r.violated, bool(r)
(False, True, False)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from swarmproof.models.verdict import ThreeValued

__all__ = ["InvariantResult", "state_value"]


@dataclass(frozen=True)
class InvariantResult(ThreeValued):
    """Outcome of one invariant over one trace or state.

    Attributes
    ----------
    name : str
    status : str
        ``"held"``, ``"violated"`` or ``"inconclusive"``.
    cites : str
        The claim checked (seed file and lemma/definition).
    witness : dict or None
        For a violation: where and what (JSON-friendly).
    message : str
    applicable : bool
        False when the claim's premise does not hold (vacuous).
    """

    name: str
    status: str
    cites: str
    witness: dict | None = None
    message: str = ""
    applicable: bool = True
    detail: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self._check_status()


    def as_dict(self) -> dict:
        return {"name": self.name, "status": self.status, "cites": self.cites,
                "witness": self.witness, "message": self.message, "applicable": self.applicable}


def state_value(state: Any, key: str, default: Any = None) -> Any:
    """Read ``key`` from a controller state: a mapping, an object with that
    attribute, or a tuple of ``(key, value)`` pairs (the documented forms).

    >>> state_value((("parent", 7), ("stable", True)), "parent")
    7
    >>> state_value({"parent": None}, "parent", -1) is None
    True
    >>> state_value("idle", "parent", "none")
    'none'
    """
    if state is None:
        return default
    if isinstance(state, dict):
        return state.get(key, default)
    if isinstance(state, tuple) and key in getattr(state, "_fields", ()):  # namedtuple
        return getattr(state, key)
    if isinstance(state, tuple):
        for item in state:
            if isinstance(item, tuple) and len(item) == 2 and item[0] == key:
                return item[1]
        return default
    return getattr(state, key, default)
