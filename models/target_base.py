"""What every target kind shares: the :class:`Target` protocol, its verdict :class:`TargetCheck`
and the robots' positions read from their poses (:func:`as_xy`).

The kinds themselves live with their mathematics (a lattice graph in
:mod:`swarmproof.models.lattice`, a goal set in :mod:`swarmproof.models.shapes`, a repeating
pattern in :mod:`swarmproof.models.repeating_pattern`, a line pattern in
:mod:`swarmproof.models.targets`), and :mod:`swarmproof.models.targets` keeps the registry of
kinds that resolves a name of any kind.  This module imports none of them, so each kind can
import it without an import circle.

Examples
--------
>>> TargetCheck("held", "ok", "001 Def. 2").as_dict()
{'status': 'held', 'message': 'ok', 'cites': '001 Def. 2', 'witness': None}
>>> as_xy([[0, 1, 3.0], [2, 3, 0.5]]).tolist()
[[0.0, 1.0], [2.0, 3.0]]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

from .verdict import ThreeValued

__all__ = ["TargetCheck", "Target", "as_xy"]


@dataclass(frozen=True)
class TargetCheck(ThreeValued):
    """A target's verdict on one configuration."""

    status: str
    message: str
    cites: str
    witness: dict | None = None
    detail: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self._check_status()


    def as_dict(self) -> dict:
        return {"status": self.status, "message": self.message, "cites": self.cites,
                "witness": self.witness, **({"detail": self.detail} if self.detail else {})}


@runtime_checkable
class Target(Protocol):
    """What the engine, the properties and the metrics need of a target."""

    kind: str
    name: str

    def satisfied(self, ids, poses, *, phi: float | None = None, tol=None) -> TargetCheck: ...

    def progress(self, ids, poses, *, phi: float | None = None) -> float: ...

    def metrics(self, ids, poses, *, phi: float | None = None) -> dict: ...

    def describe(self) -> dict: ...


def as_xy(poses) -> np.ndarray:
    """The ``(x, y)`` columns of ``poses`` (rows ``[x, y, theta]``) as an ``(n, 2)`` float array.

    Parameters
    ----------
    poses : array_like
        Robot poses, one per row (any leading shape); empty gives a ``(0, 2)`` array.

    Returns
    -------
    numpy.ndarray

    Examples
    --------
    >>> as_xy([]).shape
    (0, 2)
    """
    a = np.asarray(poses, dtype=float)
    return a.reshape(-1, a.shape[-1])[:, :2] if a.size else np.zeros((0, 2))
