"""Formation quality of a repeating pattern, exactly: Jiang et al. (002) Defs. 4-9.

A repeating pattern is a basic pattern graph B (Def. 3: points, the first at
the origin) and an assembling graph A (Def. 7: distinct vectors).  For a
configuration C of robot positions:

* Def. 4 -- a sub-configuration S is *compatible* with B when one
  translation maps every point of S onto a point of B; its *completion rate*
  is ``alpha = |S| / |B|`` (0 when incompatible) and its *center* is
  ``O(S, B) = O(B) - v`` with ``v`` that translation (``O(B)`` the centroid
  of B).  Equality is judged within a declared tolerance ``tol`` (DESIGN.md
  section 5: the paper's exact equality is not computable on floats).
* Def. 6 / Eq. 1-2 -- ``beta`` of a partition is the mean of its parts'
  completion rates; ``gamma(C, B)`` is the best ``beta`` over *all*
  partitions, and a partition reaching it is *optimal*.
* Def. 8 / Eq. 3 -- link the centers of an optimal partition's parts when
  they differ by a vector of A; ``delta = 1 / (number of components)``.
* Def. 9 / Eq. 4 -- ``epsilon = gamma * delta``.

``gamma`` is a combinatorial optimum.  It is computed exactly, with the method
and the problem size reported:

1. *perfect cover*: when ``|C|`` is a multiple of ``|B|``, an exact cover of
   C by full translated copies of B (Knuth's Algorithm X, smallest column
   first) proves ``gamma = 1``; every exact cover is then an optimal
   partition, and they are enumerated (up to ``max_covers`` search nodes)
   for the one with the fewest components (largest ``delta``);
2. otherwise an integer program over candidate parts (the maximal compatible
   subsets, one per translation that puts a robot on a point of B), solved
   exactly by scipy's ``milp`` (HiGHS, relative gap 0) inside Dinkelbach's
   iteration for the ratio of Eq. 1.  Its optimum *is* ``gamma``: any
   partition maps to a solution of equal value and back (a part of the
   program's solution that is not compatible -- at most one is useful, the
   "rest" -- scores 0, exactly as Def. 4 says).

Where the search or the solver stops on its node budget (deterministic:
never a wall clock) the result is *inconclusive* with bounds, never a wrong
number.

Choices (docs/decisions.md, "Jiang et al."): an incompatible part has no
center (Def. 4 defines it only through ``v``) and is no vertex of Def. 8's
graph; a part with several fitting translations (a partial copy) takes the
one whose center has the most A-links to the full copies' centers (ties: the
first found, by robot and B index), and the result says
``centers_ambiguous``; among several optimal partitions ``delta`` is the
largest found by the exact-cover enumeration (perfect case); otherwise a
second integer program picks an optimal partition with the most full copies of
B, and delta is that partition's.

Examples
--------
>>> B = [(0, 0), (1, 0)]                 # a segment
>>> A = [(0, 0), (0, 1)]                 # copies stacked upward
>>> q = formation_quality([(0, 0), (1, 0), (0, 1), (1, 1)], B, A)
>>> q.exact, str(q.gamma), str(q.delta), str(q.epsilon), q.method
(True, '1', '1', '1', 'perfect-cover')
>>> q = formation_quality([(0, 0), (1, 0), (0, 5), (1, 5)], B, A)   # two copies, not linked by A
>>> str(q.gamma), str(q.delta), str(q.epsilon)
('1', '1/2', '1/2')
>>> q = formation_quality([(0, 0), (1, 0), (7, 7)], B, A)            # a copy and a lone robot
>>> str(q.gamma), q.method, q.completion_rates()
('3/4', 'milp', {'1': 1, '1/2': 1})
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from .errors import UsageError

__all__ = ["FormationQuality", "formation_quality", "candidate_parts", "MAX_COVER_NODES", "MAX_MILP_NODES",
           "MAX_CANDIDATES"]

#: Search nodes of the exact-cover enumeration (deterministic budget).
MAX_COVER_NODES = 200_000
#: Branch-and-bound nodes per integer program (deterministic budget).
MAX_MILP_NODES = 20_000
#: Candidate parts above which the integer program is not attempted (bounded memory).
MAX_CANDIDATES = 200_000

CITES = "002 Defs. 4-9, Eqs. 1-4"


@dataclass(frozen=True)
class FormationQuality:
    """The figures of Defs. 4-9 for one configuration.

    ``exact`` is True when ``gamma`` is the proven optimum; otherwise
    ``gamma`` is None and ``gamma_bounds`` brackets it.  ``parts`` is the
    optimal partition found: ``(center or None, robot indices)`` per part
    (None: the incompatible rest).
    """

    exact: bool
    gamma: Fraction | None
    gamma_bounds: tuple[Fraction, Fraction]
    delta: Fraction | None
    epsilon: Fraction | None
    method: str
    size: dict
    parts: tuple = ()
    components: int | None = None
    optimal_partitions: str = "unknown"      # "one", "several" or "unknown"
    centers_ambiguous: bool = False
    message: str = ""
    cites: str = CITES
    #: Which partition delta (and so epsilon) is of: "the best optimal partition" (every
    #: optimal partition seen, or delta = 1), "the best optimal partition seen" (the search
    #: budget ran out first), or "the optimal partition found" (gamma < 1: epsilon is then a
    #: lower bound of the best epsilon over optimal partitions).
    delta_of: str = "the optimal partition found"

    def completion_rates(self) -> dict:
        """How many parts of the partition have each completion rate (Def. 4's alpha, as a
        fraction string; an incompatible part has alpha 0): ``{"1": 10, "1/3": 1}``."""
        b = self.size.get("basic_points")
        out: dict = {}
        for center, members in self.parts:
            key = "0" if center is None or not b else str(Fraction(len(members), b))
            out[key] = out.get(key, 0) + 1
        return dict(sorted(out.items(), key=lambda kv: -Fraction(kv[0])))

    def as_dict(self) -> dict:
        """JSON-ready: exact fractions as strings (``"3/4"``) beside floats."""
        def fr(x):
            return None if x is None else str(x)

        def fl(x):
            return None if x is None else float(x)

        return {"exact": self.exact, "epsilon": fl(self.epsilon), "epsilon_exact": fr(self.epsilon),
                "basic_fulfillment": fl(self.gamma), "basic_fulfillment_exact": fr(self.gamma),
                "basic_fulfillment_bounds": [fr(self.gamma_bounds[0]), fr(self.gamma_bounds[1])],
                "assembling_fulfillment": fl(self.delta), "assembling_fulfillment_exact": fr(self.delta),
                "components": self.components, "parts": len(self.parts), "assembling_fulfillment_of": self.delta_of,
                "completion_rates": self.completion_rates(),
                "optimal_partitions": self.optimal_partitions, "centers_ambiguous": self.centers_ambiguous,
                "method": self.method, "size": dict(self.size), "message": self.message, "cites": self.cites}


def _points(a, what: str) -> np.ndarray:
    try:
        arr = np.asarray(a, dtype=float)
    except (TypeError, ValueError):
        raise UsageError(f"{what} must be a list of (x, y) points") from None
    if arr.size == 0:
        return np.zeros((0, 2))
    if arr.ndim != 2 or arr.shape[1] < 2:
        raise UsageError(f"{what} must be a list of (x, y) points, got shape {arr.shape}")
    arr = arr[:, :2]
    if not np.isfinite(arr).all():
        raise UsageError(f"{what} holds a value that is not a finite number")
    return arr


def candidate_parts(xy: np.ndarray, basic: np.ndarray, tol: float) -> list[tuple[tuple[int, ...], np.ndarray]]:
    """The maximal compatible subsets of ``xy`` (Def. 4), one per distinct member set.

    For every robot ``i`` and point ``B_j``, the copy ``B + (p_i - B_j)`` of B;
    its members are the robots within ``tol`` of one of its points.  Returns
    ``[(sorted member indices, translation c), ...]`` in a fixed order (by
    ``i``, then ``j``); the copy's center is ``O(B) + c``.  Every compatible
    subset of ``xy`` is a subset of one of them.
    """
    from scipy.spatial import cKDTree

    n, b = len(xy), len(basic)
    if n == 0:
        return []
    tree = cKDTree(xy)
    shifts = (xy[:, None, :] - basic[None, :, :]).reshape(-1, 2)          # c for (i, j), i-major
    copies = shifts[:, None, :] + basic[None, :, :]                        # (n*b, b, 2)
    dist, idx = tree.query(copies.reshape(-1, 2), k=1, distance_upper_bound=tol)
    idx = idx.reshape(n * b, b)
    out, seen = [], set()
    for r in range(n * b):
        members = tuple(sorted(int(x) for x in idx[r] if x < n))
        if members and members not in seen and len(set(members)) == len(members):
            seen.add(members)
            out.append((members, shifts[r]))
    return out


def _exact_covers(n: int, full: list[tuple[int, ...]], budget: int):
    """Yield exact covers of ``range(n)`` by the sets ``full`` (indices into it); stop after
    ``budget`` search nodes.  The generator's ``.exhausted`` attribute is not available, so
    the caller reads ``state["complete"]``."""
    state = {"nodes": 0, "complete": True}
    cols: dict[int, set[int]] = {p: set() for p in range(n)}
    for k, s in enumerate(full):
        for p in s:
            cols[p].add(k)

    def select(k):
        removed = []
        for p in full[k]:
            for other in cols[p]:
                for q in full[other]:
                    if q != p:
                        cols[q].discard(other)
            removed.append(cols.pop(p))
        return removed

    def deselect(k, removed):
        for p in reversed(full[k]):
            cols[p] = removed.pop()
            for other in cols[p]:
                for q in full[other]:
                    if q != p:
                        cols[q].add(other)

    chosen: list[int] = []

    def search():
        if not cols:
            yield list(chosen)
            return
        state["nodes"] += 1
        if state["nodes"] > budget:
            state["complete"] = False
            return
        p = min(cols, key=lambda c: (len(cols[c]), c))
        for k in sorted(cols[p]):
            removed = select(k)
            chosen.append(k)
            yield from search()
            chosen.pop()
            deselect(k, removed)
            if state["nodes"] > budget:
                state["complete"] = False
                return

    return search(), state


def _components(centers: list[np.ndarray], assembling: np.ndarray, tol: float) -> int:
    """Connected components of Def. 8's graph: centers linked when they differ by a vector of A
    (:func:`swarmproof.models.sensing.components` on those links)."""
    from scipy.spatial import cKDTree

    from .sensing import components

    m = len(centers)
    if m == 0:
        return 0
    pts = np.asarray(centers, dtype=float)
    tree = cKDTree(pts)
    src, dst = [], []
    for a in assembling:
        if math.hypot(a[0], a[1]) <= tol:
            continue
        _, idx = tree.query(pts + a, k=1, distance_upper_bound=tol)
        hit = np.flatnonzero(idx < m)
        src.append(hit)
        dst.append(idx[hit])
    if not src:
        return m
    return len(components(m, np.concatenate(src), np.concatenate(dst)))


def _best_translations(parts: list, xy: np.ndarray, bp: np.ndarray, av: np.ndarray, tol: float) -> list:
    """For each partial part (fewer robots than B) with several fitting translations, the one
    whose center has the most A-links to the full copies' centers (ties: the first, by robot
    and B index).  A full copy fits one translation only."""
    b = len(bp)
    ob = bp.mean(axis=0)
    full = np.array([ob + c for c, ms in parts if c is not None and len(ms) == b]).reshape(-1, 2)
    steps = [a for a in av if math.hypot(a[0], a[1]) > tol]

    def links(center) -> int:
        if not len(full):
            return 0
        k = 0
        for a in steps:
            for q in (center + a, center - a):
                k += bool(np.any(np.hypot(full[:, 0] - q[0], full[:, 1] - q[1]) <= tol))
        return k

    out = []
    for c, ms in parts:
        if c is None or len(ms) == b:
            out.append((c, ms))
            continue
        best, best_links = c, links(ob + c)
        p0 = xy[ms[0]]
        for bj in bp:
            cand = p0 - bj
            copy = bp + cand
            if all(np.min(np.hypot(copy[:, 0] - xy[m, 0], copy[:, 1] - xy[m, 1])) <= tol for m in ms):
                k = links(ob + cand)
                if k > best_links:
                    best, best_links = cand, k
        out.append((best, ms))
    return out


def _upper_bound(n: int, b: int) -> Fraction:
    """The largest beta any partition of n robots could have (parts hold at most b robots;
    an incompatible rest scores 0): a bound used when the optimum is not proven."""
    best = Fraction(n, b * math.ceil(n / b))
    for k in range(2, n + 1):
        best = max(best, Fraction(min(n - 1, b * (k - 1)), b * k))
        if b * (k - 1) >= n - 1:
            break
    return min(best, Fraction(1))


def _beta(parts: list[tuple], b: int) -> Fraction:
    """Eq. 1 for a partition: parts ``(center or None, members)``; None scores 0."""
    if not parts:
        return Fraction(0)
    return sum((Fraction(len(m), b) for c, m in parts if c is not None), Fraction(0)) / len(parts)


def _most_full_copies(cands, b, ratio, best, a, lo_b, hi_b, nv, m, n, parts_of, node_limit):
    """Among the optimal partitions, one with the most full copies of B (a second integer
    program: keep ``beta = gamma`` as a constraint, maximise the full candidates chosen), so that
    Def. 8's graph is built on whole copies where the optimum allows; the first optimum is kept
    when this one does not finish or does not reach gamma exactly."""
    from scipy.optimize import Bounds, LinearConstraint, milp
    from scipy.sparse import csr_matrix, vstack

    p, q = ratio.numerator, ratio.denominator
    # q * sum z - p * b * (sum y + G) >= 0  <=>  beta of the solution >= gamma
    row = np.concatenate((np.full(m, -float(p * b)), np.full(n, float(q)), [-float(p * b)]))
    cons = [LinearConstraint(vstack([a, csr_matrix(row)]), np.concatenate((lo_b, [0.0])),
                             np.concatenate((hi_b, [np.inf])))]
    full = np.array([1.0 if len(ms) == b else 0.0 for ms, _ in cands])
    # full copies count, and their members must be covered (z_p <= y_c is implied by the
    # covering rows only one way): reward whole copies, prefer fewer parts among equals
    cost = np.concatenate((-full * (n + 1) + 1.0, np.zeros(n), [1.0]))
    res = milp(cost, constraints=cons, integrality=np.ones(nv), bounds=Bounds(np.zeros(nv), np.ones(nv)),
               options={"node_limit": node_limit, "mip_rel_gap": 0.0, "presolve": True})
    if res.status != 0 or res.x is None:
        return best
    cand = parts_of(res.x)
    return cand if _beta(cand, b) == ratio else best


def _milp_gamma(n: int, b: int, cands: list, singles: np.ndarray, node_limit: int):
    """Dinkelbach's iteration over exact MILPs; returns ``(exact, parts, lo, size)``."""
    from scipy.optimize import Bounds, LinearConstraint, milp
    from scipy.sparse import coo_matrix

    m = len(cands)
    nv = m + n + 1                                    # y_c, z_p, G
    rows, cols, vals = [], [], []
    for k, (members, _) in enumerate(cands):          # z_p - sum_{c ∋ p} y_c <= 0
        for p in members:
            rows.append(p)
            cols.append(k)
            vals.append(-1.0)
    for p in range(n):
        rows += [p, n + p, n + p]                     # ... and z_p + G >= 1
        cols += [m + p, m + p, m + n]
        vals += [1.0, 1.0, 1.0]
    a = coo_matrix((vals, (rows, cols)), shape=(2 * n, nv)).tocsr()
    lo_b = np.concatenate((np.full(n, -np.inf), np.ones(n)))
    hi_b = np.concatenate((np.zeros(n), np.full(n, np.inf)))
    cons = LinearConstraint(a, lo_b, hi_b)
    integrality = np.ones(nv)
    bounds = Bounds(np.zeros(nv), np.ones(nv))
    size = {"robots": n, "basic_points": b, "candidate_parts": m, "variables": nv, "constraints": 2 * n}

    def parts_of(x) -> list[tuple]:
        # whole copies first: a robot two chosen candidates share goes to the larger one
        chosen = sorted((k for k in range(m) if x[k] > 0.5), key=lambda k: (-len(cands[k][0]), k))
        owner: dict[int, int] = {}
        for k in chosen:
            for p in cands[k][0]:
                owner.setdefault(p, k)
        parts: dict[int, list[int]] = {}
        rest = []
        for p in range(n):
            (parts.setdefault(owner[p], []) if p in owner else rest).append(p)
        out = [(cands[k][1], tuple(ps)) for k, ps in sorted(parts.items())]
        return out + ([(None, tuple(rest))] if rest else [])

    best = [(singles[p], (p,)) for p in range(n)]        # every lone robot is compatible (Def. 4)
    ratio = _beta(best, b)
    for _ in range(64):
        cost = np.concatenate((np.full(m, float(ratio)), np.full(n, -1.0 / b), [float(ratio)]))
        res = milp(cost, constraints=cons, integrality=integrality, bounds=bounds,
                   options={"node_limit": node_limit, "mip_rel_gap": 0.0, "presolve": True})
        if res.x is None:
            return False, best, ratio, size
        cand = parts_of(res.x)
        value = _beta(cand, b)
        if value <= ratio:
            if res.status == 0:
                best = _most_full_copies(cands, b, ratio, best, a, lo_b, hi_b, nv, m, n, parts_of, node_limit)
            return res.status == 0, best, ratio, size
        best, ratio = cand, value
        if res.status != 0:
            return False, best, ratio, size
    return False, best, ratio, size


