"""Does a configuration satisfy a lattice graph?  Decided exactly (001 Def. 2, 000 Def. 2).

A set of robots satisfies a lattice graph G if there is a role function f
from robots to vertices such that for *every* pair of neighbors
``r_i, r_j`` (strictly closer than phi) there is an edge
``f(r_i) -> f(r_j)`` whose transform is the pose of ``r_j`` in the body frame
of ``r_i`` (001 Def. 2; 000 Eq. 2: ``T(r_j) = T(r_i) T(e_ij)``).  Pairs
that are not neighbors impose nothing.

Decision procedure (complete, with backtracking): for each connected
component of the neighbor graph, robots are visited in breadth-first order
from its lowest-ID robot; the first robot tries every role in the graph's
role order, every later robot's candidate roles are those allowed by *all*
its already-assigned neighbors in both directions (an edge ``f(a) -> w``
matching the pose of the robot in ``a``'s frame, and an edge ``w -> f(a)``
matching ``a`` in the robot's frame), and the search backtracks when a
robot has no candidate.  Components are independent (Def. 2 says nothing
about robots that are not neighbors).  The search is exponential only in
pathological graphs; ``max_nodes`` bounds it and then the result is
inconclusive.

A violation comes with a witness pair: the neighbor pair whose constraint
ruled out the last candidate at the deepest point of the search (or a pair
whose relative pose matches no edge at all).

References
----------
001_7a4e517b856331bc.txt (Song & O'Kane 2016), Sec. III-B, Def. 2.
000_3ad33c5b62f11d5f.txt (Song & O'Kane 2014), Sec. III-B, Def. 2, Eq. 2.

Examples
--------
>>> from swarmproof.models.lattice import LatticeGraph
>>> from swarmproof.models.se2 import SE2
>>> sq = LatticeGraph("square", ["A"], [("A", "A", SE2(1, 0, 0)), ("A", "A", SE2(0, 1, 0)),
...                                     ("A", "A", SE2(-1, 0, 0)), ("A", "A", SE2(0, -1, 0))])
>>> r = satisfies_lattice([5, 6, 7], [[0, 0, 0], [1, 0, 0], [1, 1, 0]], sq, 1.2)
>>> r.held, r.roles
(True, {5: 'A', 6: 'A', 7: 'A'})
>>> bad = satisfies_lattice([5, 6], [[0, 0, 0], [0.9, 0, 0]], sq, 1.2)
>>> bad.held, bad.witness["pair"]
(False, [5, 6])
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .se2 import wrap_angle
from .verdict import ThreeValued
from .sensing import components, neighbor_pairs

__all__ = ["SatisfactionResult", "satisfies_lattice", "DEFAULT_SAT_POS_TOL", "DEFAULT_SAT_ANG_TOL",
           "fulfillment_ratio", "non_fulfillment_ratio", "neighbor_counts"]

#: Default tolerances for matching a relative pose with an edge transform.
DEFAULT_SAT_POS_TOL = 1e-6
DEFAULT_SAT_ANG_TOL = 1e-6

DEF_2 = "001 Def. 2 (R satisfies G); 000 Def. 2, Eq. 2"


@dataclass(frozen=True)
class SatisfactionResult(ThreeValued):
    """Outcome of :func:`satisfies_lattice`.

    Attributes
    ----------
    status : str
        ``"held"``, ``"violated"`` or ``"inconclusive"`` (search budget spent).
    roles : dict or None
        Robot ID -> role name (a witness role function) when held.
    witness : dict or None
        When violated: ``pair`` ``[id_i, id_j]``, ``relative_pose`` of j in
        i's frame ``[x, y, theta]``, ``roles`` tried, and a message.
    message : str
    cites : str
    """

    status: str
    roles: dict | None
    witness: dict | None
    message: str
    cites: str = DEF_2


    def as_dict(self) -> dict:
        return {"status": self.status, "roles": None if self.roles is None else
                {str(k): v for k, v in self.roles.items()},
                "witness": self.witness, "message": self.message, "cites": self.cites}


def _rel(frames: np.ndarray, poses: np.ndarray) -> np.ndarray:
    c, s = np.cos(frames[:, 2]), np.sin(frames[:, 2])
    dx, dy = poses[:, 0] - frames[:, 0], poses[:, 1] - frames[:, 1]
    return np.column_stack((c * dx + s * dy, -s * dx + c * dy, wrap_angle(poses[:, 2] - frames[:, 2])))


def _matching_role_pairs(src, dst, rel, edges, pos_tol: float, ang_tol: float) -> tuple[dict, int | None]:
    """``(allowed, k)``: per directed neighbor pair ``(a, b)`` the ``(role of a, role of b)`` pairs
    of the edges whose transform matches the pose of b in a's frame (``rel``), in pair order,
    up to the first pair ``k`` that matches no edge (``k`` None: every pair matches one)."""
    if edges:
        et = np.array([[e.transform.x, e.transform.y, e.transform.theta] for e in edges])
    else:
        et = np.empty((0, 3))
    allowed: dict[tuple[int, int], set] = {}
    for k in range(len(src)):
        a, b = int(src[k]), int(dst[k])
        if len(et):
            dpos = np.hypot(et[:, 0] - rel[k, 0], et[:, 1] - rel[k, 1])
            dang = np.abs(wrap_angle(et[:, 2] - rel[k, 2]))
            hits = np.flatnonzero((dpos <= pos_tol) & (dang <= ang_tol))
        else:
            hits = []
        allowed[(a, b)] = {(edges[h].source, edges[h].target) for h in hits}
        if not allowed[(a, b)]:
            return allowed, k
    return allowed, None


def _bfs_order(comp, nbrs: list, ids: list) -> list:
    """The robots of one component breadth first from its lowest ID, neighbors in ID order."""
    start = min(comp, key=lambda k: ids[k])
    order = [start]
    seen = {start}
    for x in order:
        for y in sorted(nbrs[x], key=lambda k: ids[k]):
            if y not in seen:
                seen.add(y)
                order.append(y)
    return order


class _RoleSearch:
    """The backtracking search for a role function (module docstring), one component after the
    other: the roles given so far (``role_of``), the assignments tried (``nodes``, the budget
    counts them over all components) and the deepest dead end met (``deepest``: ``(level,
    (robot, neighbor to blame or None))``, the violation's witness)."""

    def __init__(self, roles: list, nbrs: list, allowed: dict, max_nodes: int) -> None:
        self.roles, self.nbrs, self.allowed, self.max_nodes = roles, nbrs, allowed, max_nodes
        self.role_of: dict[int, str] = {}
        self.nodes = 0
        self.deepest = (-1, None)

    def candidates(self, x: int, start: int) -> tuple[list, int | None]:
        """The roles robot ``x`` can take given its neighbors' roles so far, in the lattice's role
        order (every role for the component's first robot ``start``), and the neighbor that
        ruled out the last one (None when some role is left)."""
        roles, role_of, allowed = self.roles, self.role_of, self.allowed
        cand = set(roles) if x == start else None
        blame = None
        for a in self.nbrs[x]:
            if a not in role_of:
                continue
            ra = role_of[a]
            ok = {w for (u, w) in allowed[(a, x)] if u == ra} & {u for (u, w) in allowed[(x, a)] if w == ra}
            cand = ok if cand is None else cand & ok
            if not cand:
                blame = a
                break
        return [r for r in roles if r in (cand or ())], blame

    def solve(self, order: list) -> bool | None:
        """Give the robots of one component (in ``order``) roles: True when every one has a role,
        False when no role function fits, None when the budget ``max_nodes`` is spent."""
        role_of, start = self.role_of, order[0]
        first, _ = self.candidates(start, start)
        stack: list[tuple[int, list[str]]] = [(0, first)]
        while stack:
            level, cands = stack[-1]
            x = order[level]
            role_of.pop(x, None)
            if not cands:
                stack.pop()
                continue
            role_of[x] = cands.pop(0)
            self.nodes += 1
            if self.nodes > self.max_nodes:
                return None
            if level + 1 == len(order):
                return True
            nxt, blame = self.candidates(order[level + 1], start)
            if not nxt and level + 1 > self.deepest[0]:
                self.deepest = (level + 1, (order[level + 1], blame))
            stack.append((level + 1, nxt))
        return False


def _no_matching_edge(ids: list, a: int, b: int, rel_ab, lattice) -> SatisfactionResult:
    """Violated: neighbors ``a`` and ``b`` whose relative pose matches no edge of the lattice."""
    x, y, th = (float(v) for v in rel_ab)
    return SatisfactionResult(
        "violated", None,
        {"pair": [ids[a], ids[b]], "relative_pose": [x, y, th], "roles": None,
         "reason": "no_matching_edge"},
        f"robots {ids[a]} and {ids[b]} are neighbors but the pose of {ids[b]} in the "
        f"frame of {ids[a]}, ({x:.6g}, {y:.6g}, {np.degrees(th):.6g}deg), matches no edge "
        f"of lattice {lattice.name!r}")


def _no_role_function(ids: list, dead_end, first: int, src, dst, rel) -> SatisfactionResult:
    """Violated: no role function fits; the witness is the search's deepest dead end
    ``(robot, neighbor to blame)`` (None: the component's ``first`` robot, no role at all)."""
    x, a = dead_end if dead_end is not None else (first, None)
    if a is None:
        return SatisfactionResult("violated", None, {"pair": [ids[x]], "reason": "no_role"},
                                  f"no role fits robot {ids[x]}")
    k = np.flatnonzero((src == a) & (dst == x))[0]
    xr, yr, th = (float(v) for v in rel[k])
    return SatisfactionResult(
        "violated", None,
        {"pair": [ids[a], ids[x]], "relative_pose": [xr, yr, th],
         "reason": "no_consistent_role_function"},
        f"no role function fits: with the roles forced on the robots before it, robot "
        f"{ids[x]} can take no role consistent with its neighbor {ids[a]} (pose of {ids[x]} "
        f"in the frame of {ids[a]}: ({xr:.6g}, {yr:.6g}, {np.degrees(th):.6g}deg))")


def satisfies_lattice(ids, poses, lattice, phi: float, *, pos_tol: float = DEFAULT_SAT_POS_TOL,
                      ang_tol: float = DEFAULT_SAT_ANG_TOL, max_nodes: int = 1_000_000
                      ) -> SatisfactionResult:
    """Decide Def. 2 for robots ``ids`` at ``poses`` (global frame) and ``lattice`` at range ``phi``.

    Parameters
    ----------
    ids : sequence of int
    poses : array_like, shape (n, 3)
    lattice : LatticeGraph
    phi : float
    pos_tol, ang_tol : float
        A relative pose matches an edge when its translation is within
        ``pos_tol`` (Euclidean) and its angle within ``ang_tol`` (wrapped).
    max_nodes : int
        Search budget (role assignments tried) before giving up (inconclusive).

    Returns
    -------
    SatisfactionResult
    """
    ids = [int(i) for i in ids]
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    n = len(ids)
    roles = list(lattice.roles)
    if n == 0:
        return SatisfactionResult("held", {}, None, "no robots")
    i, j, _ = neighbor_pairs(poses[:, :2], phi)
    src = np.concatenate((i, j))
    dst = np.concatenate((j, i))
    rel = _rel(poses[src], poses[dst]) if len(src) else np.empty((0, 3))
    # allowed[(a, b)] = set of (role_a, role_b) with an edge matching pose of b in a's frame
    allowed, unmatched = _matching_role_pairs(src, dst, rel, list(lattice.edges), pos_tol, ang_tol)
    if unmatched is not None:
        return _no_matching_edge(ids, int(src[unmatched]), int(dst[unmatched]), rel[unmatched], lattice)
    nbrs: list[list[int]] = [[] for _ in range(n)]
    for a, b in zip(src.tolist(), dst.tolist()):
        nbrs[a].append(b)
    search = _RoleSearch(roles, nbrs, allowed, max_nodes)
    for comp in components(n, i, j):
        order = _bfs_order(comp, nbrs, ids)
        solved = search.solve(order)
        if solved is None:
            return SatisfactionResult("inconclusive", None, None, f"search budget max_nodes={max_nodes} spent")
        if not solved:
            # (the deepest dead end of the whole search: it may lie in an earlier component that
            # did get roles, so the witness can name robots outside this one; left as it was)
            return _no_role_function(ids, search.deepest[1], order[0], src, dst, rel)
    return SatisfactionResult("held", {ids[k]: search.role_of[k] for k in range(n)}, None,
                              f"{n} robots satisfy lattice {lattice.name!r}")


# -- the lattice's figures: 001 Sec. III-C-2 (Q) and 000 Eq. 3 (swarmproof.invariants.metrics) --

def neighbor_counts(poses, phi: float) -> np.ndarray:
    """``N_i``: how many robots are strictly closer than ``phi`` to each robot."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    i, j, _ = neighbor_pairs(poses[:, :2], phi)
    return np.bincount(np.concatenate((i, j)), minlength=len(poses))


def _ratios(ids, poses, lattice, phi, roles, pos_tol, ang_tol):
    ids = [int(x) for x in ids]
    if not ids:
        return None
    if roles is None:
        sat = satisfies_lattice(ids, poses, lattice, phi, pos_tol=pos_tol, ang_tol=ang_tol)
        if not sat.held:
            return None
        roles = sat.roles
    counts = neighbor_counts(poses, phi)
    out = []
    for k, rid in enumerate(ids):
        e = len(lattice.out_edges(roles[rid]))
        nk = int(counts[k])
        out.append((nk, e))
    return out


def fulfillment_ratio(ids, poses, lattice, phi: float, roles: dict | None = None, *,
                      pos_tol: float = DEFAULT_SAT_POS_TOL, ang_tol: float = DEFAULT_SAT_ANG_TOL):
    """Q of 001 Sec. III-C-2 (see the module docstring); None when roles are undefined."""
    r = _ratios(ids, poses, lattice, phi, roles, pos_tol, ang_tol)
    if r is None:
        return None
    return float(sum((nk / e) if e else (1.0 if nk == 0 else 0.0) for nk, e in r) / len(r))


def non_fulfillment_ratio(ids, poses, lattice, phi: float, roles: dict | None = None, *,
                          pos_tol: float = DEFAULT_SAT_POS_TOL, ang_tol: float = DEFAULT_SAT_ANG_TOL):
    """The non-fulfillment ratio of 000 Eq. 3; None when roles are undefined."""
    r = _ratios(ids, poses, lattice, phi, roles, pos_tol, ang_tol)
    if r is None:
        return None
    return float(sum(((e - nk) / e) if e else (0.0 if nk == 0 else 1.0) for nk, e in r) / len(r))
