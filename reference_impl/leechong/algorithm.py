"""Lee & Chong (003): anonymous robots agree on a frame, allocate IDs, and form, flock and switch patterns.

The algorithms of 003 Secs. 2-4 for the engine:

* **Robot model** (Secs. 2.1, 5.3, 6): anonymous planar points at distinct
  positions, no IDs, no leader, no common frame at the start; every robot senses
  the positions of all others in its own body frame (``sensing="anonymous"``: the
  engine gives positions only -- no IDs, no headings -- ordered by body-frame
  ``(x, y)``, and messages keyed by the row a sender is sensed at, never by an
  ID).  The only messages are the two the paper names: a failed robot's ID (Sec.
  3.5) and the leader's pattern command (Sec. 3.6) (``communication="all"``:
  wireless LAN, Sec. 6).  Holonomic motion at most ``v dt`` per step.  A robot
  knows its own motion (it integrates its own commands: odometry), which the
  engine applies exactly.
* **Algorithm 1** (Sec. 2.1): common origin p_o (Eq. 1, the centroid), leader
  (farthest from p_o), common direction u (from p_o to p_l), v (u turned
  90 degrees counter-clockwise), common coordinates (Eqs. 3-4), IDs.  Leader ties
  (two or more robots equally far from p_o): the candidates move slightly
  outward, off the circle (a random distance drawn from their own generator),
  the others stay, and the selection is repeated.
* **Algorithms 2 and 3** (Sec. 3.2): a follower's target f_i in the common
  frame, from its ID, p_l and the pattern F (:mod:`swarmproof.models.line_patterns`).
* **Leader-referenced control** (Sec. 3): the leader stays; every follower
  moves straight to its f_i.  **Neighbor-referenced control** (Sec. 4,
  Algorithm 4): a follower keeps the offset ``f_i - f_N`` (distance and local
  angle) to its neighbor N_id's current position, and follows it.
* **Flocking** (Secs. 3.3, 4.3): once the pattern stands, the leader drives to a
  goal; followers do not move until it starts moving, then keep their offset to
  the leader (leader-referenced) or to N_id (neighbor-referenced).
* **Pattern switching** (Secs. 3.4, 3.6, 4.3): the leader, which sees the
  pattern complete, broadcasts the next pattern; the leader and the IDs stay, the
  origin moves to p_l (``u_l = 0``), u is kept.
* **Robustness** (Secs. 3.5, 4.4): a robot that fails stops and broadcasts its
  ID.  A follower's failure: the survivors keep the leader and u, move the
  origin to p_l and re-issue IDs with Algorithm 1's numbering; the leader's
  failure: the survivors repeat Algorithm 1 from where they stand.  ``d_u =
  span / (n - 1)`` with the survivors' n keeps the span.

Readings (docs/decisions.md, "Lee & Chong (issue 17)" and "Lee & Chong: the ID numbering
(issue 31)"): IDs follow Sec. 2.1's prose -- odd IDs below u, even above, "by turns, until the
numbering is completed in either half plane. Remaining members in the other half plane are
assigned their IDs consecutively" (Lee & Chong, Sec. 2.1) -- which is a bijection onto 1..n-1
for every split of the followers and forms every pattern the paper shows formed (Figs. 2, 6, 7)
(``leechong-leader``, ``leechong-neighbor``, reading "2").  Alg. 1's printed formula ``2 x rank``
(v >= 0) / ``2 x rank - 1`` (v < 0), the rank counted within the robot's own half plane by
increasing u (Lee & Chong, Alg. 1 lines 11-14), gives the same IDs when the half planes hold
a = b or b = a + 1 followers and IDs up to 2 (n - 1) otherwise; it is the variant
``leechong-leader-printed`` / ``leechong-neighbor-printed`` (reading "1" of the default names,
their default up to swarmproof 0.1.0).  Sec. 3.2's "robots closer to r_l get IDs 1-4" is the
option ``id_order="leader-first"``.  F-team (Sec. 3.7, robots with fixed IDs) is ``team="F"``:
the robots know a fixed label (RobotModel ``own_id``), the robot labelled 0 leads, and the IDs
are the labels' ranks, so no numbering of Alg. 1 applies to it.

Examples
--------
>>> allocate_ids([(1.0, 0.0), (0.5, 0.3), (0.2, -0.4), (-0.1, 0.2), (-0.6, -0.1)], 0)
[0, 4, 3, 2, 1]
>>> allocate_ids([(1.0, 0.0), (0.5, 0.3), (0.2, 0.4), (-0.1, 0.2)], 0)
[0, 3, 2, 1]
>>> allocate_ids([(1.0, 0.0), (0.5, 0.3), (0.2, 0.4), (-0.1, 0.2)], 0, numbering="formula")
[0, 6, 4, 2]
>>> neighbor_id(7, "uni"), neighbor_id(2, "uni"), neighbor_id(3, "multi", 4), neighbor_id(8, "multi", 4)
(5, 0, 1, 4)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from swarmproof.invariants.algorithm_invariants import Invariant
from swarmproof.models.errors import UsageError
from swarmproof.reference_impl.protocol import (Assumption, Command, Observation, Params, ParamSpec, RobotModel,
                                               VerifyPlan)

from .numbering import neighbor_id

__all__ = ["LeeChongLeader", "LeeChongNeighbor", "LeeChongLeaderPrinted", "LeeChongNeighborPrinted",
           "LeeChongLeaderFTeam", "LeeChongNeighborFTeam",
           "LeeChongController", "Agreement",
           "agree", "allocate_ids", "neighbor_id", "NUMBERINGS", "ID_ORDERS", "TEAMS"]

#: Alg. 1's ID numberings: ``"prose"`` (Sec. 2.1's text: the default since reading "2") and
#: ``"formula"`` (Alg. 1 lines 11-14 as printed: the ``-printed`` variants).
NUMBERINGS = ("prose", "formula")
ID_ORDERS = ("u-increasing", "leader-first")
TEAMS = ("A", "F")
#: Two robots whose distances to p_o differ by at most this (relative to the largest) tie.
TIE_REL = 1e-9
ARRIVE = 1e-9


# ---------------------------------------------------------------------------------------------
# Algorithm 1
# ---------------------------------------------------------------------------------------------

def allocate_ids(common, leader: int, *, numbering: str = "prose", order: str = "u-increasing") -> list:
    """IDs of the robots at common coordinates ``common`` (rows), the leader at row ``leader`` (003 Alg. 1).

    ``numbering="prose"`` (the default; Lee & Chong, Sec. 2.1: "they are assigned an odd ID if
    they have a negative-coordinate of v-axis, or an even ID if they have a positive coordinate
    of v-axis, by turns, until the numbering is completed in either half plane. Remaining
    members in the other half plane are assigned their IDs consecutively, beginning with the
    number after the last number assigned"): odd IDs to the lower half plane, even to the
    upper, by turns (1, 2, 3, ...) until one half plane is used up, then the rest
    consecutively; always a bijection onto 1..n-1.  ``numbering="formula"`` (Lee & Chong,
    Alg. 1 lines 11-14, as printed): a robot with ``v >= 0`` gets ``2 x rank``, one with
    ``v < 0`` gets ``2 x rank - 1``, rank = its place (from 1) among the robots of its own
    half plane by increasing u (ties by increasing v); the same IDs as the prose when the
    half planes hold a = b or b = a + 1 followers, else not a bijection onto 1..n-1 (IDs up to
    2 (n - 1); docs/leechong.md).  ``order="leader-first"`` ranks by decreasing u
    (Sec. 3.2: "robots positioned closer to r_l are assigned ... ID_1 to ID_4").
    """
    if numbering not in NUMBERINGS:
        raise UsageError(f"id_numbering={numbering!r} is not one of {list(NUMBERINGS)!r}")
    if order not in ID_ORDERS:
        raise UsageError(f"id_order={order!r} is not one of {list(ID_ORDERS)!r}")
    pts = [(float(u), float(v)) for u, v in common]
    sign = 1.0 if order == "u-increasing" else -1.0
    upper = sorted((k for k in range(len(pts)) if k != leader and pts[k][1] >= 0.0),
                   key=lambda k: (sign * pts[k][0], pts[k][1]))
    lower = sorted((k for k in range(len(pts)) if k != leader and pts[k][1] < 0.0),
                   key=lambda k: (sign * pts[k][0], pts[k][1]))
    ids = [0] * len(pts)
    if numbering == "formula":
        for rank, k in enumerate(upper, start=1):
            ids[k] = 2 * rank                              # Alg. 1 line 12
        for rank, k in enumerate(lower, start=1):
            ids[k] = 2 * rank - 1                          # Alg. 1 line 14
    else:
        turns = min(len(upper), len(lower))
        for j in range(turns):
            ids[lower[j]] = 2 * j + 1
            ids[upper[j]] = 2 * j + 2
        rest = upper[turns:] if len(upper) > turns else lower[turns:]
        for j, k in enumerate(rest):
            ids[k] = 2 * turns + 1 + j
    return ids


@dataclass(frozen=True)
class Agreement:
    """The outcome of Algorithm 1 on one robot's view (rows of ``points``).

    ``tie`` holds the rows of the leader candidates when the farthest distance is
    shared (then the other fields are None)."""

    origin: tuple | None
    leader: int | None
    u: tuple | None
    common: np.ndarray | None
    ids: tuple | None
    tie: tuple = ()


def agree(points, *, numbering: str = "prose", order: str = "u-increasing", leader: int | None = None) -> Agreement:
    """003 Alg. 1 on ``points`` (an ``(n, 2)`` array in any frame: the result is the same up to
    that frame).  ``leader`` fixes the leader row (F-team, Sec. 3.7) instead of the farthest robot.

    >>> a = agree(np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]]))
    >>> a.leader, a.ids, [round(float(x), 6) for x in a.u]
    (1, (1, 0, 2), [0.970143, -0.242536])
    >>> agree(np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 0.5], [0.0, -0.5]])).tie
    (0, 1)
    """
    return _agree_at(np.asarray(points, dtype=float).reshape(-1, 2), numbering, order, leader)[1]


def _agree_at(pts: np.ndarray, numbering: str, order: str, leader: int | None) -> tuple:
    """:func:`agree` on an ``(n, 2)`` float array: ``(p_o as an array, Agreement)`` (p_o also for a
    tie, which the controller moves its candidates away from)."""
    n = len(pts)
    origin = pts.mean(axis=0)                                            # Eq. (1)
    dist = np.hypot(pts[:, 0] - origin[0], pts[:, 1] - origin[1])
    if leader is None:
        far = float(dist.max()) if n else 0.0
        cands = tuple(int(k) for k in np.flatnonzero(dist >= far - TIE_REL * max(far, 1e-300)))
        if len(cands) > 1:                                               # Sec. 2.1: no unique leader
            return origin, Agreement(None, None, None, None, None, cands)
        leader = cands[0]
    d = pts[leader] - origin
    norm = math.hypot(*d)
    u = (float(d[0] / norm), float(d[1] / norm)) if norm > 0 else (1.0, 0.0)
    rel = pts - origin
    common = np.column_stack((rel @ np.array(u), rel @ np.array((-u[1], u[0]))))   # Eqs. (3)-(4)
    ids = tuple(allocate_ids(common, leader, numbering=numbering, order=order))
    return origin, Agreement((float(origin[0]), float(origin[1])), int(leader), u, common, ids)


# ---------------------------------------------------------------------------------------------
# Algorithm 4
# ---------------------------------------------------------------------------------------------

# ---------------------------------------------------------------------------------------------
# the controller
# ---------------------------------------------------------------------------------------------

def _rot(th: float):
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s], [s, c]])


#: The ``Params.extra`` keys 003's algorithms read (``--param KEY=VALUE``; ``--then``/``--fail``),
#: besides the pattern parameters of :mod:`swarmproof.models.line_patterns` (``alpha_star``, ``m``,
#: ``k``, ``rotation``, ``radius``, ``center``, ``index``, ``noline``), which apply to every pattern.
OPTION_KEYS = ("then", "fail", "flock_to", "position_errors", "error_size", "perturbation", "arrive_tol", "id_order")
PATTERN_PARAM_KEYS = ("alpha_star", "m", "k", "rotation", "radius", "center", "index", "noline")
#: engine keys of ``Params.extra`` that any algorithm may see
_ENGINE_KEYS = ("grid_spacing", "clock_rate_min", "clock_rate_max", "broadcast_every", "robot_radius")

#: The declarations of :data:`OPTION_KEYS` and :data:`PATTERN_PARAM_KEYS` (type, range, meaning): the
#: engine refuses any other key before a run (issue 29).  ``object``: :func:`options_of` and the line
#: patterns check the value themselves (lists, ``ROBOT@STEP``, points).
PARAMETERS = (
    ParamSpec("then", object, (), meaning="patterns to switch to once the present one stands (Secs. 3.4, 3.6)"),
    ParamSpec("fail", object, (), meaning="robots that fail, ROBOT@STEP, ROBOT an allocated ID or 'leader' (Sec. 3.5)"),
    ParamSpec("flock_to", object, None, meaning="a point the formation flocks to (Sec. 3.3)"),
    ParamSpec("position_errors", object, (), meaning="IDs of the followers with a position error (Sec. 5.2)"),
    ParamSpec("error_size", float, 0.3, low=0, meaning="the size of a position error (Sec. 5.2)"),
    ParamSpec("perturbation", float, 0.05, low=0, low_open=True, meaning="the noise of a perturbed start"),
    ParamSpec("arrive_tol", float, 1e-6, low=0, low_open=True, meaning="a robot this close to its target has arrived"),
    ParamSpec("id_order", str, "u-increasing", choices=ID_ORDERS, meaning="the order of Alg. 1's IDs"),
) + tuple(ParamSpec(k, object, None, meaning="a line pattern's parameter (models/line_patterns.py checks it)")
          for k in PATTERN_PARAM_KEYS)


def _positive(name: str, value, example: str, *, zero: bool = False) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise UsageError(f"{name}={value!r} is not a number", fix=f"e.g. --param {name}={example}") from None
    if not math.isfinite(x) or x < 0 or (x == 0 and not zero):
        raise UsageError(f"{name}={value!r} must be a finite number {'>=' if zero else '>'} 0",
                         fix=f"e.g. --param {name}={example}")
    return x


def options_of(extra, *, target_shape: str | None = None, n: int | None = None, numbering: str = "prose") -> dict:
    """003's options from ``Params.extra``, checked: a usage error names the key, the value and the
    fix.  With ``n``, a ``fail`` naming an ID no robot of ``n`` can hold under ``numbering`` (above
    n - 1 for the prose numbering and the F-team's ranks, above 2 (n - 1) for the printed formula,
    Alg. 1 lines 11-14) is refused too.

    >>> options_of({"fail": "leader@5,3@9", "then": "circle"})["fail"]
    {'leader': {5}, 3: {9}}
    >>> options_of({"position_errors": 3})["position_errors"]
    (3,)
    >>> options_of({"nosuch": 1})
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: params.extra nosuch=1 is not an option of Lee & Chong 2008's algorithms; fix: use one of ['then', 'fail', 'flock_to', 'position_errors', 'error_size', 'perturbation', 'arrive_tol', 'id_order', 'alpha_star', 'm', 'k', 'rotation', 'radius', 'center', 'index', 'noline']
    """
    from swarmproof.models import line_patterns as lp

    ex = dict(extra or {})
    for key in ex:
        if key not in OPTION_KEYS + PATTERN_PARAM_KEYS + _ENGINE_KEYS:
            raise UsageError(f"params.extra {key}={ex[key]!r} is not an option of Lee & Chong 2008's algorithms",
                             fix=f"use one of {list(OPTION_KEYS + PATTERN_PARAM_KEYS)!r}")
    order = str(ex.get("id_order", "u-increasing"))
    if order not in ID_ORDERS:
        raise UsageError(f"id_order={order!r} is not one of {list(ID_ORDERS)!r}",
                         fix="--param id_order=u-increasing (Alg. 1 as printed) or leader-first (Sec. 3.2)")
    then = tuple(str(p).strip() for p in _as_list(ex.get("then", ())))
    pattern_params = {k: ex[k] for k in PATTERN_PARAM_KEYS if k in ex}
    for name in ((target_shape,) if target_shape else ()) + then:
        if name not in lp.PATTERN_NAMES:
            raise UsageError(f"pattern={name!r} is not a pattern of 003", fix=f"use one of {list(lp.PATTERN_NAMES)!r}")
        if pattern_params:
            lp._params(name, {k: v for k, v in pattern_params.items()
                              if k in lp.pattern_info(name)["params"]})       # checks the values
    errors = []
    for x in _as_list(ex.get("position_errors", ())):
        try:
            errors.append(int(str(x).strip()))
        except ValueError:
            raise UsageError(f"position_errors={ex['position_errors']!r}: {x!r} is not an ID",
                             fix="--param position_errors=3,6,9 (003 Sec. 5.2)") from None
        if errors[-1] < 1:
            raise UsageError(f"position_errors={ex['position_errors']!r}: ID {errors[-1]} is not a follower's",
                             fix="IDs 1, 2, ... (the leader, 0, computes no target)")
    fail = _failures(ex.get("fail", ()))
    if n is not None:
        top, how = ((2 * max(n - 1, 1), "Alg. 1's printed formula hands out at most 2 (n - 1)") if numbering == "formula"
                    else (max(n - 1, 1), "the IDs are 0..n-1, Sec. 2.1"))
        for who in fail:
            if who != "leader" and who > top:
                raise UsageError(f"fail={who}@...: no robot of {n} can hold ID {who} ({how} = {top})",
                                 fix="name an ID the team allocates, or 'leader'")
    flock = ex.get("flock_to")
    return {"id_order": order, "then": then, "pattern_params": pattern_params,
            "arrive_tol": _positive("arrive_tol", ex.get("arrive_tol", 1e-6), "1e-6"),
            "fail": fail, "position_errors": tuple(errors),
            "error_size": _positive("error_size", ex.get("error_size", 0.3), "0.3", zero=True),
            "flock_to": None if flock in (None, "", ()) else _flock(flock),
            "perturbation": _positive("perturbation", ex.get("perturbation", 0.05), "0.05")}


class LeeChongController:
    """One robot of 003 (leader- or neighbor-referenced); see the module docstring.

    Everything is kept in the robot's *private frame*: its body frame at step 0,
    maintained by integrating its own motion (a holonomic turn, then at most
    ``v dt``; the controller never asks for more, so the engine applies it
    exactly).  Other robots are tracked from step to step by an optimal matching
    of their remembered to their sensed positions (they move at most ``v dt``).
    A failed robot stands still: its position, heard once, is left out of every
    later agreement and matching."""

    def __init__(self, alg, params: Params, target, rng, fixed_id) -> None:
        self.alg = alg
        self.params = params
        self.rng = rng
        self.fixed_id = fixed_id
        opts = options_of(params.extra, target_shape=target.shape)
        self.numbering = alg.numbering
        self.order = opts["id_order"]
        self.mode = alg.mode
        self.patterns = [target.shape] + list(opts["then"])
        self.pattern_k = 0
        self.target = target
        self.span = None
        self.tol = opts["arrive_tol"]
        self.fail_at = opts["fail"]
        self.errors = set(opts["position_errors"])
        self.error_size = opts["error_size"]
        self.flock = opts["flock_to"]
        self.perturb = opts["perturbation"]
        self.label_of: dict = {}               # F-team: ID -> fixed label (tracked with pos_of)
        self.x = self.y = self.th = 0.0        # odometry: the private pose
        self.phase = "agree"
        self.id = None
        self.pos_of: dict = {}                 # alive ID -> private position (tracked)
        self.dead: list = []                   # private positions of failed robots (they stand still)
        self.origin = None                     # common origin, private frame
        self.u = None                          # common direction, unit vector, private frame
        self.u_l = 0.0
        self.lead0 = None                      # the leader's position when the origin was set
        self.d_u = None
        self.goal = None                       # the leader's flocking goal (private frame)
        self.formed = False                    # the leader saw the present pattern stand
        self.error_vec = None
        self.done = False
        self.i_failed = False
        self.failed_at = None
        self.labels: dict = {}                 # F-team: sensed row -> fixed label heard
        self.rebuilds = 0
        self.flocking = False                  # the leader drives to its goal (Sec. 3.3)
        self.my_target = None                  # this follower's f_i now (private frame)
        self._frame = None                     # what the memoised targets below were computed under
        self._targets: dict = {}               # rid -> f_rid (private frame), read-only arrays
        self._line_kind = None                 # Alg. 4's line kind under self._frame
        self._rots: dict = {}                  # +1 / -1 -> (th, _rot(+-th)) last computed

    # -- frames ---------------------------------------------------------------------------------

    def _rotation(self, sign: int) -> np.ndarray:
        """``_rot(self.th)`` (``sign`` 1) or ``_rot(-self.th)`` (``sign`` -1), read-only, memoised
        while the heading stands (the same float object)."""
        th, r = self._rots.get(sign, (None, None))
        if th is not self.th:
            r = _rot(self.th if sign > 0 else -self.th)
            r.setflags(write=False)
            self._rots[sign] = (self.th, r)
        return r

    def _to_private(self, body: np.ndarray) -> np.ndarray:
        return body @ self._rotation(1).T + np.array([self.x, self.y])

    def _to_body(self, p) -> np.ndarray:
        return self._rotation(-1) @ (np.asarray(p, dtype=float) - np.array([self.x, self.y]))

    def _common_to_private(self, uv) -> np.ndarray:
        u = np.array(self.u)
        return np.array(self.origin) + uv[0] * u + uv[1] * np.array((-u[1], u[0]))

    # -- Algorithm 1 and the IDs ----------------------------------------------------------------

    def _live_rows(self, others: np.ndarray) -> list:
        """Rows of the sensed robots that have not failed (a failed robot stands still)."""
        dead = set()
        for p in self.dead:
            if len(others):
                dead.add(int(np.argmin(np.hypot(others[:, 0] - p[0], others[:, 1] - p[1]))))
        return [r for r in range(len(others)) if r not in dead]

    def _agree(self, me: np.ndarray, others: np.ndarray, rows: list):
        """003 Alg. 1 over this robot (row 0) and the live others; None when done, else ``(tie,
        p_o)``: the tied rows and the centre Alg. 1 computed (the candidates move away from it)."""
        pts = np.vstack((me[None, :], others[rows]))
        leader_row = None
        if self.alg.team == "F":
            labels = [self.fixed_id] + [self.labels.get(r) for r in rows]
            leader_row = labels.index(min(labels))
        centre, a = _agree_at(pts, self.numbering, self.order, leader_row)
        if a.tie:
            return a.tie, centre
        ids = list(a.ids) if self.alg.team == "A" else _rank_labels(labels)
        if self.alg.team == "F":
            self.label_of = {ids[k]: labels[k] for k in range(len(ids))}
        self.origin, self.u = a.origin, a.u
        self.u_l = float(a.common[a.leader, 0])
        self.id = ids[0]
        self.pos_of = {ids[k]: pts[k].copy() for k in range(len(pts))}
        self.lead0 = pts[a.leader].copy()
        self._new_interval()
        if self.flock is not None and self.goal is None:
            dist, ang = self.flock
            th = math.atan2(self.u[1], self.u[0]) + ang
            self.goal = pts[a.leader] + dist * np.array((math.cos(th), math.sin(th)))
        return None

    def _new_interval(self) -> None:
        n = len(self.pos_of)
        if self.span is None:
            self.span = self.target.interval_for(n) * max(n - 1, 1)
        self.d_u = self.span / max(n - 1, 1)                              # Sec. 3.5: keep the span

    def _set_origin_at_leader(self) -> None:
        lead = self.pos_of[0]
        self.origin, self.u_l, self.lead0 = (float(lead[0]), float(lead[1])), 0.0, lead.copy()

    # -- targets ------------------------------------------------------------------------------

    def _pattern(self) -> str:
        return self.patterns[self.pattern_k]

    def _memo(self) -> dict:
        """The memoised targets, emptied when what they are computed from changed: the pattern, n,
        d_u, u_l, the origin or u.  The floats and tuples are compared by identity (every change
        assigns a new object; an equal new value is only computed again), so a -0.0 for a 0.0
        never reuses a target.  Pure performance: the same targets, bit for bit."""
        f = self._frame
        if (f is None or f[0] != self.pattern_k or f[1] != len(self.pos_of) or f[2] is not self.d_u
                or f[3] is not self.u_l or f[4] is not self.origin or f[5] is not self.u):
            self._frame = (self.pattern_k, len(self.pos_of), self.d_u, self.u_l, self.origin, self.u)
            self._targets = {}
            self._line_kind = None
        return self._targets

    def _target_of(self, rid: int) -> np.ndarray:
        """f_ID in the private frame (003 Alg. 2 / Alg. 3, in the common frame); a read-only array,
        memoised (:meth:`_memo`: each robot asks for every robot's target every step)."""
        memo = self._memo()
        f = memo.get(rid)
        if f is None:
            uv = self.target.target_of(self._pattern(), rid, len(self.pos_of), self.d_u, self.u_l)
            f = self._common_to_private(uv)
            f.setflags(write=False)
            memo[rid] = f
        return f

    # -- one step -----------------------------------------------------------------------------

    def step(self, obs: Observation) -> Command:
        if self.i_failed:
            return Command(message=("failed", self.id))                   # Sec. 3.5
        others_body = np.asarray(obs.neighbor_poses, dtype=float).reshape(-1, 2)
        others = self._to_private(others_body) if len(others_body) else np.zeros((0, 2))
        me = np.array([self.x, self.y])
        due = self.fail_at.get("leader" if self.id == 0 else self.id, ()) if self.id is not None else ()
        if any(obs.step >= when for when in due):
            # --fail ID@STEP: the robot holding that ID at the first step >= STEP (IDs exist once
            # Alg. 1 has run) stops and says so (Sec. 3.5)
            self.i_failed, self.done = True, True
            self.failed_at = obs.step
            return Command(message=("failed", self.id))
        failed_rows, command = [], None
        for row, msg in obs.messages.items():
            if not (isinstance(msg, tuple) and msg):
                continue
            if msg[0] == "failed":
                failed_rows.append(row)
                self._consume_failure(msg[1])
            elif msg[0] == "pattern":
                command = msg
            elif msg[0] == "label":
                self.labels[row] = int(msg[1])
        if self.phase != "agree":
            self._track(others)
        if failed_rows:
            self._on_failures(others, failed_rows)
        if self.phase == "agree":
            return self._step_agree(obs, me, others)
        if command is not None and self.id != 0 and int(command[1]) != self.pattern_k:
            self._switch(int(command[1]))
        return self._act(me)

    def _consume_failure(self, rid) -> None:
        """A ``--fail`` entry fires once: the robots that hear it drop it (the failed robot's ID may be
        re-issued to another robot, Sec. 3.5)."""
        key = "leader" if rid == 0 else rid
        steps = self.fail_at.get(key)
        if steps:
            steps = set(steps)
            steps.discard(min(steps))
            if steps:
                self.fail_at[key] = steps
            else:
                del self.fail_at[key]

    def _step_agree(self, obs, me, others) -> Command:
        rows = self._live_rows(others)
        if self.alg.team == "F" and (obs.step == 0 or any(r not in self.labels for r in rows)):
            return Command(message=("label", self.fixed_id))              # F-team: say the fixed label
        tied = self._agree(me, others, rows)
        if tied is None:
            self.phase = "form"
            return self._act(me)
        tie, centre = tied
        if 0 in tie:                                                      # Sec. 2.1: off the circle
            d = me - centre                                               # p_o, as _agree computed it
            norm = math.hypot(*d)
            out = d / norm if norm > 0 else np.array([1.0, 0.0])
            step = float(self.rng.uniform(0.0, 1.0)) * min(self.perturb, self.params.v * self.params.dt)
            return self._move_to(me + out * step)
        return Command()                                                  # the others stay

    def _track(self, others: np.ndarray) -> None:
        """Re-identify the live robots: each remembered robot is predicted one step on toward the
        target this robot computes for it (every robot runs the same rules and knows the IDs), then
        the predictions are matched to the sensed positions at least total distance."""
        from scipy.optimize import linear_sum_assignment

        keys = [k for k in self.pos_of if k != self.id]
        rows = self._live_rows(others)
        if keys and rows:
            old = np.array([self._predict(k) for k in keys])
            new = others[rows]
            cost = np.hypot(old[:, None, 0] - new[None, :, 0], old[:, None, 1] - new[None, :, 1])
            r, c = linear_sum_assignment(cost)
            for a, b in zip(r.tolist(), c.tolist()):
                self.pos_of[keys[a]] = new[b].copy()
        if self.id is not None:
            self.pos_of[self.id] = np.array([self.x, self.y])

    def _predict(self, rid) -> np.ndarray:
        """Where robot ``rid`` should be one step later by the rules (it moves at most v dt)."""
        p = self.pos_of[rid]
        try:
            if rid == 0:
                last = self.pattern_k + 1 >= len(self.patterns)
                tgt = self.goal if (self.formed and last and self.goal is not None) else p
            else:
                tgt = self._rule_target(rid)
        except (KeyError, UsageError):
            return p
        if tgt is None:
            return p
        d = np.asarray(tgt, dtype=float) - p
        dist = float(math.hypot(d[0], d[1]))
        step = self.params.v * self.params.dt
        return p + (d if dist <= step else d * (step / dist))

    def _reference_id(self, rid: int) -> int:
        """Whom follower ``rid`` is placed relative to: the leader (Sec. 3.2) or N_id (Alg. 4)."""
        if self.mode == "leader":
            return 0
        self._memo()
        if self._line_kind is None:
            self._line_kind = self.target.line_kind(self._pattern(), len(self.pos_of))
        kind, k = self._line_kind
        return neighbor_id(rid, kind, k)

    def _rule_target(self, rid):
        """The target the rules give the follower ``rid`` now (without its own positioning error)."""
        if self.mode == "leader":
            return self._target_of(rid) + self._shift()                        # Secs. 3.2-3.3
        nid = self._reference_id(rid)                                           # Alg. 4
        ref = self.pos_of.get(nid)
        return None if ref is None else ref + (self._target_of(rid) - self._target_of(nid))   # Sec. 4.2

    def _on_failures(self, others, failed_rows) -> None:
        """Sec. 3.5: a failure heard.  The leader's: Alg. 1 again over the survivors.  A
        follower's: origin at p_l, u kept, IDs re-issued (the leader keeps 0), span kept.
        F-team (Sec. 3.7, fixed IDs): the survivors keep their labels; the smallest label leads and
        the IDs are the labels' ranks (a leader's failure: origin, direction again from there)."""
        new = []
        for row in failed_rows:
            p = others[row]
            if any(float(np.hypot(*(p - q))) <= 1e-9 for q in self.dead):
                continue
            self.dead.append(p.copy())
            if self.pos_of:
                rid = min(self.pos_of, key=lambda k: float(np.hypot(*(self.pos_of[k] - p))))
                del self.pos_of[rid]
                self.label_of.pop(rid, None)
                new.append(rid)
        if not new:
            return
        self.rebuilds += 1
        self.formed, self.done = False, False
        if self.alg.team == "F" and self.phase != "agree":
            self._reagree_fixed_labels(leader_failed=0 in new)
            return
        if 0 in new or self.phase == "agree":
            self.phase, self.id, self.pos_of = "agree", None, {}
            return
        alive = sorted(self.pos_of)
        pts = [self.pos_of[i] for i in alive]
        lead = self.pos_of[0]
        u = np.array(self.u)
        v = np.array((-u[1], u[0]))
        common = [((p - lead) @ u, (p - lead) @ v) for p in pts]
        ids = allocate_ids(common, alive.index(0), numbering=self.numbering, order=self.order)
        me = self.id
        self.pos_of = {ids[k]: pts[k] for k in range(len(alive))}
        self.id = ids[alive.index(me)]
        self._set_origin_at_leader()
        self._new_interval()

    def _reagree_fixed_labels(self, leader_failed: bool) -> None:
        """F-team after a failure, from the tracked survivors: IDs = ranks of the fixed labels; a
        follower's failure keeps u and puts the origin at p_l; the leader's runs Alg. 1's origin and
        direction again with the smallest surviving label as the leader."""
        alive = sorted(self.pos_of)
        pts = np.array([self.pos_of[i] for i in alive])
        labels = [self.label_of[i] for i in alive]
        ids = _rank_labels(labels)
        me = self.id
        if leader_failed:
            a = agree(pts, numbering=self.numbering, order=self.order, leader=labels.index(min(labels)))
            self.origin, self.u = a.origin, a.u
            self.u_l = float(a.common[a.leader, 0])
        self.pos_of = {ids[k]: pts[k].copy() for k in range(len(alive))}
        self.label_of = {ids[k]: labels[k] for k in range(len(alive))}
        self.id = ids[alive.index(me)]
        if leader_failed:
            self.lead0 = self.pos_of[0].copy()
        else:
            self._set_origin_at_leader()
        self._new_interval()

    def _switch(self, k: int) -> None:
        """Sec. 3.4: the leader and the IDs stay, the origin moves to p_l, u is kept."""
        self.pattern_k = k
        self._set_origin_at_leader()
        self.formed, self.done = False, False

    def _shift(self) -> np.ndarray:
        """How far the leader has moved since the origin was set (flocking, Sec. 3.3)."""
        return self.pos_of[0] - self.lead0

    def _all_at_targets(self) -> bool:
        """The leader sees the pattern stand: the sensed positions are the target set (matched as a
        set, at least total distance: which robot stands where does not matter)."""
        from scipy.optimize import linear_sum_assignment

        ids = sorted(self.pos_of)
        shift = self._shift()
        tgt = np.array([self._target_of(rid) + shift for rid in ids])
        pos = np.array([self.pos_of[rid] for rid in ids])
        cost = np.hypot(pos[:, None, 0] - tgt[None, :, 0], pos[:, None, 1] - tgt[None, :, 1])
        r, c = linear_sum_assignment(cost)
        return float(cost[r, c].max()) <= self.tol

    def _act(self, me) -> Command:
        return self._act_leader(me) if self.id == 0 else self._act_follower(me)

    def _act_leader(self, me) -> Command:
        last = self.pattern_k + 1 >= len(self.patterns)
        if not self.formed and self._all_at_targets():
            self.formed = True
            if not last:                                                   # Sec. 3.6: the next pattern
                self._switch(self.pattern_k + 1)
                self.done = False
                return Command(message=("pattern", self.pattern_k, self._pattern()))
        if self.formed and last and self.goal is not None and float(np.hypot(*(self.goal - me))) > ARRIVE:
            self.done, self.flocking = False, True
            return self._move_to(self.goal)                                # Sec. 3.3: the leader flocks
        self.done, self.flocking = self.formed and last, False
        return Command()

    def _act_follower(self, me) -> Command:
        if self.error_vec is None and self.id in self.errors:
            ang = float(self.rng.uniform(0.0, 2 * math.pi))                # Sec. 5.2: one computing error
            self.error_vec = self.error_size * self.d_u * np.array((math.cos(ang), math.sin(ang)))
        err = self.error_vec if self.error_vec is not None else np.zeros(2)
        tgt = self._rule_target(self.id)
        if tgt is None:                                                    # N_id is no allocated ID
            self.done = False
            return Command()
        tgt = tgt + err
        self.my_target = tgt
        self.done = float(np.hypot(*(tgt - me))) <= self.tol
        return self._move_to(tgt)

    def _move_to(self, p) -> Command:
        """Holonomic: turn toward ``p`` (private frame), drive at most ``v dt``; keep the odometry."""
        d = np.asarray(p, dtype=float) - np.array([self.x, self.y])
        dist = float(math.hypot(d[0], d[1]))
        if dist <= ARRIVE:
            return Command()
        turn = math.remainder(math.atan2(d[1], d[0]) - self.th, 2 * math.pi)
        fwd = min(dist, self.params.v * self.params.dt)
        self.th = math.remainder(self.th + turn, 2 * math.pi)
        self.x += fwd * math.cos(self.th)
        self.y += fwd * math.sin(self.th)
        return Command(turn=turn, forward=fwd)

    def _reference(self):
        """(reference ID, the offset from this robot to it in its body frame) that flocking keeps:
        the leader (Sec. 3.3) or N_id (Sec. 4.3); None for the leader or without one."""
        if self.id in (None, 0) or self.i_failed or self.phase == "agree" or self.span is None:
            return None
        try:
            ref = self._reference_id(self.id)
            off = self._rotation(-1) @ (self._target_of(ref) - self._target_of(self.id))
        except (KeyError, UsageError, ZeroDivisionError):
            return None
        return ref, (round(float(off[0]), 9), round(float(off[1]), 9))

    def state(self):
        view = None
        if self.origin is not None and 0 in self.pos_of:
            o = self._to_body(self.origin)
            lead = self._to_body(self.pos_of[0])
            ua = math.remainder(math.atan2(self.u[1], self.u[0]) - self.th, 2 * math.pi)
            view = tuple(round(float(x), 9) for x in (o[0], o[1], ua, lead[0], lead[1]))
        return (("phase", self.phase), ("id", self.id), ("failed", self.i_failed), ("done", self.done),
                ("pattern", self._pattern()), ("view", view), ("alive", len(self.pos_of)),
                ("rebuilds", self.rebuilds), ("epoch", (self.pattern_k, self.rebuilds)),
                ("span", None if self.span is None else round(float(self.span), 9)),
                ("d_u", None if self.d_u is None else round(float(self.d_u), 9)),
                ("flocking", self.flocking), ("reference", self._reference()),
                ("lag", self.params.v * self.params.dt),
                ("target", None if self.my_target is None or self.id in (None, 0) or self.i_failed
                 or self.phase == "agree" else tuple(round(float(c), 9) for c in self._to_body(self.my_target))))


def _as_list(x):
    """A list from a comma-separated string, a sequence, or one number (``--param position_errors=3``)."""
    if x is None or x == "":
        return []
    if isinstance(x, str):
        return [p for p in x.replace(";", ",").split(",") if p.strip()]
    if isinstance(x, (int, float)) and not isinstance(x, bool):
        return [x]
    try:
        return list(x)
    except TypeError:
        raise UsageError(f"value={x!r} is not a list", fix="give comma-separated values, e.g. 3,6,9") from None


def _failures(spec) -> dict:
    """``fail``: ``"ID@STEP,..."`` or pairs; ID an allocated ID or ``leader``."""
    out: dict = {}
    for item in _as_list(spec):
        if isinstance(item, str):
            who, sep, when = item.strip().partition("@")
            if not sep:
                raise UsageError(f"fail={item!r} must be ROBOT@STEP", fix="e.g. --fail leader@40 or --fail 3@25")
            who = who.strip()
        elif isinstance(item, (tuple, list)) and len(item) == 2:
            who, when = item
        else:
            raise UsageError(f"fail={item!r} must be ROBOT@STEP", fix="e.g. --fail leader@40 or --fail 3@25")
        try:
            step = int(when)
        except (TypeError, ValueError):
            raise UsageError(f"fail={item!r}: STEP={when!r} is not an integer", fix="e.g. --fail 3@25") from None
        if who != "leader":
            try:
                who = int(who)
            except (TypeError, ValueError):
                raise UsageError(f"fail={item!r}: ROBOT={who!r} is neither an allocated ID nor 'leader'",
                                 fix="e.g. --fail leader@40 or --fail 3@25") from None
            if who == 0:
                who = "leader"
            elif who < 0:
                raise UsageError(f"fail={item!r}: ROBOT={who} is not an ID", fix="IDs are 0 (the leader), 1, 2, ...")
        if step < 0:
            raise UsageError(f"fail={item!r}: STEP={step} must be >= 0")
        out.setdefault(who, set()).add(step)
    return out


def _flock(spec):
    if isinstance(spec, str):
        parts = spec.replace("@", ",").split(",")
    elif isinstance(spec, (int, float)):
        parts = [spec]
    else:
        parts = list(spec)
    try:
        dist, ang = float(parts[0]), float(parts[1])
    except (IndexError, ValueError, TypeError):
        raise UsageError(f"flock_to={spec!r} must be DISTANCE,ANGLE_DEGREES",
                         fix="e.g. --param flock_to=100,30 (003 Fig. 9)") from None
    if not (math.isfinite(dist) and dist >= 0 and math.isfinite(ang)):
        raise UsageError(f"flock_to={spec!r} must be a finite distance >= 0 and a finite angle")
    return dist, math.radians(ang)


def _rank_labels(labels) -> list:
    """F-team: fixed labels to IDs 0..n-1 by rank (the smallest label leads)."""
    order = sorted(range(len(labels)), key=lambda k: labels[k])
    out = [0] * len(labels)
    for r, k in enumerate(order):
        out[k] = r
    return out


# ---------------------------------------------------------------------------------------------
# the patterns (003 Table 1, Algs. 2-3: swarmproof.models.line_patterns)
# ---------------------------------------------------------------------------------------------

def pattern_params_for(name: str, target, extra) -> dict:
    """The parameters pattern ``name`` is computed with: the target's own (for its shape), then the
    pattern parameters of ``--param`` (``alpha_star``, ``radius``, ...) that this pattern takes."""
    from swarmproof.models import line_patterns as lp

    out = dict(target.params) if name == target.shape else {}
    takes = lp.pattern_info(name)["params"]
    out.update({k: v for k, v in dict(extra or {}).items() if k in PATTERN_PARAM_KEYS and k in takes})
    return out


class _Patterns:
    """What a controller needs of the target: its first pattern and the formulas of every pattern
    it may switch to (any name of :mod:`swarmproof.models.line_patterns`)."""

    def __init__(self, target, params: Params) -> None:
        from swarmproof.models import line_patterns as lp

        self.lp = lp
        self.shape = target.shape
        self.base = target
        names = [self.shape] + list(options_of(params.extra, target_shape=target.shape)["then"])
        self.params_of = {name: pattern_params_for(name, target, params.extra) for name in names}

    def interval_for(self, n: int) -> float:
        return self.base.interval_for(n)

    def target_of(self, name: str, rid: int, n: int, d_u: float, u_l: float):
        return self.lp.target_of(name, rid, n, d_u, u_l, **self.params_of[name])

    def line_kind(self, name: str, n: int):
        """("uni", None) or ("multi", NoLine of Alg. 4 line 7)."""
        info = self.lp.pattern_info(name)
        if info["type"] == "uni":
            return "uni", None
        return "multi", self.lp.line_count(name, n, reading="alg4", **self.params_of[name])


# ---------------------------------------------------------------------------------------------
# runtime invariants (the ``invariants`` property)
# ---------------------------------------------------------------------------------------------

def _to_world(pose, x: float, y: float, *, offset: bool = False) -> tuple:
    """A point (or, with ``offset``, a vector) given in the body frame of a robot at ``pose``, in the world."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    dx, dy = c * x - s * y, s * x + c * y
    return (dx, dy) if offset else (pose[0] + dx, pose[1] + dy)


def _world_view(pose, view):
    """A robot's (origin, direction angle, leader position) from its body-frame view, in the world."""
    ox, oy, ua, lx, ly = view
    return _to_world(pose, ox, oy), math.remainder(pose[2] + ua, 2 * math.pi), _to_world(pose, lx, ly)


AGREE_TOL = 1e-6


def _agreement(t, ids, poses, states) -> str | None:
    """003 Sec. 2.1: the robots past Alg. 1 hold the same origin, direction and leader.  Compared
    within one epoch (pattern switched to, agreements redone): a switch or a failure reaches the
    others one step after the robot that starts it (Secs. 3.4-3.5), and the frame moves on purpose."""
    ref: dict = {}
    for rid, pose, s in zip(ids.tolist(), poses, states):
        d = dict(s)
        if d["failed"] or d["view"] is None or d["phase"] == "agree":
            continue
        o, ua, lead = _world_view(pose, d["view"])
        epoch = d["epoch"]
        if epoch not in ref:
            ref[epoch] = (rid, o, ua, lead)
            continue
        r0, o0, ua0, lead0 = ref[epoch]
        if (math.hypot(o[0] - o0[0], o[1] - o0[1]) > AGREE_TOL or abs(math.remainder(ua - ua0, 2 * math.pi)) > AGREE_TOL
                or math.hypot(lead[0] - lead0[0], lead[1] - lead0[1]) > AGREE_TOL):
            return (f"robots {r0} and {rid} disagree: origin ({o0[0]:.6g}, {o0[1]:.6g}) vs ({o[0]:.6g}, {o[1]:.6g}), "
                    f"direction {math.degrees(ua0):.6g} vs {math.degrees(ua):.6g} deg, leader at "
                    f"({lead0[0]:.6g}, {lead0[1]:.6g}) vs ({lead[0]:.6g}, {lead[1]:.6g})")
    return None


def _ids_unique(t, ids, poses, states) -> str | None:
    """003 Sec. 2.1 ("unique IDs"), Sec. 3.5 ("reissuing new ID_i"): no two live robots hold one ID,
    and once every live robot has allocated IDs over the same live team, the IDs are 0 (the
    leader) and 1..n-1, one each.  (A failure reaches the others one step after it happens: in
    that step they still count the failed robot and only duplicates are judged.)"""
    live = [(rid, dict(s)) for rid, s in zip(ids.tolist(), states) if not dict(s)["failed"]]
    held = [(rid, d["id"]) for rid, d in live if d["phase"] != "agree" and d["id"] is not None]
    seen: dict = {}
    for rid, i in held:
        if i in seen:
            return f"robots {seen[i]} and {rid} both hold ID {i}"
        seen[i] = rid
    if not live or len(held) < len(live) or any(d["alive"] != len(live) for _, d in live):
        return None
    got = sorted(i for _, i in held)
    if got != list(range(len(live))):
        extra = sorted(set(got) - set(range(len(live))))
        return f"the {len(live)} IDs are {got}: ID(s) {extra} outside 0..{len(live) - 1} (not a bijection onto 0..n-1)"
    return None


def _flock_rigid(t, ids, poses, states) -> str | None:
    """003 Secs. 3.3/4.3: while the leader flocks, every follower keeps its distance and angle to its
    reference (the leader, or N_id) as in the pattern, up to the one step it lags (v dt)."""
    by_id = {}
    flocking = False
    for pose, s in zip(poses, states):
        d = dict(s)
        if d["failed"] or d["id"] is None or d["phase"] == "agree":
            continue
        by_id[d["id"]] = (pose, d)
        flocking |= d["id"] == 0 and d["flocking"]
    if not flocking:
        return None
    for rid, (pose, d) in sorted(by_id.items()):
        ref = d["reference"]
        if ref is None or ref[0] not in by_id:
            continue
        want = _to_world(pose, ref[1][0], ref[1][1], offset=True)
        rp = by_id[ref[0]][0]
        have = (rp[0] - pose[0], rp[1] - pose[1])
        err = math.hypot(want[0] - have[0], want[1] - have[1])
        if err > d["lag"] * (1 + 1e-9) + 1e-9:
            return (f"ID {rid} is {err:.6g} off its place relative to ID {ref[0]} while the leader flocks "
                    f"(allowed: one step's lag, v dt = {d['lag']:.6g})")
    return None


def _same_span(t, ids, poses, states) -> str | None:
    """003 Sec. 3.5: the team keeps its span: every live robot past Alg. 1 holds one span, and
    d_u (n - 1) = span over the robots it counts alive."""
    spans = set()
    for rid, s in zip(ids.tolist(), states):
        d = dict(s)
        if d["failed"] or d["span"] is None or d["phase"] == "agree":
            continue
        spans.add(d["span"])
        if abs(d["d_u"] * max(d["alive"] - 1, 1) - d["span"]) > 1e-6 * max(d["span"], 1.0):
            return f"robot {rid}: d_u={d['d_u']} over {d['alive']} robots does not keep span={d['span']}"
    if len(spans) > 1:
        return f"the robots hold different spans {sorted(spans)}"
    return None


def _distinct_targets(t, ids, poses, states) -> str | None:
    """003 Algs. 2-3 (and Sec. 3.2: a robot "computes its f_i"): no two live followers head for one
    target, and none for the leader's place (within 1e-6 intervals)."""
    pts = []
    lead = None
    for rid, pose, s in zip(ids.tolist(), poses, states):
        d = dict(s)
        if d["failed"] or d["phase"] == "agree":
            continue
        if d["id"] == 0:
            lead = (rid, (float(pose[0]), float(pose[1])))
            continue
        if d["target"] is None:
            continue
        pts.append((rid, d["id"], d["epoch"], _to_world(pose, *d["target"]), d["d_u"] or 1.0))
    for a in range(len(pts)):
        for b in range(a + 1, len(pts)):
            ra, ia, ea, pa, du = pts[a]
            rb, ib, eb, pb, _ = pts[b]
            if ea == eb and math.hypot(pa[0] - pb[0], pa[1] - pb[1]) <= 1e-6 * du:
                return (f"robots {ra} (ID {ia}) and {rb} (ID {ib}) head for one target "
                        f"({pa[0]:.6g}, {pa[1]:.6g})")
    if lead is not None:
        for r, i, e, p_, du in pts:
            if math.hypot(p_[0] - lead[1][0], p_[1] - lead[1][1]) <= 1e-6 * du:
                return f"robot {r} (ID {i}) heads for the leader's place ({p_[0]:.6g}, {p_[1]:.6g})"
    return None


INVARIANTS = (
    Invariant("agreement", "all robots agree on the common origin, leader and direction",
              "003 Sec. 2.1, Alg. 1 (lines 1-5)", _agreement),
    Invariant("ids_unique", "the IDs are a bijection onto 0 (the leader) and 1..n-1",
              "003 Sec. 2.1, Alg. 1 (lines 8-16)", _ids_unique),
    Invariant("flock_rigid", "while the leader flocks, each follower keeps its place relative to its reference",
              "003 Secs. 3.3, 4.3", _flock_rigid),
    Invariant("same_span", "the team keeps one span, d_u (n - 1) = span", "003 Secs. 3.1, 3.5", _same_span),
    Invariant("distinct_targets", "no two followers head for one target, none for the leader's place",
              "003 Table 1, Algs. 2-3", _distinct_targets),
)


def _v_dt_positive(params: Params, n: int, ids) -> str | None:
    return None if params.v > 0 and params.dt > 0 else f"v={params.v!r}, dt={params.dt!r} must be > 0"


def _distinct_start(params: Params, ids, poses) -> str | None:
    xy = np.asarray(poses, dtype=float)[:, :2]
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    np.fill_diagonal(d, np.inf)
    if len(xy) > 1 and float(d.min()) <= 0.0:
        i, j = np.unravel_index(int(np.argmin(d)), d.shape)
        return f"robots in rows {int(i)} and {int(j)} start at the same position"
    return None


def _fixed_labels(params: Params, n: int, ids) -> str | None:
    if ids is None:
        return None
    return None if len(set(ids)) == len(ids) else f"ids={list(ids)!r} are not distinct labels"


def _citation_of(name: str, default: str) -> str:
    """The citation of pattern ``name`` (for a restated target), else ``default``."""
    from swarmproof.models import line_patterns as lp

    try:
        return lp.pattern_info(name)["citation"]
    except UsageError:
        return default


class LeeChongLeader:
    """Lee & Chong 2008's leader-referenced formation control (registry name ``leechong-leader``); A-team, IDs
    by Sec. 2.1's prose numbering (reading "2"; the printed formula is
    ``leechong-leader-printed``).  See the module docstring."""

    name = "leechong-leader"
    #: The controller-state fields the shared checkers may read (swarmproof.invariants.capabilities):
    #: ``id`` and ``failed`` (the allocated IDs, Sec. 2.1); no spanning tree.
    state_fields = ("id", "failed")
    #: The seed paper (docs/references.md) whose claims ``claims`` cites.
    paper = "003"
    #: The reading version (protocol.Algorithm.reading: bumped when its behaviour changes on
    #: purpose; CHANGELOG.md).  "2" (swarmproof 0.2.0, issue 31): Sec. 2.1's prose numbering,
    #: which reproduces the paper's formed patterns (Figs. 2, 6, 7); "1" was Alg. 1's printed
    #: formula, registered now as ``leechong-leader-printed`` (registry.READINGS).
    reading = "2"
    mode = "leader"
    #: Alg. 1's ID numbering (:data:`NUMBERINGS`): Lee & Chong, Sec. 2.1's prose.
    numbering = "prose"
    team = "A"
    model = RobotModel(sensing="anonymous", communication="all", motion="holonomic", clocks="sync")
    assumptions = (
        Assumption("positive_speed", "v > 0 and dt > 0", "003 Sec. 6.2 (200 mm/s)", _v_dt_positive),
        Assumption("distinct_positions", "the robots start at distinct positions", "003 Sec. 2.1",
                   lambda params, n, ids: None, check_start=_distinct_start),
    )
    claims = {
        "formation": "003 Secs. 3.2, 4.2 (Function 1: the robots form the pattern)",
        "termination": "003 Secs. 3.2, 4.2 (the pattern is generated in finite time, Fig. 6)",
        "invariants": "003 Sec. 2.1 (agreement on origin, leader and direction; unique IDs)",
    }
    own_end = "every live robot at its target, the leader's pattern sequence and flocking done (003 Secs. 3-4)"
    invariants = INVARIANTS
    explore_targets = ("lines:wedge", "lines:circle", "lines:two-row", "lines:diamond")
    pattern_kind = "lines"
    #: Its ``Params.extra`` keys (:data:`PARAMETERS`) and the kind of target it forms (003's line patterns).
    parameters = PARAMETERS
    target_kinds = ("lines",)
    #: 003 is about "small-scale robot teams" (title; Sec. 3.7 and 4.6 use 12 robots, Fig. 7 up to
    #: 15): each robot re-identifies every other one by an optimal matching each step (O(n^3) per
    #: robot and step), so the engine refuses more than this many robots (exit 2).
    max_robots = 128
    max_robots_reason = "Lee & Chong 2008's small-scale teams; every robot matches all n robots every step (O(n^3))"
    #: The robots sense every robot (Sec. 2.1); a range only draws the random connected starts: 2
    #: intervals, so starts are about as dense as the patterns, at least range/4 = 0.5 apart
    #: (Sec. 6.1: 600 mm apart at a 1000 mm interval).
    default_range = 2.0
    #: simulate's --then (pattern switching, Secs. 3.4/3.6) and --fail (Sec. 3.5) become these params.
    options = ("then", "fail")
    verify = VerifyPlan(targets=("lines:wedge", "lines:circle", "lines:two-row", "lines:triangle"),
                        robots=12, seeds=(0, 1, 2), explore=True, rank=40, explore_max_examples=15,
                        explore_cost=113)

    @staticmethod
    def exact_checks() -> list:
        """``swarmproof verify``'s ``formulas`` rows: Alg. 1's numbering, Alg. 4's N_id and the pattern
        targets, checked exactly for n = 2..64 (:func:`swarmproof.reference_impl.leechong.checks.verify_rows`)."""
        from swarmproof.reference_impl.leechong.checks import verify_rows

        return verify_rows()

    @staticmethod
    def explore_start(draw, lo: int, hi: int, phi: float):
        """The explorer's starts of 003's kind (Sec. 2.1, Fig. 3): besides the generic connected
        construction (None), symmetric ones where Alg. 1 meets ties -- a regular polygon (every
        vertex a leader candidate), the same with a robot at the centre, a mirror-symmetric spread
        (robots on the axis v = 0 and pairs across it) -- and near-symmetric ones (a regular
        polygon with one vertex moved by 1e-12..1e-3, below or above the tie tolerance)."""
        from hypothesis import strategies as st

        kind = draw(st.sampled_from(["generic", "polygon", "polygon+centre", "mirror", "near-polygon"]))
        if kind == "generic":
            return None
        n = draw(st.integers(max(lo, 2), max(hi, 2)))
        head = st.floats(-math.pi, math.pi)
        rot = draw(st.floats(-math.pi, math.pi))
        if kind == "mirror":
            pairs = draw(st.integers(1, max(1, n // 2)))
            on_axis = n - 2 * pairs
            pts = [(0.6 * k, 0.0) for k in range(on_axis)]
            for j in range(pairs):
                pts += [(0.6 * j + 0.3, 0.5 + 0.4 * j), (0.6 * j + 0.3, -0.5 - 0.4 * j)]
        else:
            m = n - 1 if kind == "polygon+centre" else n
            radius = max(1.0, 0.3 / math.sin(math.pi / max(m, 2)))
            pts = [(radius * math.cos(2 * math.pi * k / m), radius * math.sin(2 * math.pi * k / m)) for k in range(m)]
            if kind == "polygon+centre":
                pts.append((0.0, 0.0))
            if kind == "near-polygon":
                eps = draw(st.sampled_from([1e-12, 1e-9, 1e-6, 1e-3]))
                pts[0] = (pts[0][0] * (1 + eps), pts[0][1] * (1 + eps))
        c, s = math.cos(rot), math.sin(rot)
        return [(c * x - s * y, s * x + c * y, draw(head)) for x, y in pts]

    @staticmethod
    def explore_extra(draw, n: int) -> dict:
        """Failures of the leader or of a follower at any step (Sec. 3.5, Figs. 12-13), or none.
        (Positioning errors, Sec. 5.2's observation errors, are the explorer's ``--fault noise``.)"""
        from hypothesis import strategies as st

        who = draw(st.sampled_from(["none", "leader", "follower"]))
        if who == "none" or n < 3:
            return {}
        step = draw(st.integers(1, 80))
        if who == "leader":
            return {"fail": f"leader@{step}"}
        return {"fail": f"{draw(st.integers(1, n - 1))}@{step}"}

    @staticmethod
    def default_params(range: float, n: int) -> Params:
        """003 Sec. 6.2's ratio (interval 1000 mm, 200 mm/s): v = 0.2 intervals per unit time, dt = 0.5;
        holonomic robots turn freely (omega unused)."""
        return Params(range=range, v=0.2, omega=math.pi, dt=0.5)

    @staticmethod
    def default_max_steps(params: Params, n: int) -> int:
        """Generous: 20 patterns' worth of 60-interval trips plus a 200-interval flight."""
        return int(math.ceil((20 * 60 + 200) / max(params.v * params.dt, 1e-9)))

    def controller(self, robot_id, params: Params, target, rng) -> LeeChongController:
        if getattr(target, "kind", None) != "lines" or not hasattr(target, "shape"):
            raise UsageError(f"{self.name} needs a line pattern of 003 (Table 1, Alg. 3), not "
                             f"{getattr(target, 'kind', type(target).__name__)} {getattr(target, 'name', '')!r}",
                             fix="e.g. --pattern wedge (or --target lines:wedge)")
        return LeeChongController(self, params, _Patterns(target, params), rng, robot_id)

    def finished(self, states) -> bool:
        live = [dict(s) for s in states if s is not None and not dict(s)["failed"]]
        return bool(live) and all(s["done"] and s["phase"] != "agree" for s in live)

    @staticmethod
    def metrics(result) -> dict:
        """simulate's ``metrics``: whether the runtime invariants held at every recorded step
        (``agreement``, ``ids_unique``: True / False, with the first violation), the final IDs
        (engine ID -> allocated ID), the failed robots and the agreements redone."""
        trace = result.trace
        out: dict = {}
        for inv in INVARIANTS:
            first = None
            for t in range(len(trace.states)):
                mask = trace.present_at(t)
                ids = trace.ids[mask]
                states = tuple(s for s, m in zip(trace.states[t], mask) if m)
                msg = inv.check(t, ids, trace.poses[t][mask], states)
                if msg is not None:
                    first = f"step {t}: {msg}"
                    break
            out[inv.name] = first is None
            if first is not None:
                out[inv.name + "_violation"] = first
        final = {int(i): dict(s) for i, s in zip(result.final_ids.tolist(), result.final_states)}
        out["ids"] = {str(i): d["id"] for i, d in sorted(final.items())}
        out["failed"] = sorted(i for i, d in final.items() if d["failed"])
        out["agreements_redone"] = max((d["rebuilds"] for d in final.values()), default=0)
        return out

    @staticmethod
    def judging_target(target, n_start: int, params=None):
        """The pattern a run ends in: the last one of a switching sequence (``then``, Secs. 3.4,
        3.6), with the pattern parameters the robots used (``--param alpha_star=...``) and the
        span of the start (Sec. 3.5: ``d_u = span / (n - 1)``, so the survivors of a failure stand
        at a wider interval)."""
        import dataclasses

        if not hasattr(target, "interval_for") or getattr(target, "shape", "line") == "line":
            return target
        extra = dict(getattr(params, "extra", None) or {})
        seq = _as_list(extra.get("then", ()))
        span = target.span if target.span is not None else target.interval_for(n_start) * max(n_start - 1, 1)
        last = str(seq[-1]).strip() if seq else target.shape
        name = target.name if last == target.shape else last
        return dataclasses.replace(target, name=name, shape=last, interval=None, span=span,
                                   params=pattern_params_for(last, target, extra),
                                   cites=_citation_of(last, target.cites))

    @classmethod
    def check_params(cls, params: Params, n: int, target) -> None:
        """Before a run (the engine calls it): 003's options checked against the team size (a
        ``--fail`` ID no robot can hold under this class's numbering, an unknown key, a bad value:
        exit 2)."""
        options_of(params.extra, target_shape=getattr(target, "shape", None), n=n, numbering=cls.numbering)

    @staticmethod
    def out_of_formation(state) -> bool:
        """A failed robot stands where it stopped; the pattern is judged on the others (Sec. 3.5)."""
        return state is not None and bool(dict(state)["failed"])


class LeeChongNeighbor(LeeChongLeader):
    """Lee & Chong 2008's neighbor-referenced formation control (registry name ``leechong-neighbor``, Sec. 4, Alg. 4);
    IDs by Sec. 2.1's prose numbering (reading "2"; the printed formula is ``leechong-neighbor-printed``)."""

    name = "leechong-neighbor"
    mode = "neighbor"
    claims = dict(LeeChongLeader.claims, formation="003 Sec. 4.2 (Function 1 by neighbor reference)")
    verify = VerifyPlan(targets=("lines:wedge", "lines:circle", "lines:two-row", "lines:triangle"),
                        robots=12, seeds=(0, 1, 2), explore=True, rank=41, explore_max_examples=15,
                        explore_cost=149)


#: The ``-printed`` variants' verify rows: the two patterns on which the printed formula's IDs
#: break the default's formation at n = 12 (seed 0: 3 followers above u and 8 below), 3 seeds,
#: no exploration (the default names explore; the formula's finding is also the exact
#: ``formulas`` row "003 Alg. 1 printed ID formula").
_PRINTED_PLAN = dict(targets=("lines:wedge", "lines:two-row"), robots=12, seeds=(0, 1, 2), explore=False)


class LeeChongLeaderPrinted(LeeChongLeader):
    """``leechong-leader`` with the IDs of Alg. 1's printed formula (Lee & Chong, Alg. 1 lines 11-14:
    ``2 x rank`` for v >= 0, ``2 x rank - 1`` for v < 0): reading "1" of ``leechong-leader``, its
    default up to swarmproof 0.1.0, kept as a registered variant (issue 31).  Not a bijection onto
    1..n-1 unless the half planes hold a = b or b = a + 1 followers (smallest failure: n = 2, its
    one follower in the upper half plane gets ID 2; verify's ``formulas`` row)."""

    name = "leechong-leader-printed"
    reading = "1"
    numbering = "formula"
    verify = VerifyPlan(**_PRINTED_PLAN, rank=42)


class LeeChongNeighborPrinted(LeeChongNeighbor):
    """``leechong-neighbor`` with Alg. 1's printed ID formula: reading "1" of ``leechong-neighbor``
    (its default up to swarmproof 0.1.0).  Besides the IDs, Alg. 4's N_id may name an ID nobody
    holds (multi-line patterns), and the robot waits for it forever."""

    name = "leechong-neighbor-printed"
    reading = "1"
    numbering = "formula"
    verify = VerifyPlan(**_PRINTED_PLAN, rank=43)


class LeeChongLeaderFTeam(LeeChongLeader):
    """Sec. 3.7's F-team: robots with fixed IDs (labels 0..n-1; label 0 leads), same control.  The
    IDs are the labels' ranks, so Alg. 1's numbering (prose or printed) never applies: its runs
    did not change with issue 31 and it keeps reading "1"; no ``-printed`` F-team variant."""

    name = "leechong-leader-fteam"
    #: Unchanged by issue 31 (no numbering applies; traces bit-identical): reading "1".
    reading = "1"
    team = "F"
    model = RobotModel(sensing="anonymous", communication="all", motion="holonomic", clocks="sync", own_id=True)
    assumptions = LeeChongLeader.assumptions + (
        Assumption("fixed_labels", "every robot carries its own fixed label", "003 Sec. 3.7 (F-team)", _fixed_labels),)
    claims: dict = {}
    verify = None


class LeeChongNeighborFTeam(LeeChongLeaderFTeam):
    """Sec. 4.6's F-team with neighbor-referenced control."""

    name = "leechong-neighbor-fteam"
    mode = "neighbor"
