"""Song & O'Kane 2014: authority trees, local Hungarian matching, bounded-range motion.

A faithful reference implementation of 000_3ad33c5b62f11d5f.txt ("Decentralized
Formation of Arbitrary Multi-Robot Lattices", ICRA 2014), Sec. IV.  It is
*not repaired*: the 2016 paper (001 Sec. I) says this algorithm may oscillate
and that its orphans' motion "often caused the team to become disconnected";
both behaviours are kept so that the explorer can find them.

Every step each robot (000 Sec. I, steps 1-4, and Sec. IV):

1. **Authority** (Sec. IV-A, Defs. 4-5): discards received messages whose
   authority contains its own ID, compares its own ``<id>`` with the rest
   (:func:`authority_key`), and becomes a *root* or picks the sender of the
   highest authority as its *parent*, appending its ID (:func:`select_parent`).
2. **Role** (Sec. IV-B-1/2): a root takes ``lattice.v0``; a descendant takes
   the terminal vertex of the edge its parent's matching gives its ID.
3. **Local task assignment** (Def. 6): an ``N x max(N, E)`` matrix of body-frame
   distances, null columns as a last resort, for a descendant the parent's
   row and the inverse edge's column forced (:func:`weight_matrix`,
   :func:`solve_matching`); the matching is broadcast with the authority.
4. **Motion** (Sec. IV-C): roots stay; a descendant goes to the point of the
   intersection of its reach (radius ``v*dt``) and the disc of radius
   ``phi - v*dt`` around its parent (Lemma 7, Fig. 6) nearest its ultimate
   destination, and at the destination turns to the heading of Eq. 8
   (:func:`descendant_motion`).
5. **Unmatched robots** (Sec. IV-D): a descendant matched to the null value
   by its parent moves directly away from the parent for ``2*phi/v`` time,
   silent and neither root nor descendant, then resumes.

The readings of the paper's gaps are recorded in docs/decisions.md
("## song2014"); docs/song2014.md maps each function to the paper.

References
----------
000_3ad33c5b62f11d5f.txt, Sec. III-A (robots), IV-A..IV-D, Defs. 4-6,
Lemma 7, Eq. 8, Fig. 6.  001_7a4e517b856331bc.txt, Sec. I (its flaws).

Examples
--------
Five robots that all see each other form the letter F (Fig. 11); see
``tests/reference_impl/test_song2014.py``.  The pure pieces:

>>> authority_key((7, 3, 5))
(7, -3, 5)
>>> select_parent(4, {9: Song2014Message((9,), ()), 5: Song2014Message((5,), ())})
(9, (9, 4))
>>> select_parent(9, {5: Song2014Message((5,), ())})
(None, (9,))
"""

from __future__ import annotations

import math
from typing import Hashable, Mapping, NamedTuple, Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

from swarmproof.models.errors import AssumptionError, ProtocolError
from swarmproof.models.geometry import nearest_xy
from swarmproof.models.se2 import wrap_angle

from ..protocol import (Assumption, Command, ExhaustiveCell, Observation, Params, ParamSpec, RobotModel,
                        VerifyPlan)

__all__ = [
    "Song2014", "Song2014Controller", "Song2014Message", "authority_key", "is_higher",
    "select_parent", "weight_matrix", "solve_matching", "match_positions", "descendant_motion",
    "unmatched_steps", "ROLE_UNMATCHED", "NEVER",
]

#: ``state()`` role value of a robot in the unmatched (dispersal) phase, Sec. IV-D.
ROLE_UNMATCHED = "<unmatched>"
#: Dispersal length (steps) standing for "forever" when ``v = 0``.
NEVER = 2**62


class Song2014Message(NamedTuple):
    """The broadcast message of 000 Sec. IV: an authority and a matching.

    Attributes
    ----------
    authority : tuple of int
        Def. 4: ``<id_1, ..., id_k>``, root first, sender last.
    matching : tuple of (int, int or None)
        Def. 6: ``(neighbor ID, lattice edge index)`` pairs in increasing
        neighbor-ID order; ``None`` is the null value.  Empty when the
        sender has no role this step (see docs/decisions.md).
    """

    authority: tuple[int, ...]
    matching: tuple[tuple[int, int | None], ...]


