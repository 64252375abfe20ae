"""Goal shapes of Wang & Rubenstein 2020 (004): bitmaps and images to goal cells, scaled to n robots.

004 Sec. V-A: "the goal shape is given to the swarm in the form of a binary
figure, i.e., a black and white image.  The figure is scaled such that the
number of goal pixels on the figure equals the number of agents."  Sec. II-C
asks for "an arbitrary connected target formation" ``Q`` with ``|Q| = |A|``.
This module reads such figures and makes a
:class:`GoalSet` (the ``shape`` target kind) of exactly ``n`` connected cells.

Files
-----
* ``.txt``: a text bitmap, ``'#'`` a goal cell, ``'.'`` a free cell, rows from
  top to bottom (the top row has the largest y); rows may differ in length
  (missing cells are free); blank lines are rows of free cells; any other
  character is an :class:`~swarmproof.models.errors.InputFileError` naming the
  file, line, column and character.
* ``.png``: read with Pillow (matplotlib's own image reader uses it).  Each
  pixel is composited over white by its alpha, its luminance
  ``L = 0.299 R + 0.587 G + 0.114 B`` taken on 0..255, and it is *filled*
  (a goal cell) when ``L < DARK_THRESHOLD = 128``: dark ink on a light or
  transparent background.  Row 0 of the image is the top.

Both are refused above ``MAX_SIDE = 2048`` rows or columns (the image header
is read before any pixel); :func:`scale_to` makes at most
``MAX_GOALS = 16384`` goal cells.

Connected means 4-connected on the grid: two goal cells are adjacent when
they share a grid edge, the moves of 004 Sec. III-A (north, east, south,
west).  See docs/decisions.md, "Wang & Rubenstein shapes (issue 15)".

Bundled shapes (``models/shape_bitmaps/*.txt``): ``letter-n`` and ``letter-u``
(004 Figs. 1 and 9, the letters "N" and "U"), besides ``square-9`` and
``letter-l`` defined here as small bitmaps (``_BUNDLED_SHAPES``).  004's Fig. 8 shows
four other input images that its text does not describe, and Figs. 10-12 use
"randomly generated ... connected random positions": :func:`random_shape`.

References
----------
004_004a3703645971e3.txt (Wang & Rubenstein 2020), Sec. II-C (connected Q,
``|Q| = |A|``), Sec. III-A (grid of waypoints, four moves), Sec. V-A (the
binary image scaled to the number of agents; fixed-size arena; r = 0.05 m,
R = 0.6 m), Sec. V-B3 (grid length l = 0.20 m), Figs. 1, 8-12.

Examples
--------
>>> g = shape_for("letter-n", 256)
>>> len(g.cells), connected(g.cells), g.spacing, g.range
(256, True, 0.2, 0.6)
>>> sorted(scale_to({(0, 0), (1, 0), (0, 1)}, 12)) == sorted(scale_to({(0, 0), (1, 0), (0, 1)}, 12))
True
>>> len(scale_to({(0, 0), (1, 0), (0, 1)}, 12))
12
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from dataclasses import dataclass
from typing import Iterable, Mapping

import numpy as np

from .errors import InputFileError, UsageError, check_type
from .target_base import TargetCheck, as_xy

__all__ = ["GoalSet", "load_shape_file", "scale_to", "scale_details", "connected", "components", "shape_for",
           "bundled_shape_names", "random_shape", "arena_cells", "centered_arena", "random_start_cells",
           "DEFAULT_ARENA", "DEFAULT_SPACING", "MAX_SIDE", "MAX_GOALS", "DARK_THRESHOLD"]

#: Grid length l of 004 Sec. V-B3 (metres).
DEFAULT_SPACING = 0.2
#: Communication range R over grid length l in 004 (0.6 m / 0.2 m): a goal set's recommended range.
RANGE_OVER_SPACING = 3.0
#: Largest number of rows or columns of a shape file.
MAX_SIDE = 2048
#: Largest number of goal cells :func:`scale_to` makes (004 runs at most 1,024 agents).
MAX_GOALS = 16384
#: A PNG pixel is a goal cell when its luminance (0..255, over white) is below this.
DARK_THRESHOLD = 128
#: The arena :func:`random_start_cells` uses by default: 32 x 32 waypoints (docs/decisions.md).
DEFAULT_ARENA = (32, 32)



def _range(spacing: float) -> float:
    """The recommended range for grid length ``spacing``: R = 3 l (0.6 m at 0.2 m), rounded to 12 digits."""
    return float(round(RANGE_OVER_SPACING * float(spacing), 12))


_BITMAP_DIR = Path(__file__).resolve().parent / "shape_bitmaps"
_PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
_FOUR = ((1, 0), (0, 1), (-1, 0), (0, -1))


# ----------------------------------------------------------------------------
# shape (004): a set of goal cells on a grid
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class GoalSet:
    """Goal cells of 004 Sec. III: the shape is a set of grid waypoints, one robot each.

    ``cells`` are integer ``(i, j)``; a cell's position is ``origin + spacing
    * (i, j)`` in the common frame (004's robots know global coordinates).
    Satisfied when every goal cell holds exactly one robot (within ``tol``,
    default ``1e-9 spacing``) and no robot stands elsewhere.  A bitmap
    builds one: ``'#'`` a goal cell, ``'.'`` none, rows from top to bottom.

    >>> g = GoalSet.from_bitmap("L", ["#.", "##"], spacing=0.2)
    >>> sorted(g.cells)
    [(0, 0), (0, 1), (1, 0)]
    >>> g.satisfied([1, 2, 3], [[0, 0, 0], [0, 0.2, 0], [0.2, 0, 0]]).status
    'held'
    >>> g.progress([1, 2, 3], [[0, 0, 0], [0, 0.2, 0], [5, 5, 0]])
    0.6666666666666666
    """

    name: str
    cells: frozenset
    spacing: float = 1.0
    origin: tuple = (0.0, 0.0)
    range: float | None = None   # a recommended range for runs toward it (004 Sec. V-A: R = 0.6 m)
    kind: str = "shape"
    cites: str = "004 Sec. III (goal set on grid waypoints; shape complete)"

    def __post_init__(self) -> None:
        cells = frozenset((int(i), int(j)) for i, j in self.cells)
        if not cells:
            raise UsageError("cells=[] is empty", fix="give at least one goal cell")
        object.__setattr__(self, "cells", cells)
        if not (isinstance(self.spacing, (int, float)) and math.isfinite(self.spacing) and self.spacing > 0):
            raise UsageError(f"spacing={self.spacing!r} must be a finite number > 0")
        object.__setattr__(self, "origin", (float(self.origin[0]), float(self.origin[1])))

    @classmethod
    def from_bitmap(cls, name: str, rows, spacing: float = 1.0, origin=(0.0, 0.0),
                    range: float | None = None) -> "GoalSet":
        rows = list(rows)
        cells = []
        for r, line in enumerate(rows):
            for c, ch in enumerate(line):
                if ch == "#":
                    cells.append((c, len(rows) - 1 - r))
                elif ch != ".":
                    raise UsageError(f"bitmap row {r} column {c}: {ch!r} is neither '#' (goal) nor '.' (free)")
        return cls(name, frozenset(cells), spacing, origin, range)

    def positions(self) -> np.ndarray:
        """Goal cell positions, sorted by cell."""
        cells = sorted(self.cells)
        return np.array([(self.origin[0] + self.spacing * i, self.origin[1] + self.spacing * j)
                         for i, j in cells], dtype=float)

    def _occupancy(self, poses, tol):
        xy = as_xy(poses)
        tol = 1e-9 * self.spacing if tol is None else float(tol[0] if isinstance(tol, tuple) else tol)
        cells = sorted(self.cells)
        goal = self.positions()
        on = {}
        off = []
        for k, (x, y) in enumerate(xy):
            d = np.hypot(goal[:, 0] - x, goal[:, 1] - y)
            g = int(np.argmin(d))
            if d[g] <= tol:
                on.setdefault(cells[g], []).append(k)
            else:
                off.append(k)
        return xy, on, off

    def satisfied(self, ids, poses, *, phi: float | None = None, tol=None) -> TargetCheck:
        xy, on, off = self._occupancy(poses, tol)
        ids = [int(x) for x in ids]
        doubled = {c: ks for c, ks in on.items() if len(ks) > 1}
        empty = sorted(self.cells - set(on))
        if not doubled and not off and not empty:
            return TargetCheck("held", f"all {len(self.cells)} goal cells of {self.name!r} hold one robot each",
                               self.cites)
        if doubled:
            c, ks = sorted(doubled.items())[0]
            return TargetCheck("violated", f"goal cell {c} holds robots {[ids[k] for k in ks]}", self.cites,
                               {"cell": list(c), "robots": [ids[k] for k in ks]})
        if off:
            k = off[0]
            return TargetCheck("violated", f"robot {ids[k]} at ({xy[k, 0]:.4g}, {xy[k, 1]:.4g}) is on no goal "
                                           f"cell ({len(off)} robot(s) off the shape)", self.cites,
                               {"robot": ids[k], "off": len(off)})
        return TargetCheck("violated", f"goal cell {empty[0]} is empty ({len(empty)} empty; "
                                       f"{len(xy)} robots for {len(self.cells)} cells)", self.cites,
                           {"cell": list(empty[0]), "empty": len(empty)})

    def progress(self, ids, poses, *, phi: float | None = None) -> float:
        """The fraction of goal cells occupied."""
        _, on, _ = self._occupancy(poses, None)
        return len(on) / len(self.cells)

    def metrics(self, ids, poses, *, phi: float | None = None) -> dict:
        _, on, off = self._occupancy(poses, None)
        return {"cells": len(self.cells), "occupied": len(on), "off_shape": len(off)}

    def describe(self) -> dict:
        d = {"kind": self.kind, "name": self.name, "cells": [list(c) for c in sorted(self.cells)],
             "spacing": float(self.spacing), "origin": list(self.origin)}
        if self.range is not None:
            d["range"] = float(self.range)
        return d

    @classmethod
    def from_description(cls, d: Mapping) -> "GoalSet":
        name = d.get("name")
        if name in _BUNDLED_SHAPES and "cells" not in d:
            return _BUNDLED_SHAPES[name]()
        if isinstance(name, str) and "cells" not in d and name in bundled_shape_names():
            return bundled_shape(name)
        cells = d.get("cells")
        if not isinstance(cells, (list, tuple)) or not all(
                isinstance(c, (list, tuple)) and len(c) == 2 and all(isinstance(v, int) and not isinstance(v, bool)
                                                                   for v in c) for c in cells):
            raise UsageError(f"cells={cells!r} must be a list of [i, j] integer pairs", fix="e.g. [[0, 0], [1, 0]]")
        return cls(str(name or "shape"), frozenset(map(tuple, cells)), d.get("spacing", 1.0),
                   tuple(d.get("origin", (0.0, 0.0))), d.get("range"))


#: Small bundled shapes (004 Fig. 10 uses large bitmaps; these keep tests fast).  Spacing
#: l = 0.20 m (004 Sec. V-B3), range R = 0.6 m (004 Sec. V-A).
_BUNDLED_SHAPES = {
    "square-9": lambda: GoalSet.from_bitmap("square-9", ["###", "###", "###"], spacing=0.2, range=0.6),
    "letter-l": lambda: GoalSet.from_bitmap("letter-l", ["#..", "#..", "###"], spacing=0.2, range=0.6),
}


# ----------------------------------------------------------------------------
# connectivity
# ----------------------------------------------------------------------------

def _as_cells(cells, name: str = "cells") -> frozenset:
    try:
        out = frozenset((int(i), int(j)) for i, j in cells)
    except (TypeError, ValueError):
        raise UsageError(f"{name}={cells!r} must be (i, j) integer pairs", fix="e.g. [(0, 0), (1, 0)]") from None
    return out


def _to_array(cells: frozenset):
    """Cells as a boolean array ``a[x - x0, y - y0]`` and its offset ``(x0, y0)``."""
    xs = np.fromiter((c[0] for c in cells), dtype=np.int64, count=len(cells))
    ys = np.fromiter((c[1] for c in cells), dtype=np.int64, count=len(cells))
    x0, y0 = int(xs.min()), int(ys.min())
    a = np.zeros((int(xs.max()) - x0 + 1, int(ys.max()) - y0 + 1), dtype=bool)
    a[xs - x0, ys - y0] = True
    return a, (x0, y0)


def _from_array(a: np.ndarray, offset=(0, 0)) -> frozenset:
    xs, ys = np.nonzero(a)
    return frozenset(zip((xs + offset[0]).tolist(), (ys + offset[1]).tolist()))


def _bfs_components(cells: frozenset) -> list:
    left = set(cells)
    out = []
    while left:
        start = min(left)
        left.discard(start)
        comp, stack = [start], [start]
        while stack:
            x, y = stack.pop()
            for dx, dy in _FOUR:
                c = (x + dx, y + dy)
                if c in left:
                    left.discard(c)
                    comp.append(c)
                    stack.append(c)
        out.append(frozenset(comp))
    return out


def components(cells) -> list:
    """The 4-connected components of a set of grid cells, largest first (ties: smallest cell first).

    Two cells are adjacent when they share a grid edge (004 Sec. III-A: the
    moves north, east, south, west).

    >>> [sorted(c) for c in components({(0, 0), (1, 0), (3, 0), (1, 1)})]
    [[(0, 0), (1, 0), (1, 1)], [(3, 0)]]
    >>> components(set())
    []
    """
    cells = _as_cells(cells)
    if not cells:
        return []
    xs = [c[0] for c in cells]
    ys = [c[1] for c in cells]
    area = (max(xs) - min(xs) + 1) * (max(ys) - min(ys) + 1)
    if area > 4 * MAX_SIDE * MAX_SIDE:          # sparse and far apart: no dense array
        comps = _bfs_components(cells)
    else:
        from scipy import ndimage

        a, off = _to_array(cells)
        labels, k = ndimage.label(a)             # the default 2-D structure is the 4-neighbour cross
        comps = [_from_array(labels == i, off) for i in range(1, k + 1)]
    return sorted(comps, key=lambda c: (-len(c), min(c)))


def connected(cells) -> bool:
    """True when the cells are non-empty and 4-connected (004 Sec. II-C "connected target formation").

    >>> connected({(0, 0), (0, 1), (1, 1)}), connected({(0, 0), (1, 1)}), connected(set())
    (True, False, False)
    """
    return len(components(cells)) == 1


def _check_connected(cells: frozenset, what: str, *, file: str | None = None, fix: str | None = None) -> None:
    comps = components(cells)
    if len(comps) <= 1:
        return
    sizes = ", ".join(str(len(c)) for c in comps[:5]) + (", ..." if len(comps) > 5 else "")
    msg = (f"{what} is not connected: {len(comps)} separate parts of {sizes} cells (cell {min(comps[1])} "
           f"is cut off from cell {min(comps[0])}); 004 Sec. II-C asks for a connected target formation")
    fix = fix or "join the parts with goal cells that share an edge (diagonal contact does not count), or remove the stray parts"
    if file is not None:
        raise InputFileError(msg, file=file, fix=fix)
    raise UsageError(msg, fix=fix)


# ----------------------------------------------------------------------------
# scaling to n goal cells (004 Sec. V-A)
# ----------------------------------------------------------------------------

def _resample(table: np.ndarray, shape: tuple, s: float, rule: str = "nearest") -> np.ndarray:
    """The bitmap scaled by ``s`` (target grid ``ceil(W s) x ceil(H s)``).

    ``rule="nearest"``: target cell ``(X, Y)`` takes the source cell under its
    centre, ``(floor((X + 1/2)/s), floor((Y + 1/2)/s))`` (ordinary image
    scaling; keeps 4-connectivity for ``s >= 1``, where every source cell
    keeps at least one target cell).  ``rule="overlap"``: filled when the
    target square ``[X/s, (X+1)/s) x [Y/s, (Y+1)/s)`` overlaps a filled source
    cell (keeps 4-connectivity at every scale: the image of a cell is a
    rectangle of target cells, and those of two adjacent cells touch or overlap).

    ``table`` is the summed-area table of the source (shape ``(W+1, H+1)``).
    """
    w, h = shape

    def spans(size):
        m = int(math.ceil(size * s))
        k = np.arange(m, dtype=float)
        if rule == "nearest":                  # centres past the source's edge sample nothing
            lo = np.floor((k + 0.5) / s).astype(np.int64)
            return lo[lo < size], lo[lo < size]
        lo = np.clip(np.floor(k / s).astype(np.int64), 0, size - 1)
        hi = np.clip(np.ceil((k + 1) / s).astype(np.int64) - 1, 0, size - 1)
        return lo, np.maximum(hi, lo)

    xl, xh = spans(w)
    yl, yh = spans(h)
    count = (table[xh[:, None] + 1, yh[None, :] + 1] - table[xl[:, None], yh[None, :] + 1]
             - table[xh[:, None] + 1, yl[None, :]] + table[xl[:, None], yl[None, :]])
    return count > 0


def _scale_search(table: np.ndarray, shape: tuple, n: int, n0: int, rule: str) -> float:
    """The end ``hi`` of a bisection on the scale with ``count(lo) < n <= count(hi)``."""
    def count(s):
        return int(_resample(table, shape, s, rule).sum())

    lo = 1.0 / (2.0 * max(shape))              # a 1 x 1 target grid: at most one cell
    if count(lo) >= n:
        return lo
    hi = max(1.0, math.sqrt(n / n0))
    while count(hi) < n:
        lo, hi = hi, 2.0 * hi
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if count(mid) >= n:
            hi = mid
        else:
            lo = mid
    return hi


def _locally_removable(filled: set, c) -> bool:
    """Removing ``c`` keeps its filled 4-neighbours connected inside its 3 x 3 ring (a sufficient
    condition for the whole set to stay 4-connected)."""
    x, y = c
    ring = [(0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1), (-1, 0), (-1, 1)]   # cyclic; even = 4-nbr
    on = [(x + dx, y + dy) in filled for dx, dy in ring]
    if not any(on[k] for k in (0, 2, 4, 6)):
        return False
    if all(on):
        return True
    start = on.index(False)
    runs_with_nbr, in_run, has_nbr = 0, False, False
    for step in range(1, 9):
        k = (start + step) % 8
        if on[k]:
            if not in_run:
                in_run, has_nbr = True, False
            has_nbr = has_nbr or k % 2 == 0
        elif in_run:
            runs_with_nbr += has_nbr
            in_run = False
    if in_run:
        runs_with_nbr += has_nbr
    return runs_with_nbr == 1


def _trim(cells: frozenset, k: int) -> frozenset:
    """Drop ``k`` boundary cells keeping the set 4-connected, spread out: each time the removable
    cell with the fewest filled 4-neighbours, then the farthest (Manhattan) from the cells dropped
    so far, then the smallest ``(x, y)``.  Removable: locally simple, else (rarely) not an
    articulation point of the cell graph."""
    if k <= 0:
        return cells
    order = sorted(cells)
    index = {c: i for i, c in enumerate(order)}
    xs = np.array([c[0] for c in order], dtype=np.int64)
    ys = np.array([c[1] for c in order], dtype=np.int64)
    filled = set(cells)
    deg = np.array([sum((x + dx, y + dy) in filled for dx, dy in _FOUR) for x, y in order], dtype=np.int64)
    dist = np.full(len(order), np.iinfo(np.int64).max // 4, dtype=np.int64)
    alive = np.ones(len(order), dtype=bool)
    for _ in range(k):
        # candidates in key order: degree (boundary first), far from earlier drops, then (x, y)
        live = np.nonzero(alive)[0]
        keys = np.lexsort((ys[live], xs[live], -dist[live], deg[live]))
        pick = None
        for i in live[keys]:
            if deg[i] >= 4:
                break
            if _locally_removable(filled, order[i]):
                pick = int(i)
                break
        if pick is None:
            import networkx as nx

            g = nx.Graph()
            g.add_nodes_from(filled)
            g.add_edges_from((c, (c[0] + dx, c[1] + dy)) for c in filled for dx, dy in _FOUR[:2]
                             if (c[0] + dx, c[1] + dy) in filled)
            cut = set(nx.articulation_points(g))
            pick = next(int(i) for i in live[keys] if order[i] not in cut)
        c = order[pick]
        filled.discard(c)
        alive[pick] = False
        for dx, dy in _FOUR:
            j = index.get((c[0] + dx, c[1] + dy))
            if j is not None and alive[j]:
                deg[j] -= 1
        np.minimum(dist, np.abs(xs - c[0]) + np.abs(ys - c[1]), out=dist)
    return frozenset(filled)


def _check_n(n) -> int:
    check_type("n", n, (int, np.integer), fix="give the number of robots as a whole number")
    if not 1 <= n <= MAX_GOALS:
        raise UsageError(f"n={n!r} robots is outside 1..{MAX_GOALS}",
                         fix=f"give between 1 and {MAX_GOALS} robots (004 runs at most 1,024)")
    return int(n)


def scale_details(cells, n: int) -> tuple:
    """:func:`scale_to` with its working: ``(goal_cells, factor, dropped, rule)``.

    ``factor`` is the scale ``s`` applied to the bitmap (1.0 when it already
    has ``n`` cells), ``dropped`` the number of boundary cells removed after
    scaling to reach exactly ``n``, and ``rule`` the resampling rule used
    (``"nearest"``, or ``"overlap"`` when nearest-neighbour sampling cut the
    shape apart; ``"none"`` at scale 1).

    >>> cells, s, dropped, rule = scale_details({(0, 0), (1, 0), (2, 0)}, 3)
    >>> sorted(cells), s, dropped, rule
    ([(0, 0), (1, 0), (2, 0)], 1.0, 0, 'none')
    >>> cells, s, dropped, rule = scale_details({(0, 0), (1, 0), (2, 0)}, 6)
    >>> sorted(cells), round(s, 6), dropped, rule
    ([(0, 0), (0, 1), (1, 0), (1, 1), (2, 0), (2, 1)], 1.5, 4, 'nearest')
    """
    n = _check_n(n)
    cells = _as_cells(cells)
    if not cells:
        raise UsageError("cells=[] is empty", fix="give at least one goal cell")
    _check_connected(cells, "the shape")
    a, _ = _to_array(cells)
    if len(cells) == n:                        # already n goal pixels: scale 1
        return _from_array(a), 1.0, 0, "none"
    table = np.zeros((a.shape[0] + 1, a.shape[1] + 1), dtype=np.int64)
    table[1:, 1:] = a.cumsum(0).cumsum(1)
    for rule in ("nearest", "overlap"):
        factor = _scale_search(table, a.shape, n, len(cells), rule)
        scaled = _from_array(_resample(table, a.shape, factor, rule))
        if connected(scaled):                  # "nearest" can cut thin parts when shrinking
            break
    else:                                      # cannot happen: "overlap" keeps 4-connectivity
        raise RuntimeError(f"internal: scaling a connected shape by {factor!r} disconnected it")
    dropped = len(scaled) - n
    out = _trim(scaled, dropped)
    if len(out) != n or not connected(out):
        raise RuntimeError(f"internal: trimming left {len(out)} cells, connected={connected(out)}")
    b, _ = _to_array(out)
    return _from_array(b), float(factor), dropped, rule


def scale_to(cells, n: int) -> frozenset:
    """Exactly ``n`` connected goal cells from a connected bitmap, deterministically.

    004 Sec. V-A: "The figure is scaled such that the number of goal pixels
    on the figure equals the number of agents."  The paper does not say how.
    Here (docs/decisions.md, "Wang & Rubenstein shapes (issue 15)"):

    1. if the bitmap has ``n`` cells it is returned (moved to start at (0, 0));
    2. else it is resampled at scale ``s`` by nearest-neighbour sampling (a
       target cell takes the source cell under its centre), with ``s`` the
       end of a bisection on the scale where the filled count first reaches
       ``n``; if that cuts the shape apart (only possible when shrinking), it
       is resampled instead by overlap (a target cell is filled when its
       square, mapped back, overlaps a filled cell), which keeps 4-connectivity;
    3. the surplus (usually a few cells) is removed from the boundary, keeping
       the set connected: fewest filled neighbours first (corners, spurs),
       then farthest from earlier removals, then smallest ``(x, y)``.

    The result starts at ``(0, 0)`` (smallest x and smallest y are 0).

    Raises
    ------
    UsageError
        ``n`` not in ``1..MAX_GOALS``, ``cells`` empty or not 4-connected.

    >>> sorted(scale_to({(0, 0)}, 4))
    [(0, 0), (0, 1), (1, 0), (1, 1)]
    >>> scale_to({(0, 0), (2, 0)}, 4)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: the shape is not connected: ...
    """
    return scale_details(cells, n)[0]


# ----------------------------------------------------------------------------
# files
# ----------------------------------------------------------------------------

def _parse_text(path: str) -> frozenset:
    try:
        size = os.path.getsize(path)
        if size > (MAX_SIDE + 2) * MAX_SIDE:
            raise InputFileError(f"size={size} bytes is too large for a text bitmap (at most {MAX_SIDE} rows of "
                                 f"{MAX_SIDE} cells)", file=path, fix="give a smaller bitmap; it is scaled to the "
                                 "number of robots anyway")
        with open(path, "rb") as fh:
            raw = fh.read()
    except OSError as exc:
        raise InputFileError(f"cannot read the file ({exc.strerror or exc})", file=path) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise InputFileError("the file is not UTF-8 text", file=path, line=line,
                             fix="write the bitmap with '#' and '.' only") from None
    lines = text.split("\n")
    while lines and not lines[-1].strip("\r"):
        lines.pop()
    if len(lines) > MAX_SIDE:
        raise InputFileError(f"rows={len(lines)} is more than MAX_SIDE={MAX_SIDE}", file=path,
                             fix="give a smaller bitmap; it is scaled to the number of robots anyway")
    cells = []
    nrows = len(lines)
    for r, line in enumerate(lines):
        line = line.rstrip("\r")
        if len(line) > MAX_SIDE:
            raise InputFileError(f"columns={len(line)} is more than MAX_SIDE={MAX_SIDE}", file=path, line=r + 1,
                                 fix="give a smaller bitmap; it is scaled to the number of robots anyway")
        for c, ch in enumerate(line):
            if ch == "#":
                cells.append((c, nrows - 1 - r))
            elif ch != ".":
                raise InputFileError(f"column {c + 1}: character {ch!r} is neither '#' (goal cell) nor '.' "
                                     "(free cell)", file=path, line=r + 1,
                                     fix="use only '#' and '.' (no spaces or tabs) in a text bitmap")
    return frozenset(cells)


def _read_png(path: str) -> frozenset:
    try:
        with open(path, "rb") as fh:
            magic = fh.read(8)
    except OSError as exc:
        raise InputFileError(f"cannot read the file ({exc.strerror or exc})", file=path) from None
    if magic != _PNG_MAGIC:
        raise InputFileError("the file is not a PNG image (no PNG signature)", file=path,
                             fix="save the shape as PNG, or as a .txt bitmap of '#' and '.'")
    from PIL import Image   # a dependency of matplotlib, which swarmproof requires

    try:
        with Image.open(path) as img:
            w, h = img.size
            if w > MAX_SIDE or h > MAX_SIDE:
                raise InputFileError(f"size={w}x{h} pixels is more than MAX_SIDE={MAX_SIDE} on a side", file=path,
                                     fix=f"shrink the image to at most {MAX_SIDE} x {MAX_SIDE}; it is scaled to "
                                         "the number of robots anyway")
            if w == 0 or h == 0:
                raise InputFileError(f"size={w}x{h} pixels is empty", file=path, fix="draw the shape")
            if img.mode in ("I;16", "I;16B", "I;16L", "I"):     # 16-bit grey: to 0..255 (exact for 0, 65535)
                grey = np.clip(np.asarray(img, dtype=np.int64), 0, 65535) * 255 // 65535
                lum1000 = grey * 1000
                alpha = np.full(grey.shape, 255, dtype=np.int64)
            else:
                rgba = np.asarray(img.convert("RGBA"), dtype=np.int64)
                lum1000 = 299 * rgba[..., 0] + 587 * rgba[..., 1] + 114 * rgba[..., 2]   # 1000 x luminance
                alpha = rgba[..., 3]
    except InputFileError:
        raise
    except (OSError, ValueError, SyntaxError, Image.DecompressionBombError) as exc:
        raise InputFileError(f"cannot decode the PNG image ({exc})", file=path,
                             fix="re-save it as an ordinary 8-bit PNG") from None
    # composited over white, in integers: (a L + (255 - a) 255) / 255 < DARK_THRESHOLD
    filled = alpha * lum1000 + (255 - alpha) * 255000 < 255 * 1000 * DARK_THRESHOLD   # rows top to bottom
    rows, cols = np.nonzero(filled)
    return frozenset(zip(cols.tolist(), (h - 1 - rows).tolist()))


def _stem(path: str) -> str:
    base = os.path.basename(path)
    return base.rsplit(".", 1)[0] or base


def load_shape_file(path, n: int | None = None, *, spacing: float = DEFAULT_SPACING,
                    name: str | None = None) -> GoalSet:
    """A goal set from a ``.txt`` bitmap or a ``.png`` image, scaled to ``n`` cells if ``n`` is given.

    Parameters
    ----------
    path : str or path-like
        The file: ``.txt`` (``'#'`` goal, ``'.'`` free) or ``.png`` (dark pixel =
        goal, see the module docstring for the threshold and alpha).
    n : int, optional
        Number of robots; the shape is scaled to exactly ``n`` connected cells
        (:func:`scale_to`).  None keeps the file's cells as they are.
    spacing : float
        Grid length l in metres (004 Sec. V-B3: 0.20 m); the goal set's
        recommended range is ``3 l`` (004: R = 0.6 m).
    name : str, optional
        The goal set's name; default the file name without its suffix.

    Raises
    ------
    InputFileError
        Unreadable file, unknown suffix, a bad character (file, line, column),
        too large (``MAX_SIDE``), no filled cell, not 4-connected.
    UsageError
        Bad ``n`` or ``spacing``.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "t.txt")
    >>> _ = open(p, "w").write("###\\n.#.\\n.#.\\n")
    >>> g = load_shape_file(p)
    >>> g.name, sorted(g.cells), g.spacing
    ('t', [(0, 2), (1, 0), (1, 1), (1, 2), (2, 2)], 0.2)
    >>> len(load_shape_file(p, 20).cells)
    20
    >>> _ = open(p, "w").write("#.\\n.x\\n")
    >>> load_shape_file(p)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.InputFileError: ...t.txt:2: column 2: character 'x' is neither '#' (goal cell) nor '.' (free cell); fix: use only '#' and '.' (no spaces or tabs) in a text bitmap
    """
    try:
        path = os.fspath(path)
    except TypeError:
        raise UsageError(f"path={path!r} must be a file path", fix="give a .txt or .png file") from None
    if n is not None:
        n = _check_n(n)
    if isinstance(spacing, bool) or not isinstance(spacing, (int, float)) or not (
            math.isfinite(spacing) and spacing > 0):
        raise UsageError(f"spacing={spacing!r} must be a finite number > 0", fix="e.g. 0.2 (004 Sec. V-B3)")
    suffix = os.path.splitext(path)[1].lower()
    if not os.path.isfile(path):
        raise InputFileError("no such file", file=path, fix="give the path of a .txt bitmap or a .png image")
    if suffix == ".txt":
        cells = _parse_text(path)
        what = "no '#' cell"
        fix = "mark the goal cells with '#'"
    elif suffix == ".png":
        cells = _read_png(path)
        what = f"no dark pixel (luminance below {DARK_THRESHOLD} of 255 over white)"
        fix = "draw the shape in dark pixels on a light or transparent background"
    else:
        raise InputFileError(f"suffix={suffix!r} is not a shape file type", file=path,
                             fix="give a .txt bitmap ('#' and '.') or a .png image")
    if not cells:
        raise InputFileError(f"the shape has {what}: there is no goal cell", file=path, fix=fix)
    _check_connected(cells, "the shape", file=path)
    if n is not None:
        cells = scale_to(cells, n)
    return GoalSet(name or _stem(path), cells, float(spacing), (0.0, 0.0), _range(spacing))


def bundled_shape_names() -> list:
    """Names of the shape bitmaps in ``models/shape_bitmaps/``.

    >>> bundled_shape_names()
    ['letter-n', 'letter-u']
    """
    return sorted(p.stem for p in _BITMAP_DIR.glob("*.txt") if p.is_file())


def bundled_shape(name: str, n: int | None = None, *, spacing: float = DEFAULT_SPACING) -> GoalSet:
    """A bundled shape by name (one of :func:`bundled_shape_names` or the small
    ``square-9`` / ``letter-l`` of ``_BUNDLED_SHAPES``), scaled to ``n`` cells if given."""
    if name in bundled_shape_names():
        return load_shape_file(_BITMAP_DIR / f"{name}.txt", n, spacing=spacing, name=name)
    if name in _BUNDLED_SHAPES:
        g = _BUNDLED_SHAPES[name]()
        if n is None and spacing == g.spacing:
            return g
        cells = g.cells if n is None else scale_to(g.cells, n)
        return GoalSet(name, cells, float(spacing), (0.0, 0.0), _range(spacing))
    names = sorted(set(bundled_shape_names()) | set(_BUNDLED_SHAPES))
    raise UsageError(f"shape={name!r} is neither a file nor a bundled shape",
                     fix=f"give a .txt or .png file or one of {names!r}")


def shape_for(name_or_path, n: int, *, spacing: float = DEFAULT_SPACING) -> GoalSet:
    """The goal set for ``n`` robots: a bundled shape's name or a ``.txt`` / ``.png`` path (an
    existing file wins), scaled to exactly ``n`` connected cells (004 Sec. V-A).

    >>> len(shape_for("letter-u", 100).cells), len(shape_for("square-9", 9).cells)
    (100, 9)
    >>> shape_for("letter-q", 10)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: shape='letter-q' is neither a file nor a bundled shape; fix: give a .txt or .png file or one of ['letter-l', 'letter-n', 'letter-u', 'square-9']
    """
    n = _check_n(n)
    try:
        text = os.fspath(name_or_path)
    except TypeError:
        raise UsageError(f"shape={name_or_path!r} must be a name or a path") from None
    if text.startswith("shape:") and not os.path.exists(text):
        text = text[len("shape:"):]
    if os.path.exists(text):
        return load_shape_file(text, n, spacing=spacing)
    return bundled_shape(text, n, spacing=spacing)


def random_shape(n: int, rng: np.random.Generator, *, spacing: float = DEFAULT_SPACING,
                 name: str = "random-connected") -> GoalSet:
    """A random connected goal set of ``n`` cells (004 Sec. V-A, Figs. 10-12: "the target shape is
    randomly generated as a set of connected random positions").

    Grown from ``(0, 0)``: each next cell is drawn uniformly from the free
    4-neighbours of the cells so far (an Eden cluster); the paper does not
    say how it draws its shapes (docs/decisions.md).

    >>> g = random_shape(30, np.random.default_rng(1))
    >>> len(g.cells), connected(g.cells), g == random_shape(30, np.random.default_rng(1))
    (30, True, True)
    """
    n = _check_n(n)
    if not isinstance(rng, np.random.Generator):
        raise UsageError(f"rng={rng!r} must be a numpy.random.Generator", fix="pass np.random.default_rng(seed)")
    cells = {(0, 0)}
    frontier = [(1, 0), (0, 1), (-1, 0), (0, -1)]
    in_frontier = set(frontier)
    while len(cells) < n:
        k = int(rng.integers(len(frontier)))
        c = frontier[k]
        frontier[k] = frontier[-1]
        frontier.pop()
        in_frontier.discard(c)
        cells.add(c)
        for dx, dy in _FOUR:
            d = (c[0] + dx, c[1] + dy)
            if d not in cells and d not in in_frontier:
                frontier.append(d)
                in_frontier.add(d)
    a, _ = _to_array(frozenset(cells))
    return GoalSet(name, _from_array(a), float(spacing), (0.0, 0.0), _range(spacing))


# ----------------------------------------------------------------------------
# arenas and random starts (004 Sec. V-A)
# ----------------------------------------------------------------------------

def arena_cells(width: int = DEFAULT_ARENA[0], height: int | None = None, *, origin=(0, 0)) -> frozenset:
    """The waypoints of a rectangular arena: ``width x height`` cells from ``origin``.

    004 Sec. V-A: "the swarm moved in a fixed-size arena" whose number of
    vertices bounds the swarm; its size is not given (``DEFAULT_ARENA``,
    32 x 32, is our choice: docs/decisions.md).

    >>> len(arena_cells(4, 3)), min(arena_cells(4, 3, origin=(-2, -1)))
    (12, (-2, -1))
    """
    height = width if height is None else height
    for nm, v in (("width", width), ("height", height)):
        check_type(nm, v, (int, np.integer), fix="give the arena size in grid cells")
        if not 1 <= v <= MAX_SIDE:
            raise UsageError(f"{nm}={v!r} is outside 1..{MAX_SIDE}", fix="give the arena size in grid cells")
    ox, oy = (int(origin[0]), int(origin[1]))
    return frozenset((ox + i, oy + j) for i in range(int(width)) for j in range(int(height)))


def centered_arena(goal_cells, width: int, height: int | None = None) -> frozenset:
    """A ``width x height`` arena whose centre is the goal set's centre of mass (rounded to a cell):
    004 Sec. V-A's runs for Fig. 11, where agents "are initialized with a uniform random
    distribution centered at the shape's center of mass".

    >>> a = centered_arena({(10, 10), (11, 10), (12, 10)}, 3)
    >>> min(a), max(a)
    ((10, 9), (12, 11))
    """
    cells = _as_cells(goal_cells, "goal_cells")
    if not cells:
        raise UsageError("goal_cells=[] is empty", fix="give the goal set")
    height = width if height is None else height
    cx = sum(c[0] for c in cells) / len(cells)
    cy = sum(c[1] for c in cells) / len(cells)
    ox = int(math.floor(cx - (width - 1) / 2.0 + 0.5))
    oy = int(math.floor(cy - (height - 1) / 2.0 + 0.5))
    return arena_cells(width, height, origin=(ox, oy))


def _arena_label(arena: frozenset) -> str:
    xs = [c[0] for c in arena]
    ys = [c[1] for c in arena]
    w, h = max(xs) - min(xs) + 1, max(ys) - min(ys) + 1
    return f"{w}x{h}" if w * h == len(arena) else f"{len(arena)} cells"


def random_start_cells(n: int, arena=DEFAULT_ARENA, rng: np.random.Generator | None = None, *,
                       exclude: Iterable = ()) -> list:
    """``n`` distinct start cells drawn uniformly (without replacement) from the arena.

    004 Sec. V-A: agents start from "a random initialization" in a fixed-size
    arena; Fig. 11's runs draw "a uniform random distribution centered at the
    shape's center of mass" (use :func:`centered_arena`).  Start cells may be
    goal cells.  Robot ``k`` starts at the ``k``-th cell returned.

    Parameters
    ----------
    n : int
        Number of robots.
    arena : (width, height) or set of cells
        The arena; a pair makes :func:`arena_cells` from ``(0, 0)``.
    rng : numpy.random.Generator
        The only source of randomness (required).
    exclude : cells
        Cells no robot may start on.

    Raises
    ------
    UsageError
        More robots than the arena holds (naming ``n`` and the arena), or no ``rng``.

    >>> random_start_cells(3, (4, 4), np.random.default_rng(0)) == random_start_cells(3, (4, 4), np.random.default_rng(0))
    True
    >>> random_start_cells(17, (4, 4), np.random.default_rng(0))
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: n=17 robots is more than the arena=4x4 holds (16 free cells); fix: give at most 16 robots or a larger arena
    """
    check_type("n", n, (int, np.integer), fix="give the number of robots as a whole number")
    if n < 1:
        raise UsageError(f"n={n!r} must be >= 1", fix="ask for at least one robot")
    if not isinstance(rng, np.random.Generator):
        raise UsageError(f"rng={rng!r} must be a numpy.random.Generator", fix="pass np.random.default_rng(seed)")
    if isinstance(arena, tuple) and len(arena) == 2 and all(isinstance(v, (int, np.integer)) for v in arena):
        cells = arena_cells(int(arena[0]), int(arena[1]))
    else:
        cells = _as_cells(arena, "arena")
        if not cells:
            raise UsageError("arena=[] is empty", fix="give (width, height) or a set of cells")
    label = _arena_label(cells)
    free = sorted(cells - _as_cells(exclude, "exclude"))
    if n > len(free):
        raise UsageError(f"n={n} robots is more than the arena={label} holds ({len(free)} free cells)",
                         fix=f"give at most {len(free)} robots or a larger arena")
    pick = rng.choice(len(free), size=int(n), replace=False)
    return [free[int(i)] for i in pick]
