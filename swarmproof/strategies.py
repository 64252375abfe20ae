"""Hypothesis strategies for lattice graphs and lattice files (public API).

Use them in your own property tests::

    from hypothesis import given
    from swarmproof.strategies import periodic_lattices

    @given(periodic_lattices())
    def test_my_algorithm_handles_any_lattice(graph):
        ...

* :func:`periodic_lattices` -- a random periodic point pattern (a 2-D lattice
  basis plus a motif of 1-4 roles with random headings) and a range phi; the
  lattice graph has **exactly** the edges between every pair of pattern points
  closer than phi, so it is valid and self-consistent for phi
  (001 Defs. 1 and 4) by construction.
* :func:`finite_lattices` -- a random finite formation (each robot its own
  role), connected at phi, with an edge between every pair closer than phi.
* :func:`lattice_graph_documents` -- valid ``lattice-graph/1`` documents
  (plain dicts; well-formed files, not necessarily self-consistent graphs).
* :func:`mutated_lattice_documents` -- invalid documents for fuzzing a loader:
  every one breaks the format in one documented way.

The edges are enumerated here, independently of the checker
(:mod:`swarmproof.checkers.lattice_check`), so these strategies can serve as
its oracle: geometry first (points and headings), graph second.

Ranges are never drawn close to a pair distance: phi is placed strictly
inside a gap between consecutive distinct distances, at least
``min_gap / 10`` away from both ends, so tolerance choices cannot change
which pairs are neighbors.

References
----------
001_7a4e517b856331bc.txt, Sec. III-B, Definitions 1-4 (lattice graph,
endpoint transformation, self-consistency for phi).

Examples
--------
>>> from hypothesis import given, settings
>>> @settings(max_examples=5, database=None, derandomize=True)
... @given(periodic_lattices())
... def check(g):
...     assert g.range > 0 and len(g.edges) > 0
...     assert all(g.find_inverse(e) is not None for e in g.edges)
>>> check()
"""

from __future__ import annotations

import math
import string
from typing import Any

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

from swarmproof.models.lattice import LatticeGraph
from swarmproof.models.lattice_io import ALLOWED_KEYS, FORMAT
from swarmproof.models.se2 import SE2, wrap_angle

__all__ = [
    "periodic_lattices",
    "finite_lattices",
    "lattice_graph_documents",
    "mutated_lattice_documents",
    "MUTATION_KINDS",
    "SCHEMA_BLIND_KINDS",
    "lattice_from_points",
    "sample_pattern",
    "bounded_defects",
]

_ROLE_NAMES = string.ascii_uppercase
_TIE = 1e-9  # distances closer than this count as one distance


def _transform(p_from, th_from: float, p_to, th_to: float) -> SE2:
    """Pose of ``(p_to, th_to)`` in the body frame of ``(p_from, th_from)`` (001 Def. 2)."""
    dx, dy = p_to[0] - p_from[0], p_to[1] - p_from[1]
    c, s = math.cos(th_from), math.sin(th_from)
    return SE2(c * dx + s * dy, -s * dx + c * dy, wrap_angle(th_to - th_from))


def _groups(dists: np.ndarray) -> list[float]:
    """Sorted distinct distances (values within ``_TIE`` merged; the largest kept)."""
    out: list[float] = []
    for d in np.sort(dists):
        if out and d - out[-1] <= _TIE:
            out[-1] = float(d)
        else:
            out.append(float(d))
    return out


def _choose_range(draw, groups: list[float], k_min: int, extra: int, min_gap: float,
                  tail: float | None) -> tuple[int, float]:
    """Pick a group index ``k >= k_min`` (at most ``extra`` further) and phi strictly
    inside ``(groups[k], groups[k + 1])``; ``tail`` is the gap allowed after the last group."""
    ks = []
    for k in range(k_min, min(k_min + extra + 1, len(groups))):
        gap = (groups[k + 1] - groups[k]) if k + 1 < len(groups) else tail
        if gap is not None and gap >= min_gap:
            ks.append((k, gap))
    assume(ks)
    k, gap = draw(st.sampled_from(ks))
    u = draw(st.floats(0.1, 0.9))
    return k, groups[k] + u * gap