# ---------------------------------------------------------------------------
# Sec. IV-A: authorities
# ---------------------------------------------------------------------------

def authority_key(authority: Sequence[int]) -> tuple:
    """Sort key of an authority under Def. 5: higher key, higher authority.

    Def. 5 ranks by (1) the higher root ID, then (2) the shorter length, then
    (3) the higher sender ID.  Two authorities with equal keys are the
    "incomparable" pairs of Def. 5 (or equal); the paper notes they never
    meet because senders are unique within one comparison.

    Examples
    --------
    >>> authority_key((3,)) > authority_key((2, 9))       # higher root wins
    True
    >>> authority_key((5, 1)) > authority_key((5, 8, 9))   # same root: shorter wins
    True
    >>> authority_key((5, 2)) > authority_key((5, 1))      # same root, length: sender
    True

    References
    ----------
    000 Sec. IV-A-1, Definition 5.
    """
    return (authority[0], -len(authority), authority[-1])


def is_higher(a2: Sequence[int], a1: Sequence[int]) -> bool:
    """Def. 5 verbatim: is authority ``a2`` higher than ``a1``?

    Examples
    --------
    >>> is_higher((4, 1), (3,)), is_higher((3,), (4, 1))
    (True, False)
    >>> is_higher((4, 1, 2), (4, 3, 2))   # incomparable under Def. 5
    False

    References
    ----------
    000 Sec. IV-A-1, Definition 5 (items 1-3).
    """
    if a2[0] != a1[0]:
        return a2[0] > a1[0]
    if len(a2) != len(a1):
        return len(a2) < len(a1)
    return a2[-1] > a1[-1]


def select_parent(own_id: int, messages: Mapping[int, "Song2014Message | None"]
                  ) -> tuple[int | None, tuple[int, ...]]:
    """Choose root or parent and build this step's authority (Sec. IV-A-2).

    Parameters
    ----------
    own_id : int
        This robot's ID.
    messages : mapping
        Sender ID -> the message it broadcast last step (``None``: silent).

    Returns
    -------
    parent : int or None
        None when the robot becomes a root (its own ``<id>`` is highest),
        else the sender of the highest remaining authority.
    authority : tuple of int
        ``(own_id,)`` for a root, else the highest authority with ``own_id``
        appended.

    Raises
    ------
    ProtocolError
        If two remaining authorities tie under Def. 5 (the paper says this
        cannot occur; it is reported rather than resolved silently).

    References
    ----------
    000 Sec. IV-A-2: discard messages whose authority holds the own ID;
    compare ``<id(r_i)>`` with the rest; root if it is the highest, else the
    sender of the highest becomes the parent and ``id(r_i)`` is appended.
    """
    best_key = authority_key((own_id,))
    best_sender: int | None = None
    best_auth: tuple[int, ...] = (own_id,)
    tie = False
    for sender, msg in messages.items():
        if msg is None:
            continue
        auth = msg.authority
        if own_id in auth:
            continue
        key = authority_key(auth)
        if key > best_key:
            best_key, best_sender, best_auth, tie = key, sender, tuple(auth), False
        elif key == best_key:
            tie = True
    if tie:
        raise ProtocolError(f"own_id={own_id!r}: two received authorities tie under Def. 5 "
                            f"(key={best_key!r}); 000 Sec. IV-A says senders are unique")
    if best_sender is None:
        return None, (own_id,)
    return best_sender, best_auth + (own_id,)


# ---------------------------------------------------------------------------
# Sec. IV-B: local task assignment (Def. 6)
# ---------------------------------------------------------------------------

