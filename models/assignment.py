"""The centralized distance-optimal assignment of 004 Sec. V (the baseline of Figs. 10, 12, 14).

004 Sec. V compares its method with the centralized algorithm of its
reference [12], in which "every agent is initially assigned a unique goal"
and "this assignment minimizes the total traveling distance".  Robots move
on the grid (Sec. III-A), so the distance from a start cell to a goal cell
is the Manhattan distance times the grid length ``l``; the optimum is a
linear assignment problem, solved here by scipy's
``linear_sum_assignment`` on the integer matrix of Manhattan distances
(exact: integer costs, no rounding).

An independent exact check for small sizes, with z3's ``Optimize``, is
:func:`swarmproof.checkers.assignment_check.z3_optimal_assignment` (the
models package imports numpy, scipy and networkx only, DESIGN.md section 1).

References
----------
004_004a3703645971e3.txt (Wang & Rubenstein 2020), Sec. V (centralized
method [12], distance-optimal), Sec. V-A (Figs. 10 and 12: distance
travelled against the centralized method), Sec. III-A (grid, Manhattan
distance).

Examples
--------
>>> a = optimal_assignment([(0, 0), (5, 0)], [(4, 0), (1, 0)], spacing=0.2)
>>> total, pairs = a
>>> round(total, 12), pairs, a.cells, a.method, a.size
(0.4, [(0, 1), (1, 0)], 2, 'scipy.optimize.linear_sum_assignment', 2)
"""

from __future__ import annotations

import math

import numpy as np

from .errors import UsageError

__all__ = ["Assignment", "optimal_assignment", "manhattan_matrix", "assignment_cost"]


class Assignment(tuple):
    """``(total, pairs)``: unpacks as a pair, and carries how it was found.

    Attributes
    ----------
    total : float
        Total distance in metres (``cells * spacing``).
    pairs : list of (int, int)
        ``(start index, goal index)`` for every robot, by start index.
    cells : int
        Total Manhattan distance in grid cells (exact).
    method : str
        The solver (``'scipy.optimize.linear_sum_assignment'`` or ``'z3.Optimize'``).
    size : int
        Number of robots.
    """

    def __new__(cls, total: float, pairs: list, *, cells: int, method: str, size: int):
        self = super().__new__(cls, (total, pairs))
        self.cells, self.method, self.size = int(cells), str(method), int(size)
        return self

    @property
    def total(self) -> float:
        return self[0]

    @property
    def pairs(self) -> list:
        return self[1]

    def as_dict(self) -> dict:
        return {"total": self.total, "cells": self.cells, "pairs": [list(p) for p in self.pairs],
                "method": self.method, "size": self.size}

    def __repr__(self) -> str:
        return (f"Assignment(total={self.total!r}, cells={self.cells}, size={self.size}, "
                f"method={self.method!r})")


def _check_cells(name: str, cells) -> np.ndarray:
    try:
        a = np.array([(int(c[0]), int(c[1])) for c in cells], dtype=np.int64).reshape(-1, 2)
        ok = all(len(c) == 2 and float(c[0]) == int(c[0]) and float(c[1]) == int(c[1]) for c in cells)
    except (TypeError, ValueError, IndexError, OverflowError):
        ok = False
    if not ok:
        raise UsageError(f"{name}={cells!r} must be a sequence of (i, j) integer grid cells",
                         fix="e.g. [(0, 0), (3, 1)]")
    return a


def manhattan_matrix(start_cells, goal_cells) -> np.ndarray:
    """The integer matrix ``D[i, j] = |x_i - x_j| + |y_i - y_j|`` between start ``i`` and goal ``j``.

    >>> manhattan_matrix([(0, 0), (2, 1)], [(1, 1)]).tolist()
    [[2], [1]]
    """
    s = _check_cells("start_cells", start_cells)
    g = _check_cells("goal_cells", goal_cells)
    return np.abs(s[:, None, 0] - g[None, :, 0]) + np.abs(s[:, None, 1] - g[None, :, 1])


def assignment_cost(start_cells, goal_cells, goal_of) -> int:
    """Total Manhattan distance (cells) when start ``i`` goes to goal ``goal_of[i]``.

    >>> assignment_cost([(0, 0), (5, 0)], [(4, 0), (1, 0)], [0, 1])
    8
    """
    d = manhattan_matrix(start_cells, goal_cells)
    return int(sum(int(d[i, j]) for i, j in enumerate(goal_of)))


def _check_sizes(s, g) -> int:
    if len(s) != len(g):
        raise UsageError(f"start_cells has {len(s)} cells and goal_cells {len(g)}: 004 Sec. II-C assumes "
                         "|Q| = |A|", fix="give one goal cell per robot")
    if len(s) == 0:
        raise UsageError("start_cells=[] is empty", fix="give at least one robot")
    if len({tuple(c) for c in g.tolist()}) != len(g):
        raise UsageError("goal_cells has a repeated cell: 004 Sec. II-B asks for distinct target locations",
                         fix="remove the duplicate goal cells")
    return len(s)


def optimal_assignment(start_cells, goal_cells, *, spacing: float = 1.0) -> Assignment:
    """The distance-optimal one-to-one assignment of start cells to goal cells (004 Sec. V).

    Parameters
    ----------
    start_cells, goal_cells : sequences of (i, j) integer cells
        Equally many (004 Sec. II-C: ``|Q| = |A|``); goals distinct.
    spacing : float
        Grid length in metres (004 Sec. V-B3: l = 0.20 m); ``total`` is the
        Manhattan total in cells times ``spacing``.

    Returns
    -------
    Assignment
        ``(total, pairs)`` with ``pairs[k] = (k, goal index)``; also
        ``.cells`` (exact integer total), ``.method`` and ``.size``.

    Raises
    ------
    UsageError
        Unequal sizes, no robots, repeated goals, non-integer cells, bad spacing.

    Examples
    --------
    >>> optimal_assignment([(0, 0), (0, 1), (0, 2)], [(3, 2), (3, 0), (3, 1)]).pairs
    [(0, 1), (1, 2), (2, 0)]
    """
    if isinstance(spacing, bool) or not isinstance(spacing, (int, float)) or not (
            math.isfinite(spacing) and spacing > 0):
        raise UsageError(f"spacing={spacing!r} must be a finite number > 0", fix="e.g. 0.2 (004 Sec. V-B3)")
    s = _check_cells("start_cells", start_cells)
    g = _check_cells("goal_cells", goal_cells)
    n = _check_sizes(s, g)
    from scipy.optimize import linear_sum_assignment

    d = manhattan_matrix(s.tolist(), g.tolist())
    rows, cols = linear_sum_assignment(d)
    cells = int(d[rows, cols].sum())
    pairs = sorted((int(i), int(j)) for i, j in zip(rows, cols))
    return Assignment(cells * float(spacing), pairs, cells=cells, method="scipy.optimize.linear_sum_assignment",
                      size=n)