def lattice_from_points(points, headings, roles, pairs, rng: float, name: str,
                        source: str) -> LatticeGraph:
    """Build a lattice graph from explicit neighbor pairs.

    Parameters
    ----------
    points : sequence of (x, y)
        The role positions (one per role).
    headings : sequence of float
        Role headings in radians.
    roles : sequence of str
    pairs : iterable of (i, j, (dx, dy))
        ``role i`` sees ``role j`` at global position ``points[j] + (dx, dy)``.
    rng : float
        The range phi stored on the graph.

    Edges are ordered by source role, then by distance, bearing in the
    source's frame, target role and offset: a deterministic order.
    """
    rows = []
    for i, j, off in pairs:
        q = (points[j][0] + off[0], points[j][1] + off[1])
        t = _transform(points[i], headings[i], q, headings[j])
        key = (i, round(math.hypot(t.x, t.y), 9), round(math.atan2(t.y, t.x), 9), j,
               round(off[0], 9), round(off[1], 9))
        rows.append((key, (roles[i], roles[j], t)))
    rows.sort(key=lambda r: r[0])
    return LatticeGraph(name, roles, [r[1] for r in rows], range=rng, source=source)


def _draw_basis(draw, min_angle_deg: float, max_aspect: float) -> tuple[np.ndarray, float]:
    """Draw the lattice vectors: ``a1 = (cos alpha, sin alpha)`` and ``a2`` of length ``r2`` in
    ``[1, max_aspect]`` at an angle in ``[min_angle_deg, 180 - min_angle_deg]`` to ``a1``.

    Returns
    -------
    (basis, r2) : (numpy.ndarray, float)
        ``basis`` has columns ``a1``, ``a2`` (cell ``n`` is at ``basis @ n``).
    """
    alpha = draw(st.floats(-math.pi, math.pi))
    beta = math.radians(draw(st.floats(min_angle_deg, 180.0 - min_angle_deg)))
    r2 = draw(st.floats(1.0, max_aspect))
    a1 = np.array([math.cos(alpha), math.sin(alpha)])
    a2 = r2 * np.array([math.cos(alpha + beta), math.sin(alpha + beta)])
    return np.column_stack([a1, a2]), r2


def _draw_motif(draw, basis: np.ndarray, max_roles: int, min_separation: float) -> list[np.ndarray]:
    """Draw 1 to ``max_roles`` points in the cell; each is kept only if it is at least
    ``min_separation`` from every point kept so far and their periodic images."""
    k = draw(st.integers(1, max_roles))
    near = [np.array([u, v]) for u in range(-2, 3) for v in range(-2, 3)]
    pts: list[np.ndarray] = []
    for _ in range(k):
        f = np.array([draw(st.floats(0.0, 1.0, exclude_max=True)),
                      draw(st.floats(0.0, 1.0, exclude_max=True))])
        p = basis @ f
        if all(np.linalg.norm(p + basis @ n - q) >= min_separation for q in pts for n in near):
            pts.append(p)
    return pts


def _candidate_pairs(pts: list[np.ndarray], basis: np.ndarray, r2: float) -> list[tuple]:
    """Every pair ``(dist, i, j, n)``: the point of role ``j`` in cell ``n`` at distance ``dist``
    (below ``L = 2 max(1, r2) + 1``, not 0) from the point of role ``i`` in cell 0; complete for
    that ``L``, sorted by distance, then ``i``, ``j``, ``n``."""
    k = len(pts)
    lmax = max(1.0, r2)
    big = 2.0 * lmax + 1.0
    dual = np.linalg.inv(basis)  # rows b_k: n_k = b_k . (q - (p_j - p_i))
    reach = big + np.linalg.norm(basis[:, 0]) + np.linalg.norm(basis[:, 1])
    nb = [int(math.ceil(np.linalg.norm(dual[r]) * reach)) + 1 for r in range(2)]
    grid = np.array([(u, v) for u in range(-nb[0], nb[0] + 1) for v in range(-nb[1], nb[1] + 1)])
    cand = []  # (dist, i, j, n)
    for i in range(k):
        for j in range(k):
            q = pts[j][None, :] + grid @ basis.T - pts[i][None, :]
            d = np.hypot(q[:, 0], q[:, 1])
            for idx in np.nonzero((d < big) & (d > 1e-12))[0]:
                cand.append((float(d[idx]), i, j, (int(grid[idx, 0]), int(grid[idx, 1]))))
    cand.sort(key=lambda c: (c[0], c[1], c[2], c[3]))
    return cand