def weight_matrix(neighbor_xy: np.ndarray, edge_xy: np.ndarray,
                  forced: tuple[int, int] | None = None) -> np.ndarray:
    """The ``N x max(N, E)`` weight matrix of Def. 6, with the paper's infinities.

    Parameters
    ----------
    neighbor_xy : numpy.ndarray, shape (N, 2)
        Neighbors' positions in this robot's body frame (its observations).
    edge_xy : numpy.ndarray, shape (E, 2)
        Desired positions ``T(e) [0 0 1]^T`` (Eq. 4) of the role's out-edges.
    forced : (row, column), optional
        For a descendant (Sec. IV-B-2): the parent's row and the inverse
        edge's column; both are set to ``inf`` except where they meet (0).

    Returns
    -------
    numpy.ndarray, shape (N, max(N, E))
        Columns ``0..E-1`` are edges (Euclidean distances), the rest are null
        columns set to ``inf`` ("a last resort", Sec. IV-B-1 item 4).

    Examples
    --------
    >>> w = weight_matrix(np.array([[1.0, 0], [0, 1], [3, 0]]), np.array([[1.0, 0], [0, 1]]))
    >>> w.round(3).tolist()
    [[0.0, 1.414, inf], [1.414, 0.0, inf], [2.0, 3.162, inf]]

    References
    ----------
    000 Sec. IV-B-1 items 1-4, Eq. 4; Sec. IV-B-2 (forced row and column).
    """
    n, e = len(neighbor_xy), len(edge_xy)
    m = max(n, e)
    w = np.full((n, m), np.inf)
    if n and e:
        diff = neighbor_xy[:, None, :] - edge_xy[None, :, :]
        w[:, :e] = np.hypot(diff[..., 0], diff[..., 1])
    if forced is not None:
        r, c = forced
        w[r, :] = np.inf
        w[:, c] = np.inf
        w[r, c] = 0.0
    return w


def solve_matching(w: np.ndarray, n_edges: int, forced: tuple[int, int] | None = None) -> list[int | None]:
    """Optimal matching of Def. 6 over a :func:`weight_matrix`, checked.

    scipy's ``linear_sum_assignment`` (Kuhn's Hungarian problem, Sec. IV-B-1)
    rejects infeasible matrices, so the paper's ``inf`` entries are encoded
    as large finite costs (DESIGN.md section 4):

    * null-column entries get one constant ``null_cost``.  Every complete
      assignment of the ``N x max(N, E)`` matrix uses exactly
      ``max(N, E) - E`` null columns, so this constant never changes which
      assignment is optimal: the optimum is the paper's (minimum total
      distance over the edges actually assigned).
    * forced ``inf`` entries (Sec. IV-B-2) get ``forbid_cost`` larger than
      the cost of any assignment that avoids them (one always exists: the
      forced cell itself plus any matching of the rest), so they are never
      chosen by an optimum.

    The result is then checked: no forced ``inf`` entry is used and the
    forced cell is.  A failure raises :class:`ProtocolError`.

    Parameters
    ----------
    w : numpy.ndarray, shape (N, max(N, E))
        From :func:`weight_matrix`.
    n_edges : int
        ``E``: the number of edge columns.
    forced : (row, column), optional
        The forced cell, as given to :func:`weight_matrix`.

    Returns
    -------
    list of int or None
        For each row, the matched edge column (``0..E-1``) or None (null).

    Examples
    --------
    >>> w = weight_matrix(np.array([[1.0, 0], [0, 1], [3, 0]]), np.array([[1.0, 0], [0, 1]]))
    >>> solve_matching(w, 2)
    [0, 1, None]
    >>> solve_matching(weight_matrix(np.array([[1.0, 0], [0, 1], [3, 0]]),
    ...                np.array([[1.0, 0], [0, 1]]), forced=(2, 0)), 2, forced=(2, 0))
    [None, 1, 0]

    References
    ----------
    000 Sec. IV-B-1 (Def. 6, weight matrix, Hungarian algorithm [6]) and IV-B-2.
    """
    n, m = w.shape
    if n == 0:
        return []
    finite = np.isfinite(w)
    edge_part = w[:, :n_edges]
    fmax = float(edge_part[np.isfinite(edge_part)].max()) if np.isfinite(edge_part).any() else 0.0
    null_cost = n * (fmax + 1.0)
    forbid_cost = (n + 1) * (null_cost + fmax + 1.0)
    cost = np.where(finite, w, forbid_cost)
    # Null columns (beyond E) are the paper's "last resort" infinities, unless
    # a forced row/column made them forbidden (the forced row/column of
    # Sec. IV-B-2 covers null columns too).
    if m > n_edges:
        null_block = np.full((n, m - n_edges), null_cost)
        if forced is not None:
            null_block[forced[0], :] = forbid_cost
        cost[:, n_edges:] = null_block
    rows, cols = linear_sum_assignment(cost)
    out: list[int | None] = [None] * n
    for r, c in zip(rows.tolist(), cols.tolist()):
        if c < n_edges:
            if not finite[r, c]:
                raise ProtocolError(f"matching chose an infinite entry (row={r}, column={c}) of "
                                    f"the Def. 6 matrix; the encoding is wrong")
            out[r] = c
    if forced is not None and out[forced[0]] != forced[1]:
        raise ProtocolError(f"forced cell {forced!r} of Sec. IV-B-2 was not chosen: {out!r}")
    if len(rows) != n:
        raise ProtocolError(f"matching left rows unassigned: {n - len(rows)} of {n}")
    return out


