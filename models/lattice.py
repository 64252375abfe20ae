"""Lattice graphs (Definition 1 of 001 and of 000).

A lattice graph is a directed multigraph whose edges carry rigid body
transforms: an edge ``u -T-> w`` says "a robot in role ``w`` stands at pose
``T`` in the body frame of a robot in role ``u``".  It is stored as a
``networkx.MultiDiGraph`` whose edge keys are the edge indices and whose
edge attribute ``transform`` is an :class:`~swarmproof.models.se2.SE2`.

Order matters and is kept: ``roles[0]`` is v0 (the role a root takes,
000 Sec. IV-B), and :meth:`LatticeGraph.out_edges` yields a role's
out-edges in the order they were given (it orders vacancies, 001 Def. 9).
networkx alone groups multi-edges by neighbor, so the order is kept in
:attr:`LatticeGraph.edges` and the graph is a view for graph algorithms.

This module only *represents* graphs; whether one is valid or
self-consistent is decided by :mod:`swarmproof.checkers.lattice_check`.

References
----------
001_7a4e517b856331bc.txt, Sec. III-B, Definitions 1-4.
000_3ad33c5b62f11d5f.txt, Sec. III-B, Definitions 1-2, Figs. 2, 3, 7, 11.

Examples
--------
>>> g = LatticeGraph("square", ["A"], [("A", "A", SE2(1, 0, 0)), ("A", "A", SE2(0, 1, 0)),
...                                    ("A", "A", SE2(-1, 0, 0)), ("A", "A", SE2(0, -1, 0))],
...                  range=1.2)
>>> g.v0, len(g.edges), [e.index for e in g.out_edges("A")]
('A', 4, [0, 1, 2, 3])
>>> g.find_inverse(g.edges[0]).index
2
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable, Iterator, Sequence

import networkx as nx

from .errors import UsageError, check_positive
from .se2 import DEFAULT_ANG_TOL, DEFAULT_POS_TOL, SE2

__all__ = ["Edge", "LatticeGraph"]


@dataclass(frozen=True, slots=True)
class Edge:
    """One labelled edge ``source -transform-> target``.

    Attributes
    ----------
    index : int
        Position in the graph's edge list (``edges[index]`` in the file).
    source, target : str
        Role names.
    transform : SE2
        Pose of ``target`` in the body frame of ``source``.
    """

    index: int
    source: str
    target: str
    transform: SE2

    def as_row(self, angle_unit: str = "deg") -> list:
        """The file row ``[from, to, x, y, theta]`` (theta in ``angle_unit``)."""
        th = math.degrees(self.transform.theta) if angle_unit == "deg" else self.transform.theta
        return [self.source, self.target, self.transform.x, self.transform.y, th]

    def describe(self) -> str:
        """Human form, e.g. ``edges[2]: A -> B (1, 0, 90deg)``."""
        t = self.transform
        return (f"edges[{self.index}]: {self.source} -> {self.target} "
                f"({_fmt(t.x)}, {_fmt(t.y)}, {_fmt(math.degrees(t.theta))}deg)")


def _fmt(x: float) -> str:
    r = round(x, 9)
    if r == 0:
        r = 0.0
    return f"{r:.6g}"


class LatticeGraph:
    """A lattice graph: roles (vertices) and SE(2)-labelled directed edges.

    Parameters
    ----------
    name : str
        A name for reports.
    roles : sequence of str
        Role names, unique; ``roles[0]`` is v0.
    edges : iterable of (str, str, SE2)
        ``(from, to, transform)`` triples, in order.
    range : float, optional
        A recommended/default sensing range phi (the file's ``range``).
    source : str, optional
        Where the graph came from (file path or ``library:NAME``), for messages.

    Raises
    ------
    UsageError
        Empty role list, duplicate or non-string role names, an edge naming
        an unknown role, a transform that is not an :class:`SE2`, or a
        non-positive range.  Messages name the field, e.g. ``edges[3][1]``.
    """

    #: The unit the source file wrote its angles in (``deg`` or ``rad``; set by the file reader):
    #: a checker's suggested rows are printed in it.
    angle_unit: str = "deg"

    def __init__(self, name: str, roles: Sequence[str], edges: Iterable[tuple[str, str, SE2]],
                 range: float | None = None, source: str | None = None) -> None:
        self.name = str(name)
        self.source = source
        roles = list(roles)
        if not roles:
            raise UsageError("roles=[] is empty", fix="list at least one role; the first is v0")
        seen: set[str] = set()
        for i, r in enumerate(roles):
            if not isinstance(r, str) or not r:
                raise UsageError(f"roles[{i}]={r!r} must be a non-empty string")
            if r in seen:
                raise UsageError(f"roles[{i}]={r!r} is listed twice", fix="give each role once")
            seen.add(r)
        self.roles: tuple[str, ...] = tuple(roles)
        self.range: float | None = None if range is None else check_positive("range", range)
        self._edges: list[Edge] = []
        self._out: dict[str, list[Edge]] = {r: [] for r in self.roles}
        self.graph = nx.MultiDiGraph(name=self.name)
        self.graph.add_nodes_from(self.roles)
        for i, e in enumerate(edges):
            try:
                u, w, t = e
            except (TypeError, ValueError):
                raise UsageError(f"edges[{i}]={e!r} must be a (from, to, transform) triple") from None
            for j, r in ((0, u), (1, w)):
                if r not in self._out:
                    raise UsageError(f"edges[{i}][{j}]={r!r} is not a declared role",
                                     fix=f"use one of roles={list(self.roles)!r} or add it to roles")
            if not isinstance(t, SE2):
                raise UsageError(f"edges[{i}] transform={t!r} must be an SE2")
            edge = Edge(i, u, w, t)
            self._edges.append(edge)
            self._out[u].append(edge)
            self.graph.add_edge(u, w, key=i, transform=t)

    # -- access ---------------------------------------------------------
    @property
    def v0(self) -> str:
        """The first role: the role a root takes (000 Sec. IV-B)."""
        return self.roles[0]

    @property
    def edges(self) -> tuple[Edge, ...]:
        """All edges in the given order."""
        return tuple(self._edges)

    def out_edges(self, role: str) -> list[Edge]:
        """Out-edges of ``role`` in the given order (this order ranks vacancies)."""
        try:
            return list(self._out[role])
        except KeyError:
            raise UsageError(f"role={role!r} is not a role of lattice {self.name!r}",
                             fix=f"use one of {list(self.roles)!r}") from None

    def role_index(self, role: str) -> int:
        """Index of ``role`` in :attr:`roles`."""
        try:
            return self.roles.index(role)
        except ValueError:
            raise UsageError(f"role={role!r} is not a role of lattice {self.name!r}",
                             fix=f"use one of {list(self.roles)!r}") from None

    def __len__(self) -> int:
        return len(self._edges)

    def __iter__(self) -> Iterator[Edge]:
        return iter(self._edges)

    def __repr__(self) -> str:
        return (f"LatticeGraph(name={self.name!r}, roles={len(self.roles)}, "
                f"edges={len(self._edges)}, range={self.range!r})")

    # -- queries ----------------------------------------------------------
    def find_edge(self, source: str, target: str, transform: SE2,
                  pos_tol: float = DEFAULT_POS_TOL, ang_tol: float = DEFAULT_ANG_TOL) -> Edge | None:
        """The first edge ``source -> target`` whose transform equals ``transform``
        within the tolerances, or ``None``."""
        for e in self._out.get(source, ()):
            if e.target == target and e.transform.isclose(transform, pos_tol, ang_tol):
                return e
        return None

    def find_inverse(self, edge: Edge, pos_tol: float = DEFAULT_POS_TOL,
                     ang_tol: float = DEFAULT_ANG_TOL) -> Edge | None:
        """The inverse edge ``target -T^-1-> source`` of Definition 1, or ``None``."""
        return self.find_edge(edge.target, edge.source, edge.transform.inverse(), pos_tol, ang_tol)

    def max_edge_length(self) -> float:
        """Longest translation among the edges (0 for an edgeless graph)."""
        return max((e.transform.norm() for e in self._edges), default=0.0)

    # -- derived graphs -----------------------------------------------------
    def with_edges(self, extra: Iterable[tuple[str, str, SE2]], name: str | None = None) -> "LatticeGraph":
        """A new graph with ``extra`` edges appended (existing order kept)."""
        rows = [(e.source, e.target, e.transform) for e in self._edges] + list(extra)
        return LatticeGraph(name or self.name, self.roles, rows, range=self.range, source=self.source)

    def without_edges(self, indices: Iterable[int], name: str | None = None) -> "LatticeGraph":
        """A new graph without the edges whose indices are given (re-indexed)."""
        drop = set(indices)
        rows = [(e.source, e.target, e.transform) for e in self._edges if e.index not in drop]
        return LatticeGraph(name or self.name, self.roles, rows, range=self.range, source=self.source)

    def add_inverses(self, pos_tol: float = DEFAULT_POS_TOL,
                     ang_tol: float = DEFAULT_ANG_TOL) -> "LatticeGraph":
        """A new graph with every missing inverse edge (Definition 1) appended.

        Edges are otherwise exactly as given (DESIGN.md section 2): this helper
        runs only on request.

        >>> g = LatticeGraph("half", ["A"], [("A", "A", SE2(1, 0, 0))])
        >>> [e.describe() for e in g.add_inverses().edges]
        ['edges[0]: A -> A (1, 0, 0deg)', 'edges[1]: A -> A (-1, 0, 0deg)']
        """
        out = self
        for e in self._edges:
            if out.find_inverse(e, pos_tol, ang_tol) is None:
                out = out.with_edges([(e.target, e.source, e.transform.inverse())])
        return out

    def __eq__(self, other: object) -> bool:
        """Structural equality: same name, roles, range and edges (exact floats)."""
        if not isinstance(other, LatticeGraph):
            return NotImplemented
        return (self.name == other.name and self.roles == other.roles and self.range == other.range
                and [(e.source, e.target, e.transform) for e in self._edges]
                == [(e.source, e.target, e.transform) for e in other._edges])

    __hash__ = None  # mutable-looking container; compare with == only

    # -- as a target (models/targets.py) -----------------------------------
    #: The target kind (:mod:`swarmproof.models.targets`).
    kind = "lattice"

    def _phi(self, phi):
        phi = self.range if phi is None else phi
        if phi is None:
            raise UsageError(f"lattice {self.name!r} has no range and none was given", fix="pass phi=PHI")
        return float(phi)

    def satisfied(self, ids, poses, *, phi: float | None = None, tol=None):
        """001 Def. 2 (000 Def. 2): do the robots satisfy the graph at range ``phi``?

        ``tol`` is ``(pos_tol, ang_tol)`` (default 1e-6 each).  Returns a
        :class:`~swarmproof.models.target_base.TargetCheck` whose ``detail`` holds the
        role of each robot when it held.

        >>> from swarmproof.models import library
        >>> sq = library.load("square")
        >>> sq.satisfied([1, 2], [[0, 0, 0], [1, 0, 0]]).status
        'held'
        """
        from .satisfaction import DEFAULT_SAT_ANG_TOL, DEFAULT_SAT_POS_TOL, satisfies_lattice
        from .target_base import TargetCheck

        pos_tol, ang_tol = (DEFAULT_SAT_POS_TOL, DEFAULT_SAT_ANG_TOL) if tol is None else tol
        sat = satisfies_lattice(ids, poses, self, self._phi(phi), pos_tol=pos_tol, ang_tol=ang_tol)
        return TargetCheck(sat.status, sat.message, sat.cites, sat.witness,
                           {"roles": {str(k): v for k, v in sat.roles.items()}} if sat.held and sat.roles else {})

    def progress(self, ids, poses, *, phi: float | None = None) -> float:
        """Q (001 Sec. III-C-2) when the robots satisfy the graph, else 0."""
        from .satisfaction import fulfillment_ratio

        q = fulfillment_ratio(ids, poses, self, self._phi(phi))
        return 0.0 if q is None else q

    def metrics(self, ids, poses, *, phi: float | None = None) -> dict:
        """``fulfillment_ratio`` Q (001 Sec. III-C-2) and ``non_fulfillment_ratio`` (000 Eq. 3);
        None when the configuration does not satisfy the graph (roles undefined)."""
        from .satisfaction import fulfillment_ratio, non_fulfillment_ratio

        phi = self._phi(phi)
        return {"fulfillment_ratio": fulfillment_ratio(ids, poses, self, phi),
                "non_fulfillment_ratio": non_fulfillment_ratio(ids, poses, self, phi)}

    def describe(self) -> dict:
        """``{"kind": "lattice", "name"}`` for a bundled lattice; a user's graph also carries its
        whole lattice-graph/1 document (radians), so a counterexample replays without the file."""
        src = self.source or ""
        if src.startswith("library:") and src[len("library:"):] == self.name:
            return {"kind": "lattice", "name": self.name}
        from .lattice_document import lattice_to_document

        return {"kind": "lattice", "name": self.name, "document": lattice_to_document(self, "rad")}
