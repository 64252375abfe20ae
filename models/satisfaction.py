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
    edges = list(lattice.edges)
    if edges:
        et = np.array([[e.transform.x, e.transform.y, e.transform.theta] for e in edges])
    else:
        et = np.empty((0, 3))
    # allowed[(a, b)] = set of (role_a, role_b) with an edge matching pose of b in a's frame
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
            x, y, th = (float(v) for v in rel[k])
            return SatisfactionResult(
                "violated", None,
                {"pair": [ids[a], ids[b]], "relative_pose": [x, y, th], "roles": None,
                 "reason": "no_matching_edge"},
                f"robots {ids[a]} and {ids[b]} are neighbors but the pose of {ids[b]} in the "
                f"frame of {ids[a]}, ({x:.6g}, {y:.6g}, {np.degrees(th):.6g}deg), matches no edge "
                f"of lattice {lattice.name!r}")
    nbrs: list[list[int]] = [[] for _ in range(n)]
    for a, b in zip(src.tolist(), dst.tolist()):
        nbrs[a].append(b)
    role_of: dict[int, str] = {}
    nodes = 0
    deepest = (-1, None)
    for comp in components(n, i, j):
        start = min(comp, key=lambda k: ids[k])
        order = [start]
        seen = {start}
        for x in order:  # BFS (neighbors in ID order for determinism)
            for y in sorted(nbrs[x], key=lambda k: ids[k]):
                if y not in seen:
                    seen.add(y)
                    order.append(y)

        def candidates(x: int):
            cand = set(roles) if x == start else None
            blame = None
            for a in nbrs[x]:
                if a not in role_of:
                    continue
                ra = role_of[a]
                ok = {w for (u, w) in allowed[(a, x)] if u == ra} & {u for (u, w) in allowed[(x, a)] if w == ra}
                cand = ok if cand is None else cand & ok
                if not cand:
                    blame = a
                    break
            return [r for r in roles if r in (cand or ())], blame

        stack: list[tuple[int, list[str]]] = []
        level = 0
        first, _ = candidates(order[0])
        stack.append((0, first))
        ok_comp = False
        while stack:
            level, cands = stack[-1]
            x = order[level]
            role_of.pop(x, None)
            if not cands:
                stack.pop()
                continue
            role_of[x] = cands.pop(0)
            nodes += 1
            if nodes > max_nodes:
                return SatisfactionResult("inconclusive", None, None,
                                          f"search budget max_nodes={max_nodes} spent")
            if level + 1 == len(order):
                ok_comp = True
                break
            nxt, blame = candidates(order[level + 1])
            if not nxt and level + 1 > deepest[0]:
                deepest = (level + 1, (order[level + 1], blame))
            stack.append((level + 1, nxt))
        if not ok_comp:
            x, a = deepest[1] if deepest[1] is not None else (order[0], None)
            for y in order:
                role_of.pop(y, None)
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
    return SatisfactionResult("held", {ids[k]: role_of[k] for k in range(n)}, None,
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