def _connecting_distance(cand: list[tuple], k: int) -> float | None:
    """The smallest distance at which the infinite pattern of ``k`` roles is connected, from the
    sorted candidate pairs: a Kruskal pass with cell potentials that also tracks the
    translations of closed walks, which must generate the whole lattice (gcd 1), not a
    sub-lattice or a strip.  None when the candidates do not get there."""
    parent = list(range(k))
    off = [(0, 0)] * k  # cell offset of i relative to parent[i]

    def find(i):
        o = (0, 0)
        while parent[i] != i:
            o = (o[0] + off[i][0], o[1] + off[i][1])
            i = parent[i]
        return i, o

    gens: list[tuple[int, int]] = []
    g = 0
    comps = k
    for d, i, j, n in cand:
        ri, oi = find(i)
        rj, oj = find(j)
        if ri != rj:
            parent[rj] = ri
            off[rj] = (oi[0] + n[0] - oj[0], oi[1] + n[1] - oj[1])
            comps -= 1
        else:
            v = (oi[0] + n[0] - oj[0], oi[1] + n[1] - oj[1])
            if v != (0, 0):
                for w in gens:
                    g = math.gcd(g, abs(v[0] * w[1] - v[1] * w[0]))
                gens.append(v)
        if comps == 1 and g == 1:
            return d
    return None


@st.composite
def periodic_lattices(draw, max_roles: int = 4, min_separation: float = 0.3,
                      min_angle_deg: float = 60.0, max_aspect: float = 1.5,
                      extra_distances: int = 2, min_gap: float = 1e-3,
                      headings: bool = True) -> LatticeGraph:
    """Random periodic lattice graphs, valid and self-consistent for their range.

    The pattern: lattice vectors ``a1 = (cos alpha, sin alpha)`` and ``a2`` of
    length in ``[1, max_aspect]`` at an angle in ``[min_angle_deg,
    180 - min_angle_deg]`` to ``a1``; a motif of 1 to ``max_roles`` points at
    random positions in the cell, each kept only if it is at least
    ``min_separation`` from every point kept so far and their periodic images;
    random headings (all 0 with ``headings=False``).  Roles are ``A, B, ...``.

    The range: the smallest distance ``t`` at which the infinite pattern is
    connected (a Kruskal pass that also tracks the translations of closed
    walks, so that they must generate the whole lattice, not a sub-lattice
    or a strip), then phi strictly between one of the first
    ``extra_distances + 1`` distinct pair distances ``>= t`` and the next one.

    The graph: an edge ``i -> j`` for every pattern point of role ``j`` closer
    than phi to the point of role ``i`` in cell 0, labelled with the exact
    relative pose.  Inverses come out by symmetry.

    Returns
    -------
    LatticeGraph
        With ``range`` set to phi and ``source='strategy:periodic_lattices'``.
    """
    basis, r2 = _draw_basis(draw, min_angle_deg, max_aspect)
    pts = _draw_motif(draw, basis, max_roles, min_separation)
    k = len(pts)
    ths = [draw(st.floats(-math.pi, math.pi, exclude_max=True)) if headings else 0.0 for _ in range(k)]
    cand = _candidate_pairs(pts, basis, r2)
    t_conn = _connecting_distance(cand, k)
    assume(t_conn is not None)  # pragma: no cover - big >= 2 max|a_k| + 1 always suffices
    groups = _groups(np.array([c[0] for c in cand]))
    k_conn = next(idx for idx, dd in enumerate(groups) if dd >= t_conn - _TIE)
    kk, phi = _choose_range(draw, groups, k_conn, extra_distances, min_gap, tail=None)
    limit = groups[kk] + _TIE
    pairs = [(i, j, tuple((basis @ np.array(n)).tolist())) for d, i, j, n in cand if d <= limit]
    roles = list(_ROLE_NAMES[:k])
    points = [tuple(p.tolist()) for p in pts]
    return lattice_from_points(points, ths, roles, pairs, phi, name=f"periodic-{k}",
                               source="strategy:periodic_lattices")


