"""Who is a neighbor of whom: the one definition the engine and the invariants share.

Two robots are *neighbors* when the Euclidean distance between their
positions, computed as ``numpy.hypot(dx, dy)``, is strictly less than the
range phi (001 Sec. III-A; strict by docs/decisions.md "Model and
geometry").  :func:`neighbor_pairs` finds candidates with
``scipy.spatial.cKDTree.query_pairs`` (ndarray output, DESIGN.md section 4)
on a slightly inflated radius (or, up to 50 robots, takes every pair, which
is faster there), then keeps exactly the pairs with ``hypot < phi``, so the engine's sensing, the connectivity invariant and
the satisfaction check can never disagree by a rounding error.

References
----------
001_7a4e517b856331bc.txt (Song & O'Kane 2016), Sec. III-A (range, neighbors).

Examples
--------
>>> import numpy as np
>>> xy = np.array([[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]])
>>> i, j, d = neighbor_pairs(xy, 1.5)
>>> i.tolist(), j.tolist(), d.tolist()
([0], [1], [1.0])
>>> components(3, i, j)
[[0, 1], [2]]
>>> is_connected(xy, 2.0), is_connected(xy, 2.5)
(False, True)
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from swarmproof.models.disjoint_sets import DisjointSets

__all__ = ["neighbor_pairs", "components", "is_connected", "pair_distances"]

#: Candidate radius inflation: cKDTree's own arithmetic may differ from hypot
#: in the last bits; candidates are filtered exactly afterwards.
_INFLATE = 1.0 + 1e-9

#: Up to this many robots, all pairs are candidates (no tree).
_BRUTE_MAX = 50

_TRIU: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _triu(n: int):
    """Index pairs ``i < j`` of ``0..n-1`` in lexicographic order (cached, read-only)."""
    got = _TRIU.get(n)
    if got is None:
        i, j = np.triu_indices(n, 1)
        i = i.astype(np.intp)
        j = j.astype(np.intp)
        i.setflags(write=False)
        j.setflags(write=False)
        got = _TRIU[n] = (i, j)
    return got


def pair_distances(xy: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """``hypot`` distances between rows ``i`` and ``j`` of ``xy`` (the canonical distance)."""
    d = xy[j] - xy[i]
    return np.hypot(d[:, 0], d[:, 1])


#: ``inclusive`` ("at most phi") admits a relative rounding slack of 1e-12: grid robots exactly R apart
#: (004: 3 cells of l = 0.2 m at R = 0.6 m) are neighbours although 0.4 - (-0.2) = 0.6000000000000001.
INCLUSIVE_SLACK = 1.0 + 1e-12


def neighbor_pairs(xy, phi: float, inclusive: bool = False):
    """All unordered neighbor pairs ``i < j`` with distance strictly below ``phi``
    (``inclusive``: at most ``phi``, for models that declare ``neighbor_rule="inclusive"``,
    e.g. 004's ``<= R``).

    Parameters
    ----------
    xy : array_like, shape (n, 2)
        Positions (the first two columns of poses are accepted too).
    phi : float
        The range.

    Returns
    -------
    i, j : numpy.ndarray of int, shape (m,)
        Row indices, ``i < j``, sorted lexicographically by ``(i, j)``.
    d : numpy.ndarray of float, shape (m,)
        Their distances.
    """
    xy = np.asarray(xy, dtype=float)
    if xy.ndim == 2 and xy.shape[1] > 2:
        xy = xy[:, :2]
    n = len(xy)
    if n < 2:
        e = np.empty(0, dtype=np.intp)
        return e, e.copy(), np.empty(0)
    if n <= _BRUTE_MAX:
        # small swarms: every pair is a candidate (cheaper than building a tree);
        # the exact filter below makes the result identical to the tree's.
        iu, ju = _triu(n)
        d = pair_distances(xy, iu, ju)
        keep = d <= phi * INCLUSIVE_SLACK if inclusive else d < phi
        return iu[keep], ju[keep], d[keep]
    pairs = cKDTree(xy).query_pairs(r=float(phi) * _INFLATE, output_type="ndarray")
    if len(pairs) == 0:
        e = np.empty(0, dtype=np.intp)
        return e, e.copy(), np.empty(0)
    pairs = np.sort(pairs.astype(np.intp), axis=1)
    order = np.lexsort((pairs[:, 1], pairs[:, 0]))
    pairs = pairs[order]
    d = pair_distances(xy, pairs[:, 0], pairs[:, 1])
    keep = d <= phi * INCLUSIVE_SLACK if inclusive else d < phi
    return pairs[keep, 0], pairs[keep, 1], d[keep]


#: Up to this many edges :func:`components` joins them in plain Python (union-find): building a
#: scipy sparse matrix costs about 1.7 ms whatever the size, which was half of an exploration of
#: song2016 at 3-8 robots (its connectivity monitor asks every step).  The result is the same.
_UNION_FIND_MAX_EDGES = 2000


def _components_union_find(n: int, i: list, j: list) -> list[list[int]]:
    """:func:`components` by :class:`~swarmproof.models.disjoint_sets.DisjointSets` (the root of a
    set is its smallest index, so the groups come sorted and ordered by their smallest index)."""
    sets = DisjointSets(n)
    for a, b in zip(i, j):
        if not (0 <= a < n and 0 <= b < n):
            raise ValueError(f"edge ({a}, {b}) names a vertex outside 0..{n - 1}")
        sets.union(a, b)
    return sets.groups()


def components(n: int, i, j) -> list[list[int]]:
    """Connected components of the graph on ``0..n-1`` with edges ``(i[k], j[k])``.

    Each component is a sorted list of indices; components are ordered by their
    smallest index.
    """
    if n == 0:
        return []
    i = np.asarray(i, dtype=np.intp)
    j = np.asarray(j, dtype=np.intp)
    if len(i) <= _UNION_FIND_MAX_EDGES:
        return _components_union_find(n, i.tolist(), j.tolist())
    g = coo_matrix((np.ones(len(i), dtype=np.int8), (i, j)), shape=(n, n))
    _, labels = connected_components(g, directed=False)
    groups: dict[int, list[int]] = {}
    for idx, lab in enumerate(labels.tolist()):
        groups.setdefault(lab, []).append(idx)
    return sorted(groups.values(), key=lambda c: c[0])


def is_connected(xy, phi: float) -> bool:
    """Whether the communication graph (neighbors strictly closer than ``phi``) is connected.

    An empty or one-robot configuration counts as connected.
    """
    xy = np.asarray(xy, dtype=float)
    n = len(xy)
    if n <= 1:
        return True
    i, j, _ = neighbor_pairs(xy, phi)
    if len(i) < n - 1:
        return False
    return len(components(n, i, j)) == 1
