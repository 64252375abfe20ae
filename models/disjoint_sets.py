"""Disjoint sets (union-find) over ``0..n-1``: the one implementation the connectivity of a
communication graph (:func:`swarmproof.models.sensing.components`) and the lattice checker's
duplicate groups (``checkers/lattice_check.py``) share.

>>> ds = DisjointSets(5)
>>> ds.union(3, 1); ds.union(4, 3)
>>> ds.find(4), ds.groups()
(1, [[0], [1, 3, 4], [2]])
"""

from __future__ import annotations

__all__ = ["DisjointSets"]


class DisjointSets:
    """Union-find with path halving; the root of a set is its smallest index, so :meth:`groups`
    lists each set in index order and the sets by their smallest index."""

    __slots__ = ("parent",)

    def __init__(self, n: int) -> None:
        self.parent = list(range(n))

    def find(self, a: int) -> int:
        parent = self.parent
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    def union(self, a: int, b: int) -> None:
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            self.parent[max(ra, rb)] = min(ra, rb)

    def groups(self) -> list[list[int]]:
        out: dict[int, list[int]] = {}
        for idx in range(len(self.parent)):
            out.setdefault(self.find(idx), []).append(idx)
        return list(out.values())