@st.composite
def finite_lattices(draw, min_points: int = 2, max_points: int = 6, min_separation: float = 0.3,
                    box: float = 3.0, extra_distances: int = 2, min_gap: float = 1e-3,
                    headings: bool = True) -> LatticeGraph:
    """Random finite formations: every robot its own role, a complete neighbor graph at phi.

    Points are drawn in ``[0, box]^2`` and kept if at least ``min_separation``
    from those kept before; phi lies strictly between one of the first
    ``extra_distances + 1`` distinct pair distances at or above the
    connectivity threshold (the longest edge of a minimum spanning tree) and
    the next distance (after the largest distance, up to ``box`` further).
    Every pair closer than phi gets both edges.  Roles are ``R0, R1, ...``.

    Returns
    -------
    LatticeGraph
        With ``range`` set and ``source='strategy:finite_lattices'``.
    """
    n = draw(st.integers(min_points, max_points))
    pts: list[tuple[float, float]] = []
    for _ in range(n):
        p = (draw(st.floats(0.0, box)), draw(st.floats(0.0, box)))
        if all(math.hypot(p[0] - q[0], p[1] - q[1]) >= min_separation for q in pts):
            pts.append(p)
    assume(len(pts) >= max(min_points, 1))
    n = len(pts)
    ths = [draw(st.floats(-math.pi, math.pi, exclude_max=True)) if headings else 0.0 for _ in range(n)]
    cand = sorted((math.hypot(pts[j][0] - pts[i][0], pts[j][1] - pts[i][1]), i, j)
                  for i in range(n) for j in range(n) if i != j)
    roles = [f"R{i}" for i in range(n)]
    if n == 1:
        phi = draw(st.floats(0.1, box))
        return LatticeGraph("finite-1", roles, [], range=phi, source="strategy:finite_lattices")
    parent = list(range(n))

    def find(i):
        while parent[i] != i:
            i = parent[i]
        return i

    comps, t_conn = n, 0.0
    for d, i, j in cand:
        a, b = find(i), find(j)
        if a != b:
            parent[b] = a
            comps -= 1
            if comps == 1:
                t_conn = d
                break
    groups = _groups(np.array([c[0] for c in cand]))
    k_conn = next(idx for idx, dd in enumerate(groups) if dd >= t_conn - _TIE)
    kk, phi = _choose_range(draw, groups, k_conn, extra_distances, min_gap, tail=box)
    limit = groups[kk] + _TIE
    pairs = [(i, j, (0.0, 0.0)) for d, i, j in cand if d <= limit]
    return lattice_from_points(pts, ths, roles, pairs, phi, name=f"finite-{n}",
                               source="strategy:finite_lattices")


# ---------------------------------------------------------------------------
# a bounded, independent oracle (for tests; NOT a decision procedure)
# ---------------------------------------------------------------------------