def match_positions(neighbor_xy: np.ndarray, edge_xy: np.ndarray,
                    forced: tuple[int, int] | None = None) -> list[int | None]:
    """:func:`solve_matching` of :func:`weight_matrix`, fused for the hot path.

    Builds the same finite encoding directly from positions (no ``inf``
    matrix), solves it and checks the forced cell.  The tests check that it
    returns exactly what ``solve_matching(weight_matrix(...))`` returns.

    Examples
    --------
    >>> match_positions(np.array([[1.0, 0], [0, 1], [3, 0]]), np.array([[1.0, 0], [0, 1]]))
    [0, 1, None]
    """
    n, e = len(neighbor_xy), len(edge_xy)
    if n == 0:
        return []
    m = n if n > e else e
    cost = np.empty((n, m))
    if e:
        diff = neighbor_xy[:, None, :] - edge_xy[None, :, :]
        d = np.sqrt(diff[..., 0] ** 2 + diff[..., 1] ** 2)
        if forced is not None:
            d[forced[0], :] = 0.0
            d[:, forced[1]] = 0.0
        fmax = float(d.max())
        cost[:, :e] = d
    else:
        fmax = 0.0
    null_cost = n * (fmax + 1.0)
    cost[:, e:] = null_cost
    if forced is not None:
        r, c = forced
        forbid_cost = (n + 1) * (null_cost + fmax + 1.0)
        cost[r, :] = forbid_cost
        cost[:, c] = forbid_cost
        cost[r, c] = 0.0
    rows, cols = linear_sum_assignment(cost)
    out: list[int | None] = [c if c < e else None for c in cols.tolist()]
    if forced is not None and out[forced[0]] != forced[1]:
        raise ProtocolError(f"forced cell {forced!r} of Sec. IV-B-2 was not chosen: {out!r}")
    return out


# ---------------------------------------------------------------------------
# Sec. IV-C and IV-D: motion
# ---------------------------------------------------------------------------

