"""Jiang et al. (002): repeating pattern formation by basic pattern generation and layered assembling.

The algorithm of 002 Sec. IV for the engine, followed line by line:

* **Robot model** (Sec. III-A): unique IDs; each robot knows its own pose in a
  common frame (``sensing="global"``) and, as the input of Algorithms 1 and 2,
  the robot set R and every initial position P (``knows_start``: the engine
  hands them over once before step 0); every message reaches every robot
  (``communication="all"``), asynchronously with no bound on delay (the
  engine's delay and reordering fault models); motion limited by v and omega
  (``differential``).  The paper assumes "collision-free paths"; robots here
  drive straight to their targets and the ``collision`` property checks what
  that assumption hides.
* **Algorithm 1** (basic pattern generation), for robot ``r_i``: upon finding
  that it has the largest ID in R, it becomes a head, takes ``B' = (B \\
  {(0,0)}) + p_i``, selects the ``m = |B'|`` robots of R nearest to it
  (:func:`nearest`), removes them and itself from R, assigns them to B' with
  minimum total distance (the Hungarian method, scipy's
  ``linear_sum_assignment``) and sends ``Group(R, (r_i, p_i), (r_c, p'_c)...)``.
  Upon receiving a Group naming it, a robot moves to its ``p'`` and regards the
  sender as its head (keeping its offset ``p' - p_head``); every receiver sets
  ``R <- R'`` -- an assignment, not an intersection, exactly as printed.
* **Algorithm 2** (layered assembling), among the heads H: the queue Q starts as
  ``{max H}``; upon finding that it is the first element of Q, a head takes
  ``A' = A \\ {(0,0)} \\ O``, ``l = |A'|``, ``A' + p_i``, selects the l heads
  of H nearest to it, assigns them to A' with minimum total distance, sorts them
  by ID, sets ``H = H \\ E \\ {r_i}``, ``Q = Q u E u {r_i}`` and sends
  ``Layer(H, Q, (r_i, p_i), (r_c, p'_c)...)``.  A receiver named in it moves to
  its ``p'`` (and its group's members follow, keeping their offsets: "the
  non-head robots will follow the head's action", Sec. IV-A); every receiver
  sets ``O <- O u N``, ``H <- H'``, ``Q <- Q'``.

Two readings of Algorithm 2 (docs/decisions.md, "Jiang et al."), both
registered and both reported by ``verify``:

* ``jiang`` (default, the prose of Sec. IV-B): Q is a queue -- the head that
  acts leaves it (``Q = (Q \\ {r_i}) u E``) -- and O records the *positions*
  taken ("an array O is used to record the positions have been occupied"), so
  A' holds only free positions;
* ``jiang-literal`` (the printed lines): ``Q = Q u E u {r_i}`` never removes
  ``r_i``, which stays first, and O collects *robots* (``O <- O u N``), so
  ``A \\ {(0,0)} \\ O`` removes no vector.  An "Upon" fires once per robot
  (the event of finding itself first), so after the root's layer nobody acts:
  the run goes static with unassigned heads.

Other choices (docs/decisions.md): with fewer robots left in R (or heads in H)
than positions, the ones left are assigned to the positions that minimise the
total distance (a rectangular assignment) and the rest stay empty; a head
enters Algorithm 2 when its R is empty (the paper has no barrier between the
phases), with H the heads named by the Group messages it received, and every
robot when a Layer message reaches it; Algorithm 1's "Upon" has no other
condition, so a robot whose R grows back (a late Group message) and names it
the largest acts again, as printed; a head
acts as soon as it is first in Q, from its assigned position (the position
the layer is built around), without waiting to arrive; nearest means smallest
distance from the initial positions P (robots of R and H do not move before
they are assigned), ties to the lower ID; a robot sends at most one message
per step (a second waits for the next step).

Examples
--------
>>> from swarmproof.reference_impl.engine import simulate
>>> from swarmproof.models.targets import resolve_target
>>> from swarmproof.models.trace import InitialConfiguration
>>> pat = resolve_target("pattern:square-segments")
>>> init = InitialConfiguration([1, 2, 3, 4], [[0, 0, 0], [0.3, 0.1, 0], [0.9, 0.2, 0], [0.5, 0.8, 0]])
>>> alg = Jiang()
>>> r = simulate(alg, pat, init, alg.default_params(range=1.5, n=4), seed=0)
>>> r.status, pat.satisfied(r.final_ids, r.final_poses).status
('finished', 'held')
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from swarmproof.invariants.algorithm_invariants import Invariant
from swarmproof.reference_impl.protocol import (Assumption, Command, ExhaustiveCell, Observation, Params,
                                                RobotModel, VerifyPlan, steer_toward)

__all__ = ["Jiang", "JiangLiteral", "Group", "Layer", "nearest", "assign", "JiangController"]

READINGS = ("queue", "literal")
ARRIVE_EPS = 1e-9


@dataclass(frozen=True)
class Group:
    """002 Alg. 1: ``Group(R, (r_i, p_i), (r_c1, p'_c1), ..., (r_cm, p'_cm))``."""

    available: tuple          # R after the head removed its group (sorted IDs)
    head: int
    head_pos: tuple           # p_i
    members: tuple            # ((r_c, (x, y)), ...)


@dataclass(frozen=True)
class Layer:
    """002 Alg. 2: ``Layer(H, Q, (r_i, p_i), (r_c1, p'_c1), ..., (r_cl, p'_cl))``."""

    heads: tuple              # H (sorted IDs)
    queue: tuple              # Q (in order)
    sender: int
    sender_pos: tuple         # p_i
    assigned: tuple           # ((r_c, (x, y)), ...), sorted by ID


def nearest(center, candidates, positions: dict, k: int) -> list[int]:
    """The ``k`` candidates nearest to ``center`` by their positions, ties to the lower ID.

    >>> nearest((0, 0), [5, 3, 9], {5: (1, 0), 3: (0, 1), 9: (2, 0)}, 2)
    [3, 5]
    """
    cx, cy = float(center[0]), float(center[1])
    ranked = sorted(candidates, key=lambda r: (math.hypot(positions[r][0] - cx, positions[r][1] - cy), r))
    return ranked[:max(0, k)]


def assign(robots: list[int], positions: dict, targets: list) -> list[tuple[int, tuple]]:
    """Robots to target points with minimum total distance (the Hungarian method, 002 Alg. 1/2:
    scipy's ``linear_sum_assignment``); with fewer robots than targets, each robot gets one
    target and the rest stay empty.  Returns ``[(robot, (x, y)), ...]`` sorted by robot ID.

    >>> assign([1, 2], {1: (0, 0), 2: (5, 0)}, [(5, 1), (0, 1), (9, 9)])
    [(1, (0.0, 1.0)), (2, (5.0, 1.0))]
    """
    from scipy.optimize import linear_sum_assignment

    if not robots or not targets:
        return []
    rp = np.array([positions[r] for r in robots], dtype=float)
    tp = np.array(targets, dtype=float)
    cost = np.hypot(rp[:, None, 0] - tp[None, :, 0], rp[:, None, 1] - tp[None, :, 1])
    rows, cols = linear_sum_assignment(cost)
    out = [(robots[r], (float(tp[c, 0]), float(tp[c, 1]))) for r, c in zip(rows, cols)]
    return sorted(out)


class JiangController:
    """One robot of 002 (Algorithms 1 and 2); see the module docstring."""

    def __init__(self, robot_id: int, params: Params, basic, assembling, reading: str, tol: float) -> None:
        self.id = int(robot_id)
        self.params = params
        self.basic = [tuple(map(float, p)) for p in basic]
        self.assembling = [tuple(map(float, a)) for a in assembling]
        self.reading = reading
        self.tol = tol
        self.P: dict[int, tuple] = {}
        self.R: set[int] = set()
        self.r_max: int | None = None
        self.heads: set[int] = set()
        self.is_head = False
        self.head_of: int | None = None
        self.offset: tuple | None = None      # p' - p_head (members)
        self.target: tuple | None = None
        self.in_phase2 = False
        self.H: tuple = ()
        self.Q: tuple = ()
        self.O: tuple = ()                    # positions (queue reading) or robot IDs (literal)
        self.acted2 = False
        self.pending: list = []
        self.arrived = False
        self.members: tuple = ()

    # -- input ------------------------------------------------------------------

    def know_start(self, ids, positions) -> None:
        """Alg. 1's input: R (all robots) and P (their initial positions)."""
        self.P = {int(r): (float(x), float(y)) for r, (x, y) in zip(ids, positions)}
        self._set_R(set(self.P))

    def _set_R(self, r: set) -> None:
        self.R = r
        self.r_max = max(r) if r else None

    # -- Algorithm 1 --------------------------------------------------------------

    def _become_head(self, pos) -> None:
        bprime = [(pos[0] + x, pos[1] + y) for x, y in self.basic[1:]]
        chosen = nearest(pos, [r for r in self.R if r != self.id], self.P, len(bprime))
        members = assign(chosen, self.P, bprime)
        self._set_R(self.R - set(chosen) - {self.id})
        self.is_head, self.head_of = True, self.id
        self.heads.add(self.id)
        self.target = (float(pos[0]), float(pos[1]))
        self.offset = (0.0, 0.0)
        self.members = tuple(r for r, _ in members)
        self.pending.append(Group(tuple(sorted(self.R)), self.id, self.target, tuple(members)))

    def _on_group(self, g: Group) -> None:
        for rid, p in g.members:
            if rid == self.id:
                self.target = (float(p[0]), float(p[1]))
                self.head_of = g.head
                self.offset = (p[0] - g.head_pos[0], p[1] - g.head_pos[1])
        self.heads.add(g.head)
        self._set_R(set(g.available))            # R <- R' (as printed)

    # -- Algorithm 2 --------------------------------------------------------------

    def _enter_phase2(self) -> None:
        self.in_phase2 = True
        self.H = tuple(sorted(self.heads))
        self.Q = (max(self.heads),) if self.heads else ()
        self.O = ()

    def _occupied(self, q) -> bool:
        return any(math.hypot(q[0] - o[0], q[1] - o[1]) <= self.tol for o in self.O)

    def _layer(self) -> None:
        p = self.target
        steps = [a for a in self.assembling if math.hypot(*a) > self.tol]          # A \ {(0, 0)}
        if self.reading == "queue":
            aprime = [(p[0] + a[0], p[1] + a[1]) for a in steps]
            aprime = [q for q in aprime if not self._occupied(q)]                  # \ O (positions)
        else:
            aprime = [(p[0] + a[0], p[1] + a[1]) for a in steps]                   # \ O removes no vector
        chosen = nearest(p, [h for h in self.H if h != self.id], self.P, len(aprime))
        assigned = assign(chosen, self.P, aprime)                                   # sorted by ID
        e = [r for r, _ in assigned]
        self.H = tuple(sorted(set(self.H) - set(e) - {self.id}))
        if self.reading == "queue":
            self.Q = tuple(q for q in self.Q if q != self.id) + tuple(x for x in e if x not in self.Q)
            self.O = self.O + (p,) + tuple(q for _, q in assigned)
        else:
            self.Q = self.Q + tuple(x for x in e if x not in self.Q) + (() if self.id in self.Q else (self.id,))
            self.O = tuple(sorted(set(self.O) | set(e)))
        self.acted2 = True
        self.pending.append(Layer(self.H, self.Q, self.id, p, tuple(assigned)))

    def _on_layer(self, m: Layer) -> None:
        self.in_phase2 = True
        for rid, p in m.assigned:
            if rid == self.id:
                self.target = (float(p[0]), float(p[1]))
            if rid == self.head_of and rid != self.id and self.offset is not None:
                self.target = (p[0] + self.offset[0], p[1] + self.offset[1])      # follow the head
        if self.reading == "queue":
            self.O = self.O + (m.sender_pos,) + tuple(q for _, q in m.assigned)
        else:
            self.O = tuple(sorted(set(self.O) | {r for r, _ in m.assigned}))
        self.H, self.Q = m.heads, m.queue

    # -- the step -------------------------------------------------------------------

    def step(self, obs: Observation) -> Command:
        pos = (float(obs.own_pose[0]), float(obs.own_pose[1]))
        for _sender, msg in obs.inbox:
            if isinstance(msg, Group):
                self._on_group(msg)
            elif isinstance(msg, Layer):
                self._on_layer(msg)
        if self.r_max == self.id:                                         # Alg. 1, "Upon ... largest ID in R"
            self._become_head(pos)
        if not self.R and self.is_head and not self.in_phase2:
            self._enter_phase2()
        if self.is_head and self.in_phase2 and not self.acted2 and self.Q and self.Q[0] == self.id:
            self._layer()                                                  # Alg. 2, "Upon ... first in Q"
        message = self.pending.pop(0) if self.pending else None
        if self.target is None:
            self.arrived = False
            return Command(message=message)
        dx, dy = self.target[0] - pos[0], self.target[1] - pos[1]
        self.arrived = math.hypot(dx, dy) <= ARRIVE_EPS
        th = float(obs.own_pose[2])
        c, s = math.cos(th), math.sin(th)
        return steer_toward((c * dx + s * dy, -s * dx + c * dy), self.params, arrive_eps=ARRIVE_EPS, message=message)

    def state(self):
        return (("head", self.head_of), ("is_head", self.is_head), ("members", self.members),
                ("basic", tuple(self.basic) if self.is_head else ()), ("R", len(self.R)),
                ("target", self.target), ("arrived", self.arrived), ("phase", 2 if self.in_phase2 else 1),
                ("H", self.H), ("Q", self.Q), ("O", len(self.O)), ("acted", self.acted2),
                ("pending", len(self.pending)))


# -- runtime invariants (the ``invariants`` property) ----------------------------------------

def _one_group(t, ids, poses, states) -> str | None:
    """002 Alg. 1: a head's group is its own and the m robots it removed from R; R shrinks,
    so every robot is in at most one group (a head's, or one head's members)."""
    owner: dict = {}
    for rid, s in zip(ids.tolist(), states):
        d = dict(s)
        if d["is_head"]:
            for m in (rid,) + tuple(d["members"]):
                if m in owner and owner[m] != rid:
                    return f"robot {m} is in the groups of heads {owner[m]} and {rid}"
                owner[m] = rid
    return None


def _distinct_targets(t, ids, poses, states) -> str | None:
    """002 Algs. 1-2: each position of B' and of A' goes to one robot (the Hungarian assignment
    is one-to-one; Alg. 2's O keeps taken slots out), so no two robots share a target."""
    seen: dict = {}
    for rid, s in zip(ids.tolist(), states):
        tgt = dict(s)["target"]
        if tgt is None:
            continue
        key = (round(tgt[0], 6), round(tgt[1], 6))
        if key in seen:
            return f"robots {seen[key]} and {rid} both head for ({tgt[0]:.6g}, {tgt[1]:.6g})"
        seen[key] = rid
    return None


def _finished_group_is_copy(t, ids, poses, states) -> str | None:
    """002 Alg. 1: a group whose robots have all arrived stands as a translated copy of B (the
    head's own B; within 1e-6), one robot on each point it was given."""
    by_id = {rid: (dict(s), poses[k]) for k, (rid, s) in enumerate(zip(ids.tolist(), states))}
    for rid, (d, p) in by_id.items():
        if not d["is_head"] or not d["arrived"]:
            continue
        group = [m for m in d["members"] if m in by_id]
        if not all(by_id[m][0]["arrived"] for m in group):
            continue
        taken = set()
        for m in group:
            off = by_id[m][1][:2] - p[:2]
            dist = [math.hypot(off[0] - bx, off[1] - by) for bx, by in d["basic"]]
            k = int(np.argmin(dist))
            if dist[k] > 1e-6 or k == 0 or k in taken:
                return (f"head {rid}'s group has arrived but robot {m} stands at offset "
                        f"({off[0]:.6g}, {off[1]:.6g}) from it, not on a free point of B")
            taken.add(k)
    return None


INVARIANTS = (
    Invariant("one_group", "every robot is in at most one group", "002 Alg. 1 (R shrinks by each group)",
              _one_group),
    Invariant("distinct_targets", "no two robots head for one position (no B' or A' slot taken twice)",
              "002 Algs. 1-2 (one-to-one assignment; O records taken positions)", _distinct_targets),
    Invariant("group_is_copy", "a group whose robots have all arrived is a translated copy of B",
              "002 Alg. 1, Def. 4 (the group forms the basic pattern)", _finished_group_is_copy),
)


def _v_positive(params: Params, n: int, ids) -> str | None:
    return None if params.v > 0 else f"v={params.v!r} must be > 0"


class Jiang:
    """Jiang et al.'s algorithm (registry name ``jiang``): Algorithm 2 read as a queue with occupied
    positions (Sec. IV-B's prose).  See the module docstring."""

    name = "jiang"
    #: The controller-state fields the shared checkers may read (swarmproof.invariants.capabilities):
    #: none: it keeps no spanning tree (heads and groups, Sec. IV-A).
    state_fields = ()
    #: The seed paper (docs/references.md) whose claims ``claims`` cites.
    paper = "002"
    #: The reading version (protocol.Algorithm.reading); jiang-literal inherits it.
    reading = "1"
    #: Which rule of Algorithm 2 (docs/decisions.md): "queue" (Sec. IV-B's prose) or "literal".
    rule = "queue"
    model = RobotModel(sensing="global", communication="all", motion="differential", clocks="sync",
                       message_timing="unbounded")
    knows_start = True
    assumptions = (
        Assumption("positive_speed", "v > 0 (robots move at a constant speed, 002 Sec. V-A: 10 cm/s)",
                   "002 Sec. III-A, V-A", _v_positive),
    )
    #: What 002 claims: every run forms the pattern with quality 1 (Sec. V-A, Fig. 7a), which
    #: presupposes that both phases end (Sec. IV-A: "When Alg. 1 terminates ...").
    claims = {
        "formation": "002 Sec. V-A (formation quality 1 in every run, Fig. 7a)",
        "termination": "002 Sec. IV-A/B (the phases end: R empty, every robot at its position)",
    }
    own_end = "R and H empty, Q done, every robot at its position (002 Sec. IV-A/B)"
    #: Runtime invariants of 002's bookkeeping (the ``invariants`` property, every step).
    invariants = INVARIANTS
    explore_targets = ("pattern:rhombus-triangles", "pattern:square-segments", "pattern:square-dots")
    #: 002's algorithm reads no ``Params.extra`` key (the engine refuses every one but its own) and
    #: forms a repeating pattern (002 Defs. 3, 7; ``--pattern lattice:NAME`` for a one-role lattice).
    parameters = ()
    target_kinds = ("pattern",)
    verify = VerifyPlan(targets=("pattern:rhombus-triangles", "pattern:square-segments",
                                 "pattern:triangle-segments", "pattern:trapezoid-hexagons"),
                        robots=12, seeds=(0, 1, 2), explore=True, rank=20, explore_cost=22,
                        # every way of delaying two deliveries by up to 2 steps, 3 robots, 40 steps
                        # (issue 33; within 002's model: unbounded delays): ~2 s CPU
                        exhaustive=(ExhaustiveCell(("termination",), ("delay",), steps=40, deviations=2,
                                                   max_delay=2),))

    @staticmethod
    def team_multiple(target) -> int:
        """002 Sec. V-A places ``|F_d|`` robots, a whole number of copies of B: the explorer draws
        such teams (with another n the quality cannot be 1, Def. 6)."""
        return len(getattr(target, "basic", ((0, 0),)))

    @staticmethod
    def default_params(range: float, n: int) -> Params:
        """002 Sec. V-A: 10 cm/s (v = 0.1 per step of 1 s); omega is not given: pi/2 per step."""
        return Params(range=range, v=0.1, omega=math.pi / 2, dt=1.0)

    def controller(self, robot_id, params: Params, target, rng) -> JiangController:
        basic, assembling = getattr(target, "basic", None), getattr(target, "assembling", None)
        if basic is None or assembling is None:
            from swarmproof.models.errors import UsageError

            raise UsageError(f"{self.name} needs a repeating pattern target (002 Defs. 3, 7), not "
                             f"{getattr(target, 'kind', type(target).__name__)} {getattr(target, 'name', '')!r}",
                             fix="e.g. --pattern rhombus-triangles (swarmproof check-pattern --list), or "
                                 "--pattern lattice:square for a one-role lattice")
        return JiangController(robot_id, params, basic, assembling, self.rule, float(target.tol))

    def finished(self, states) -> bool:
        live = [dict(s) for s in states if s is not None]
        return bool(live) and all(s["R"] == 0 and not s["H"] and not s["Q"] and s["arrived"] and not s["pending"]
                                  and s["phase"] == 2 for s in live)

    @staticmethod
    def default_max_steps(params: Params, n: int) -> int:
        """Phase 1 takes a step per group, phase 2 a step per head, then the trips: bounded
        generously by ``4 n + 40 x (the longest trip in steps over a 30 x 30 area)``."""
        return int(4 * n + 40 * math.ceil(30.0 * math.sqrt(2) / max(params.v * params.dt, 1e-9)))


class JiangLiteral(Jiang):
    """Jiang et al.'s Algorithm 2 as printed (registry name ``jiang-literal``): ``Q = Q u E u {r_i}``
    keeps the acting head first and ``O`` collects robots.  See the module docstring."""

    name = "jiang-literal"
    rule = "literal"
    #: 30 robots: 10 heads, more than the root's 3 slots, so the printed Q shows (docs/jiang.md).
    verify = VerifyPlan(targets=("pattern:rhombus-triangles",), robots=30, seeds=(0, 1, 2), explore=False, rank=21)