def sample_pattern(graph: LatticeGraph, radius: float, start: str | None = None,
                   merge_tol: float = 1e-6, max_points: int = 20000):
    """The pattern points a lattice graph generates within ``radius`` of a start robot.

    Breadth-first over walks from ``start`` (default v0) at the identity pose,
    composing edge transforms (001 Def. 3) and expanding only points within
    ``radius``.  Points closer than ``merge_tol`` are merged.  This is a
    *bounded sample* for tests, independent of the checker: a point reachable
    only through walks that leave the disc is missed.

    Returns
    -------
    points : list of (str, SE2)
        ``(role, pose)`` of each distinct point (the first walk to reach it).
    clashes : list of (int, str, SE2)
        Later walks reaching an existing point ``points[k]`` with another role
        or heading: ``(k, role, pose)``.

    Examples
    --------
    >>> from swarmproof.models import library
    >>> pts, clashes = sample_pattern(library.load("hexagon-ring"), 5.0)
    >>> len(pts), clashes
    (6, [])
    """
    start = graph.v0 if start is None else start
    cell = max(merge_tol * 10, 1e-3)
    grid: dict[tuple[int, int], list[int]] = {}
    points: list[tuple[str, SE2]] = []
    clashes = []

    def lookup(t: SE2):
        cx, cy = int(math.floor(t.x / cell)), int(math.floor(t.y / cell))
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for k in grid.get((cx + dx, cy + dy), ()):
                    q = points[k][1]
                    if math.hypot(q.x - t.x, q.y - t.y) < merge_tol:
                        return k
        return None

    def add(role: str, t: SE2) -> bool:
        k = lookup(t)
        if k is not None:
            r0, t0 = points[k]
            if r0 != role or abs(wrap_angle(t0.theta - t.theta)) > 1e-6:
                clashes.append((k, role, t))
            return False
        grid.setdefault((int(math.floor(t.x / cell)), int(math.floor(t.y / cell))), []).append(len(points))
        points.append((role, t))
        return True

    add(start, SE2.identity())
    frontier = [0]
    while frontier and len(points) < max_points:
        nxt = []
        for k in frontier:
            role, t = points[k]
            for e in graph.out_edges(role):
                u = t @ e.transform
                if math.hypot(u.x, u.y) <= radius and add(e.target, u):
                    nxt.append(len(points) - 1)
        frontier = nxt
    return points, clashes


def bounded_defects(graph: LatticeGraph, rng: float | None = None, check_radius: float | None = None,
                    start: str | None = None) -> list[str]:
    """Self-consistency problems (001 Def. 4) visible in a bounded sample of the pattern.

    For every sampled point ``w`` within ``check_radius`` of the start and every
    sampled point ``z`` closer than ``rng`` to it, the graph must have an edge
    ``role(w) -> role(z)`` labelled ``T_w^-1 T_z``; no two roles or headings
    may share a position; every edge must be shorter than ``rng``.  Returns
    human-readable problems (empty: none seen).  An empty answer is evidence,
    not proof: use :func:`swarmproof.checkers.lattice_check.check_lattice` to
    decide.

    Examples
    --------
    >>> from swarmproof.models import library
    >>> bounded_defects(library.load("square"), 1.2)
    []
    >>> bounded_defects(library.load("square"), 1.5)[0]
    'A at (0, 0) sees A at (1, -1) (distance 1.41421 < 1.5) but no edge A -> A (1, -1, 0deg)'
    """
    phi = graph.range if rng is None else rng
    out: list[str] = []
    longest = graph.max_edge_length()
    for e in graph.edges:
        if e.transform.norm() >= phi:
            out.append(f"{e.describe()} has length {e.transform.norm():.6g} >= range {phi:.6g}")
    if check_radius is None:
        check_radius = phi + longest
    pts, clashes = sample_pattern(graph, check_radius + 2 * phi + 2 * longest + 1.0, start)
    for k, role, t in clashes:
        r0, t0 = pts[k]
        out.append(f"{r0} and {role} forced onto ({t0.x:.6g}, {t0.y:.6g}) with headings "
                   f"{math.degrees(t0.theta):.6g}deg and {math.degrees(t.theta):.6g}deg")
    xy = np.array([[t.x, t.y] for _, t in pts])
    for a, (ra, ta) in enumerate(pts):
        if math.hypot(ta.x, ta.y) > check_radius:
            continue
        d = np.hypot(xy[:, 0] - ta.x, xy[:, 1] - ta.y)
        for b in np.nonzero(d < phi)[0]:
            if b == a:
                continue
            rb, tb = pts[b]
            rel = ta.inverse() @ tb
            if graph.find_edge(ra, rb, rel, pos_tol=1e-6, ang_tol=1e-6) is None:
                out.append(f"{ra} at ({ta.x:.6g}, {ta.y:.6g}) sees {rb} at ({tb.x:.6g}, {tb.y:.6g}) "
                           f"(distance {d[b]:.6g} < {phi:.6g}) but no edge {ra} -> {rb} "
                           f"({rel.x + 0:.6g}, {rel.y + 0:.6g}, {math.degrees(rel.theta) + 0:.6g}deg)")
    return out