def descendant_motion(parent_pose, edge_pose, params: Params, arrive_tol: float,
                      heading_tol: float = 1e-9) -> tuple[float, float, tuple[float, float, float]]:
    """One descendant step of Sec. IV-C: ``(turn, forward, destination)``.

    Parameters
    ----------
    parent_pose : (x, y, theta)
        The parent's pose in this robot's body frame (sensed now).
    edge_pose : (x, y, theta)
        ``T(e)`` of the edge the parent matched this robot to.
    params : Params
        ``range`` (phi), ``v``, ``dt``.
    arrive_tol : float
        Distance under which the ultimate destination counts as reached.
    heading_tol : float
        Heading error (radians) under which no turn is commanded.

    Returns
    -------
    turn, forward : float
        The intent (the engine clamps it: turn at most ``omega*dt``, then
        drive what time is left).
    destination : (x, y, theta)
        The ultimate destination ``p_bar`` in this robot's body frame.

    Notes
    -----
    Steps 1-3 of Sec. IV-C: the destination is the parent's pose composed
    with ``T(e)``; ``P_i`` is the disc of radius ``v*dt`` around this robot;
    ``P_p`` the disc of radius ``phi - v*dt`` around the parent (Lemma 7);
    the intermediate destination is the nearest point of ``P_i & P_p``.
    The robot "turns itself to face the target position and directly
    drives itself there".  At the destination it turns to the heading of
    Eq. 8 (the rotation of ``T(e)`` in the parent's frame).  If the two
    discs do not meet (only possible when ``v*dt >= phi`` or the parent is
    not really within range), the robot does not move.

    Examples
    --------
    >>> p = Params(range=1.0, v=0.1, omega=math.pi, dt=1.0)
    >>> t, f, d = descendant_motion((0.5, 0, 0), (0.5, 0, 0), p, 1e-9)
    >>> round(t, 9), round(f, 9), [round(x, 9) for x in d]
    (0.0, 0.1, [1.0, 0.0, 0.0])

    References
    ----------
    000 Sec. IV-C, Lemma 7, Fig. 6, Eq. 8.
    """
    px, py, pth = float(parent_pose[0]), float(parent_pose[1]), float(parent_pose[2])
    ex, ey, eth = edge_pose
    c, s = math.cos(pth), math.sin(pth)
    dx, dy = px + c * ex - s * ey, py + s * ex + c * ey
    dth = float(wrap_angle(pth + eth))
    dest = (dx, dy, dth)
    if math.hypot(dx, dy) <= arrive_tol:
        turn = dth if abs(dth) > heading_tol else 0.0
        return turn, 0.0, dest
    reach = params.v * params.dt
    r_parent = params.range - reach
    if r_parent < 0.0:
        return 0.0, 0.0, dest
    q = nearest_xy(0.0, 0.0, reach, float(px), float(py), r_parent, dx, dy)
    if q is None:
        return 0.0, 0.0, dest
    qx, qy = q
    dist = math.hypot(qx, qy)
    if dist <= arrive_tol:
        return 0.0, 0.0, dest
    return math.atan2(qy, qx), dist, dest


def unmatched_steps(params: Params) -> int:
    """Number of steps of the dispersal period ``2*phi/v`` (Sec. IV-D), rounded up.

    >>> unmatched_steps(Params(range=1.0, v=0.05, dt=1.0))
    40

    With ``v = 0`` (assumption ``positive_speed`` broken on purpose) the
    period is infinite: the robot never resumes.

    >>> unmatched_steps(Params(range=1.0, v=0.0)) == NEVER
    True
    """
    if params.v * params.dt <= 0:
        return NEVER
    return max(1, math.ceil(2.0 * params.range / params.v / params.dt - 1e-9))


# ---------------------------------------------------------------------------
# The controller and the algorithm
# ---------------------------------------------------------------------------

class _RoleTable:
    """Per-lattice precomputation: each role's out-edges and every edge's inverse."""

    def __init__(self, lattice) -> None:
        self.v0 = lattice.v0
        self.edges = lattice.edges
        self.edge_pose = [(e.transform.x, e.transform.y, e.transform.theta) for e in self.edges]
        self.out: dict[str, tuple[list[int], np.ndarray]] = {}
        for role in lattice.roles:
            out = lattice.out_edges(role)
            idx = [e.index for e in out]
            xy = np.array([[e.transform.x, e.transform.y] for e in out], dtype=float).reshape(-1, 2)
            self.out[role] = (idx, xy)
        self.inverse: dict[int, int] = {}
        for e in self.edges:
            inv = lattice.find_inverse(e)
            if inv is None:
                raise AssumptionError(
                    "inverse_edges",
                    f"edge {e.describe()} of lattice {lattice.name!r} has no inverse edge",
                    fix="Def. 1 of 000 requires every edge to have an inverse; add it "
                        "(LatticeGraph.add_inverses) or fix the lattice file")
            self.inverse[e.index] = inv.index