def formation_quality(points, basic, assembling, *, tol: float | None = None,
                      max_cover_nodes: int = MAX_COVER_NODES, max_milp_nodes: int = MAX_MILP_NODES
                      ) -> FormationQuality:
    """Defs. 4-9 of 002 for the robots at ``points`` (see the module docstring).

    ``tol`` defaults to ``1e-6`` times the smallest distance between two
    points of B (or, for a one-point B, the shortest nonzero vector of A).

    Raises
    ------
    UsageError
        If B or A is malformed (empty, repeated points, B[0] not the origin).
    """
    xy = _points(points, "points")
    bp = _points(basic, "basic pattern B")
    av = _points(assembling, "assembling graph A")
    if len(bp) == 0:
        raise UsageError("basic pattern B is empty", fix="give at least the point (0, 0)")
    if len(av) == 0:
        raise UsageError("assembling graph A is empty", fix="give at least one vector")
    if tol is None:
        tol = default_tol(bp, av)
    n, b = len(xy), len(bp)
    if n == 0:
        return FormationQuality(False, None, (Fraction(0), Fraction(1)), None, None, "none", {"robots": 0},
                                message="no robots")
    cands = candidate_parts(xy, bp, tol)
    ob = bp.mean(axis=0)

    if n % b == 0:
        full = [ms for ms, _ in cands if len(ms) == b]
        shift = {ms: c for ms, c in cands if len(ms) == b}
        covers, state = _exact_covers(n, full, max_cover_nodes)
        best = None
        count = 0
        for cover in covers:
            count += 1
            centers = [ob + shift[full[k]] for k in cover]
            comps = _components(centers, av, tol)
            if best is None or comps < best[0]:
                best = (comps, cover)
            if comps == 1 and count > 1:
                break
        size = {"robots": n, "basic_points": b, "full_copies": len(full), "search_nodes": state["nodes"]}
        if best is not None:
            comps, cover = best
            parts = tuple((tuple(float(x) for x in ob + shift[full[k]]), full[k]) for k in cover)
            several = "several" if count > 1 else ("one" if state["complete"] else "unknown")
            delta = Fraction(1, comps)
            exact_delta = comps == 1 or state["complete"]
            msg = (f"gamma = 1: {len(cover)} full copies of B cover all {n} robots; their centers form "
                   f"{comps} component(s) under A")
            if not exact_delta:
                msg += f" (search stopped after {state['nodes']} nodes: a partition with fewer may exist)"
            scope = "the best optimal partition" if exact_delta else "the best optimal partition seen"
            return FormationQuality(True, Fraction(1), (Fraction(1), Fraction(1)), delta, delta, "perfect-cover",
                                    size, parts, comps, several, False, msg, delta_of=scope)
        if not state["complete"]:
            return FormationQuality(False, None, (Fraction(1, b), _upper_bound(n, b)), None, None, "perfect-cover",
                                    size, message=f"the exact-cover search stopped after {state['nodes']} nodes "
                                                  "without an answer")
    if len(cands) > MAX_CANDIDATES:
        return FormationQuality(False, None, (Fraction(1, b), _upper_bound(n, b)), None, None, "milp",
                                {"robots": n, "candidate_parts": len(cands)},
                                message=f"{len(cands)} candidate parts: more than {MAX_CANDIDATES}, not attempted")
    exact, parts, ratio, size = _milp_gamma(n, b, cands, xy - bp[0], max_milp_nodes)
    parts = _best_translations(parts, xy, bp, av, tol)
    centers = [ob + c for c, _ in parts if c is not None]
    comps = _components(centers, av, tol)
    delta = Fraction(1, comps) if comps else None
    ambiguous = any(c is not None and len(ms) < b for c, ms in parts)
    out_parts = tuple((None if c is None else tuple(float(x) for x in ob + c), ms) for c, ms in parts)
    if not exact:
        return FormationQuality(False, None, (ratio, _upper_bound(n, b)), None, None, "milp", size, out_parts,
                                message=f"the integer program stopped on its node budget ({max_milp_nodes}); "
                                        f"gamma is at least {ratio}")
    eps = None if delta is None else ratio * delta
    rest = sum(1 for c, _ in parts if c is None)
    msg = (f"gamma = {ratio}: {len(parts) - rest} compatible part(s)" + (" and an incompatible rest" if rest else "")
           + f" among {n} robots; {comps} component(s) under A")
    return FormationQuality(True, ratio, (ratio, ratio), delta, eps, "milp", size, out_parts, comps, "unknown",
                            ambiguous, msg)


def default_tol(basic, assembling) -> float:
    """``1e-6`` times the pattern's smallest length: between two points of B, or (one-point B)
    the shortest nonzero vector of A; 1e-6 when neither exists."""
    bp = _points(basic, "basic pattern B")
    av = _points(assembling, "assembling graph A")
    lengths = []
    if len(bp) > 1:
        d = np.hypot(bp[:, None, 0] - bp[None, :, 0], bp[:, None, 1] - bp[None, :, 1])
        lengths.append(float(d[np.triu_indices(len(bp), 1)].min()))
    nz = [float(math.hypot(*a)) for a in av if math.hypot(*a) > 0]
    if len(bp) <= 1 and nz:
        lengths.append(min(nz))
    scale = min(lengths) if lengths and min(lengths) > 0 else 1.0
    return 1e-6 * scale