# ---------------------------------------------------------------------------
# documents for the file format
# ---------------------------------------------------------------------------

_role_names = st.text(alphabet=string.ascii_letters + string.digits + "_-", min_size=1, max_size=4)
_finite = st.one_of(st.integers(-1000, 1000),
                    st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False))


def _bounded_length(row: tuple) -> list:
    """A row whose translation is shorter than the files' bound (``MIN_LENGTH``, 1e-6) made
    zero-length: such rows are refused, and length 0 is legal (a defect for the checker)."""
    from swarmproof.models.lattice_io import MIN_LENGTH

    a, b, x, y, th = row
    return [a, b, 0, 0, th] if (x or y) and math.hypot(x, y) < MIN_LENGTH else [a, b, x, y, th]


@st.composite
def lattice_graph_documents(draw, max_roles: int = 4, max_edges: int = 8) -> dict:
    """Valid ``lattice-graph/1`` documents as plain dicts (well-formed files;
    the graphs need not be valid or self-consistent).

    Optional keys (``name``, ``range``, ``angle_unit``) are present or not at
    random; numbers are ints or finite floats.
    """
    roles = draw(st.lists(_role_names, min_size=1, max_size=max_roles, unique=True))
    rows = draw(st.lists(st.tuples(st.sampled_from(roles), st.sampled_from(roles), _finite, _finite,
                                   _finite).map(_bounded_length), max_size=max_edges))
    doc: dict[str, Any] = {"format": FORMAT}
    if draw(st.booleans()):
        doc["name"] = draw(st.text(alphabet=string.ascii_letters + string.digits + " -_", min_size=1,
                                   max_size=12).filter(lambda s: s.strip() != ""))
    if draw(st.booleans()):
        doc["range"] = draw(st.floats(1e-3, 1e3))
    if draw(st.booleans()):
        doc["angle_unit"] = draw(st.sampled_from(["deg", "rad"]))
    doc["roles"] = roles
    doc["edges"] = rows
    return doc


#: The mutation kinds of :func:`mutated_lattice_documents`; each makes the document invalid.
MUTATION_KINDS = (
    "drop_required_key", "unknown_key", "bad_format", "not_a_mapping",
    "roles_not_list", "roles_empty", "role_not_string", "role_duplicate",
    "edges_not_list", "row_not_list", "row_length", "unknown_role",
    "non_finite_number", "bool_number", "wrong_type_number",
    "bad_range", "bad_angle_unit", "bad_name",
)
#: Kinds that JSON Schema cannot express (the loader checks them itself).
SCHEMA_BLIND_KINDS = ("unknown_role", "non_finite_number")

_junk = st.one_of(st.none(), st.booleans(), st.integers(-5, 5), st.text(string.printable, max_size=5),
                  st.lists(st.integers(0, 3), max_size=3), st.dictionaries(st.sampled_from("ab"),
                                                                          st.integers(0, 3), max_size=2))