class Song2014Controller:
    """One robot running 000 Sec. IV.  Made by :meth:`Song2014.controller`.

    :meth:`state` returns a tuple of ``(key, value)`` pairs:

    ``role``
        The role vertex (str) this step; None for a descendant its parent did
        not match yet; :data:`ROLE_UNMATCHED` during dispersal (Sec. IV-D).
    ``parent``
        The parent's ID, or None (root, or unmatched).
    ``root``
        True when the robot is a root this step.
    ``authority``
        The authority it broadcast (Def. 4), ``()`` when silent.
    ``unmatched_until``
        The first step of normal execution after dispersal, or None.
    ``edge``
        Index of the lattice edge its parent matched it to, or None.
    ``target``
        The ultimate destination ``(x, y, theta)`` in its body frame
        (rounded to 9 decimals), or None (roots and robots without one).
    ``matching``
        The matching it broadcast (``(neighbor ID, edge index or None)``).
    ``away_turn``
        The turn still owed toward "directly away from the parent" (Sec. IV-D).
    """

    __slots__ = ("robot_id", "params", "table", "arrive_tol", "heading_tol", "_disperse_steps",
                 "role", "parent", "root", "authority", "unmatched_until", "edge", "target",
                 "matching", "away_turn")

    def __init__(self, robot_id: int, params: Params, table: _RoleTable) -> None:
        self.robot_id = robot_id
        self.params = params
        self.table = table
        self.arrive_tol = float(params.extra.get("arrive_tol", 1e-9 * params.range))
        self.heading_tol = float(params.extra.get("heading_tol", 1e-9))
        self._disperse_steps = unmatched_steps(params)
        self.role: str | None = None
        self.parent: int | None = None
        self.root = False
        self.authority: tuple[int, ...] = ()
        self.unmatched_until: int | None = None
        self.edge: int | None = None
        self.target: tuple[float, float, float] | None = None
        self.matching: tuple[tuple[int, int | None], ...] = ()
        self.away_turn = 0.0

    # -- Sec. IV-D ---------------------------------------------------------
    def _disperse(self) -> Command:
        """Move directly away from the parent: finish the owed turn, then drive."""
        p = self.params
        max_turn = p.omega * p.dt
        turn = max(-max_turn, min(max_turn, self.away_turn))
        self.away_turn -= turn
        if abs(self.away_turn) < 1e-12:
            self.away_turn = 0.0
        forward = p.v * max(0.0, p.dt - abs(turn) / p.omega)
        return Command(message=None, turn=turn, forward=forward)

    def _start_dispersal(self, step: int, parent_xy) -> Command:
        self.role = ROLE_UNMATCHED
        self.root = False
        self.parent = None
        self.authority = ()
        self.matching = ()
        self.edge = None
        self.target = None
        self.unmatched_until = step + self._disperse_steps
        self.away_turn = math.atan2(-float(parent_xy[1]), -float(parent_xy[0]))
        return self._disperse()

    # -- the step -----------------------------------------------------------
    def step(self, obs: Observation) -> Command:
        """One synchronous step of 000 Sec. IV (see the module docstring)."""
        if self.unmatched_until is not None:
            if obs.step < self.unmatched_until:
                return self._disperse()      # Sec. IV-D: silent, neither root nor descendant
            self.unmatched_until = None       # "the robot resumes normal execution"
            self.away_turn = 0.0
        ids = obs.neighbor_ids or ()
        poses = obs.neighbor_poses
        # Sec. IV-A-2: root or parent, and this step's authority.
        parent, authority = select_parent(self.robot_id, obs.messages)
        self.parent, self.authority, self.root = parent, authority, parent is None
        self.edge, self.target = None, None
        row_of = {nid: k for k, nid in enumerate(ids)}
        forced_edge: int | None = None
        turn = forward = 0.0
        if parent is None:
            role: str | None = self.table.v0          # Sec. IV-B-1: f(r_i) = v0
        else:
            pmsg = obs.messages[parent]
            assigned = _lookup(pmsg.matching, self.robot_id)
            prow = row_of.get(parent)
            if assigned is _ABSENT or prow is None:
                # Not in the parent's matching (it did not see this robot last
                # step) or the parent is not sensed: no role this step
                # (docs/decisions.md, song2014).
                role = None
            elif assigned is None:
                # Sec. IV-D: matched to the null value by the parent.
                return self._start_dispersal(obs.step, poses[prow, :2])
            else:
                edge = self.table.edges[assigned]
                role = edge.target                    # Sec. IV-B-2: terminal vertex
                self.edge = assigned
                forced_edge = self.table.inverse[assigned]
                turn, forward, dest = descendant_motion(
                    tuple(poses[prow]), self.table.edge_pose[assigned], self.params,
                    self.arrive_tol, self.heading_tol)
                self.target = dest
        self.role = role
        if role is None:
            self.matching = ()
            return Command(message=Song2014Message(authority, ()), turn=0.0, forward=0.0)
        # Def. 6: local task assignment for the neighbors.
        idx, exy = self.table.out[role]
        forced = None
        if forced_edge is not None:
            forced = (row_of[parent], idx.index(forced_edge))
        cols = match_positions(np.asarray(poses[:, :2], dtype=float), exy, forced)
        self.matching = tuple((nid, None if c is None else idx[c]) for nid, c in zip(ids, cols))
        return Command(message=Song2014Message(authority, self.matching), turn=turn, forward=forward)

    def state(self) -> Hashable:
        """Hashable snapshot (see the class docstring for the keys)."""
        t = self.target
        return (("role", self.role), ("parent", self.parent), ("root", self.root),
                ("authority", self.authority), ("unmatched_until", self.unmatched_until),
                ("edge", self.edge),
                ("target", None if t is None else (round(t[0], 9), round(t[1], 9), round(t[2], 9))),
                ("matching", self.matching),
                ("away_turn", round(self.away_turn, 12)))