@st.composite
def mutated_lattice_documents(draw, with_kind: bool = False, kinds=MUTATION_KINDS):
    """Invalid ``lattice-graph/1`` documents: a valid one broken in exactly one way.

    Parameters
    ----------
    with_kind : bool
        Return ``(document, kind)`` with ``kind`` one of :data:`MUTATION_KINDS`.
    kinds : sequence of str
        The mutation kinds to draw from (default: all of :data:`MUTATION_KINDS`).

    Every returned document must be rejected by a correct loader (JSON
    serialisation needs ``allow_nan=True`` for the non-finite kind).
    """
    doc = draw(lattice_graph_documents())
    unknown = [k for k in kinds if k not in MUTATION_KINDS]
    if unknown or not kinds:
        raise ValueError(f"kinds={list(kinds)!r}: use a non-empty subset of {list(MUTATION_KINDS)!r}")
    kind = draw(st.sampled_from(list(kinds)))
    roles = doc["roles"]
    if kind in ("row_not_list", "row_length", "unknown_role", "non_finite_number", "bool_number",
                "wrong_type_number") and not doc["edges"]:
        doc["edges"] = [[roles[0], roles[-1], 1, 0, 0]]
    rows = doc["edges"]
    r = draw(st.integers(0, max(len(rows) - 1, 0)))
    if kind == "drop_required_key":
        del doc[draw(st.sampled_from(["format", "roles", "edges"]))]
    elif kind == "unknown_key":
        key = draw(st.sampled_from(["edge", "Roles", "rang", "angle_units", "version", "nodes"])
                   | st.text(string.ascii_lowercase, min_size=1, max_size=8))
        assume(key not in ALLOWED_KEYS)
        doc[key] = draw(_junk)
    elif kind == "bad_format":
        doc["format"] = draw(st.sampled_from(["lattice-graph/2", "lattice-graph/0", "lattice-graph",
                                              "lattice-graph/1.0", "LATTICE-GRAPH/1", "", " lattice-graph/1"])
                             | _junk.filter(lambda v: v != FORMAT))
    elif kind == "not_a_mapping":
        doc = draw(_junk.filter(lambda v: not isinstance(v, dict)) | st.just([doc]))
    elif kind == "roles_not_list":
        doc["roles"] = draw(st.sampled_from(["A", 1, None, {"A": 1}]) | st.text(string.printable, max_size=3))
    elif kind == "roles_empty":
        doc["roles"] = []
    elif kind == "role_not_string":
        doc["roles"][draw(st.integers(0, len(roles) - 1))] = draw(
            st.sampled_from([1, 2.5, True, None, "", [1]]))
    elif kind == "role_duplicate":
        doc["roles"] = roles + [draw(st.sampled_from(roles))]
    elif kind == "edges_not_list":
        doc["edges"] = draw(st.sampled_from(["A A 1 0 0", 5, {"A": [1, 0, 0]}, True]))
    elif kind == "row_not_list":
        rows[r] = draw(st.sampled_from(["A, A, 1, 0, 0", 1, None, {"from": "A"}]))
    elif kind == "row_length":
        n = draw(st.integers(0, 8).filter(lambda n: n != 5))
        rows[r] = (rows[r] + [0, 0, 0, 0])[:n]
    elif kind == "unknown_role":
        bad = draw(_role_names.filter(lambda s: s not in roles))
        rows[r][draw(st.integers(0, 1))] = bad
    elif kind == "non_finite_number":
        rows[r][draw(st.integers(2, 4))] = draw(st.sampled_from([math.nan, math.inf, -math.inf]))
    elif kind == "bool_number":
        rows[r][draw(st.integers(2, 4))] = draw(st.booleans())
    elif kind == "wrong_type_number":
        rows[r][draw(st.integers(2, 4))] = draw(st.sampled_from(["1", "x", None, [1], {"a": 1}]))
    elif kind == "bad_range":
        doc["range"] = draw(st.sampled_from([0, -1, -0.5, math.nan, math.inf, True, "1.2", None, [1.2]]))
    elif kind == "bad_angle_unit":
        doc["angle_unit"] = draw(st.sampled_from(["grad", "degrees", "DEG", "", None, 1, ["deg"]]))
    elif kind == "bad_name":
        doc["name"] = draw(st.sampled_from(["", "   ", 5, None, ["x"], True]))
    return (doc, kind) if with_kind else doc