_ABSENT = object()


def _lookup(matching, robot_id):
    for nid, e in matching:
        if nid == robot_id:
            return e
    return _ABSENT


def _check_v_dt(params: Params, n: int, ids) -> str | None:
    s = params.v * params.dt
    if s < params.range:
        return None
    return (f"v*dt={s!r} (v={params.v!r}, dt={params.dt!r}) is not below range={params.range!r}: "
            f"the parent disc of radius phi - v*dt is empty")


def _check_positive_speed(params: Params, n: int, ids) -> str | None:
    if params.v > 0:
        return None
    return f"v={params.v!r} is not > 0: the dispersal period 2*phi/v is infinite"


def _check_unique_ids(params: Params, n: int, ids) -> str | None:
    if ids is None:
        return "ids=None: the algorithm needs robot IDs"
    ids = list(ids)
    if len(set(ids)) == len(ids):
        return None
    dup = sorted({i for i in ids if ids.count(i) > 1})
    return f"ids are not unique: duplicated {dup!r}"


class Song2014:
    """The Song & O'Kane 2014 algorithm, as the engine and the checkers see it.

    Attributes
    ----------
    name : str
        ``"song2014"``.
    model : RobotModel
        Local body-frame sensing with IDs, broadcast to neighbors,
        differential drive, synchronous steps (000 Sec. III-A).
    assumptions : tuple of Assumption
        ``v_dt_below_range`` (Lemma 7), ``unique_ids`` (Sec. III-A-1) and
        ``positive_speed`` (Sec. IV-D's period ``2*phi/v``).
        Def. 1's inverse edges are checked when a controller is made
        (:class:`~swarmproof.models.errors.AssumptionError`).

    Examples
    --------
    >>> alg = Song2014()
    >>> [a.name for a in alg.assumptions]
    ['v_dt_below_range', 'unique_ids', 'positive_speed']
    >>> alg.assumptions[0].check(Params(range=1.0, v=2.0, dt=1.0), 2, [0, 1])
    'v*dt=2.0 (v=2.0, dt=1.0) is not below range=1.0: the parent disc of radius phi - v*dt is empty'
    >>> alg.finished([])
    False
    """

    name = "song2014"
    #: The controller-state fields the shared checkers may read (swarmproof.invariants.capabilities):
    #: ``parent`` (its spanning tree, Sec. IV) and ``role``.
    state_fields = ("role", "parent")
    #: The seed paper (docs/references.md) whose claims ``claims`` cites.
    paper = "000"
    #: The reading version (protocol.Algorithm.reading: bumped when its behaviour changes on
    #: purpose; CHANGELOG.md).
    reading = "1"
    model = RobotModel(sensing="local", communication="neighbors", motion="differential",
                       clocks="sync")
    #: What 000 claims, property -> citation; ``None``: not claimed (001 Sec. I says so of
    #: the 2014 algorithm), a violation is then a finding, not a failed claim.
    claims = {
        "termination": None,   # 001 Sec. I: "no guarantee that the robots will eventually ... terminate"
        "formation": None,     # 001 Sec. I: "no guarantee that the robots will eventually form the desired pattern"
        "connectivity": None,  # 001 Sec. I: orphans' motion "often caused the team to become disconnected"
        "tree_links": "000 Lemma 7 (a descendant stays within range of its parent)",
    }
    #: 000 Lemma 7's premises: moves at most v dt, ends in the parent's disc phi - v dt.
    premise_monitors = ("step_bounded", "parent_bounded_range")
    #: ``swarmproof prove``'s lemmas about it (000's): Lemma 7 and its strict form, the
    #: intermediate goal of Sec. IV-C (``swarmproof prove --algorithm song2014``).
    lemmas = ("bounded_range", "bounded_range_strict", "intermediate_goal_in_region")
    #: ``swarmproof verify``: the periodic lattices of 000 Figs. 2, 3, 7, 10 robots, 3 starts.
    verify = VerifyPlan(targets=("square", "hexagon", "octagon-square"), robots=10, seeds=(0, 1, 2), rank=1,
                        explore_cost=44,
                        # every schedule of 3 robots with one robot idle once, to the runs' end (90 steps;
                        # oscillation is judged on whole runs) (issue 33): ~15 s CPU
                        exhaustive=(ExhaustiveCell(("connectivity", "oscillation"), ("activate",), steps=90,
                                                   deviations=1),))
    #: Its ``Params.extra`` keys (the engine refuses any other) and the kind of target it forms.
    parameters = (
        ParamSpec("arrive_tol", float, None, low=0,
                  meaning="a robot this close to its destination has arrived; default 1e-9 * range"),
        ParamSpec("heading_tol", float, 1e-9, low=0, meaning="arrival tolerance of the heading, radians"),
    )
    target_kinds = ("lattice",)
    assumptions = (
        Assumption("v_dt_below_range", "v*dt < phi",
                   "000 Sec. IV-C, Lemma 7 (the disc of radius phi - v*dt)", _check_v_dt),
        Assumption("unique_ids", "every robot has a unique ID from a total order",
                   "000 Sec. III-A-1", _check_unique_ids),
        Assumption("positive_speed", "v > 0",
                   "000 Sec. III-A-3 (v_max) and Sec. IV-D (the period 2*phi/v)",
                   _check_positive_speed),
    )

    def __init__(self) -> None:
        self._tables: dict[int, tuple] = {}

    def controller(self, robot_id: int | None, params: Params, lattice,
                   rng: np.random.Generator) -> Song2014Controller:
        """A fresh controller for one robot (the algorithm uses no randomness)."""
        cached = self._tables.get(id(lattice))
        if cached is not None and cached[0] is lattice:
            table = cached[1]
        else:
            table = _RoleTable(lattice)
            # Keep the lattice referenced so its id() cannot be reused.
            self._tables = {id(lattice): (lattice, table)}
        if robot_id is None:
            raise AssumptionError("unique_ids", "robot_id=None: the algorithm needs robot IDs")
        return Song2014Controller(robot_id, params, table)

    def finished(self, states: Sequence[Hashable]) -> bool:
        """Always False: the paper has no end condition (Sec. III-C-1 measures the
        time to a static state, Def. 3); the engine stops on a static state or the
        step cap."""
        return False
