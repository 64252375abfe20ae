"""wang2020's vectorised path: the same run as the engine with the per-robot controller, in numpy.

Issue 15 asks for 1,024 agents forming a shape in minutes; the per-robot path
(:class:`~swarmproof.reference_impl.wang2020.Wang2020Controller` driven by
:func:`~swarmproof.reference_impl.engine.simulate`) costs about 100 us of CPU per
agent and tick there (docs/performance.md).  :func:`simulate_fast` runs every
agent's Algorithms 2-4 at once on arrays and gives the **bit-identical** trace:
the same poses, states, events, meta and status, tested against the reference at
small n (tests/reference_impl/test_wang2020_fast.py).  The per-robot controller
stays the reference: this module follows it rule for rule, not the paper, and a
difference between the two is a bug of this module.

How the sequential parts stay exact
-----------------------------------
* **Algorithm 4 runs per received message, in order** (each may change the goal,
  start a handshake or draw a random number).  Here one vectorised pass classifies,
  from every receiver's state at the start of the tick, what each message can do
  (a higher shape count, or, outside a handshake, the same goal held by a
  lexically larger agent, a swap that lowers the pairwise cost, or one at equal
  cost); messages that can do nothing are no-ops in the reference too.  One
  Python pass in receipt order then applies them: a swap starts the handshake
  (after which only a higher shape count can act), an equal cost draws the
  agent's number first, and the first message that may change anything else
  hands that receiver's remaining messages to a scalar copy of
  ``_goal_manager``.  Every random number is drawn from the agent's own
  generator, in the reference's order (line 16's ``random() < beta`` from the
  generator's raw 64 bits, the same double).  The handshakes begun are written
  in bulk after the pass, and the exchange answers them in bulk (a server
  answers only the client its peer names).
* **msg_buff** (Alg. 2 line 15) is a list of per-tick blocks (every receipt of a
  tick, sorted by receiver then sender ID, as the deque holds them); an entry
  expires by the reference's own float test, ``time < clock() - Delta t``.
  Line 18's "first of the smallest hop" is found per block and combined oldest
  first, which is the deque's order.
* **Kept across ticks** (agents rest on their cells most ticks): the neighbour pairs
  are recomputed only around agents that moved, or, when many moved, from a Verlet list of
  candidates (:meth:`_Run._pairs`, :meth:`_Run._verlet`), a tick's block
  takes the last block's aggregates for every receiver whose receipts did not change
  (:meth:`_Run._carry_over`), and receipts between two agents resting on their goals
  are screened out of Algorithm 4 per agent (:meth:`_Run._gm_kinds`); each gives what
  a fresh computation gives, and the tests compare the traces.
* The engine's grid motion, sensing (:func:`~swarmproof.models.sensing.neighbor_pairs`),
  clocks (:class:`~swarmproof.reference_impl.engine.clocks.AsyncClocks`), recording
  (:class:`~swarmproof.reference_impl.engine.run.Recording`) and checks before the
  run (:func:`~swarmproof.reference_impl.engine.run.preflight`) are the engine's own
  objects or the same float operations in the same order.

What it covers (:func:`unsupported` names anything else): the plain model of
004's analysis -- no fault model, every clock at rate 1 (arbitrary phases), one
speed, no recorded messages, the controller class :class:`Wang2020Controller`
itself (a mutated planner runs on the reference).  Observers and ``stop_when``
get the states as a lazy sequence, valid during the call that received it.

>>> from swarmproof.reference_impl.engine import simulate
>>> from swarmproof.reference_impl.wang2020 import Wang2020
>>> from swarmproof.models.targets import resolve_target
>>> alg, shape = Wang2020(), resolve_target("shape:square-9")
>>> p = alg.default_params(0.6, 9)
>>> init = alg.initial(9, 3, p, shape)
>>> a = simulate(alg, shape, init, p, seed=3)
>>> b = simulate_fast(alg, shape, init, p, seed=3)
>>> (a.status, a.steps) == (b.status, b.steps), trace_json(a) == trace_json(b)
(True, True)
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence

import numpy as np

from swarmproof.models.errors import UsageError
from scipy.spatial import cKDTree

from swarmproof.models.sensing import _BRUTE_MAX, _INFLATE, INCLUSIVE_SLACK, neighbor_pairs
from swarmproof.models.trace import Event

from ..engine.clocks import AsyncClocks
from ..engine.common import _ro
from ..engine.motion import GridMotion
from ..engine.run import (PROGRESS_EVERY, Recording, SimulationResult, _robot_rng, preflight, run_caps,
                         run_meta)

__all__ = ["simulate_fast", "unsupported", "trace_json"]

#: hop-count infinity (Alg. 2 line 2) in the integer arrays
INF = np.int64(1) << 60
_EPS = 1e-9
_ROLE = {0: None, 1: "client", 2: "server"}
#: numpy's ``Generator.random()`` on PCG64: the next 64 bits shifted right by 11, times 2**-53
_DOUBLE_UNIT = 1.0 / 9007199254740992.0
#: columns of a message's integer row (Alg. 3's fields); px, py are a float row
(WPX, WPY, NSX, NSY, TX, TY, QX, QY, HOP, COMP) = range(10)
_NI = 10
#: the integer fields :meth:`_Run._aggregate` reads beside the gradient's (hop, q_u)
_WAIT_HELD = np.array([WPX, WPY, NSX, NSY, TX, TY, COMP])


def trace_json(result) -> str:
    """The trace of a result as canonical JSON text (what the tests compare byte for byte)."""
    import json

    from swarmproof.models.trace import to_jsonable

    t = result.trace
    return json.dumps(to_jsonable({"ids": t.ids, "poses": t.poses, "states": t.states, "events": t.events,
                                   "meta": t.meta, "times": t.times, "present": t.present,
                                   "messages": t.messages, "status": result.status, "steps": result.steps}),
                      sort_keys=True)


def unsupported(algorithm, params, *, faults=None, record_messages: bool = False) -> str | None:
    """Why this run cannot take the vectorised path (None: it can)."""
    reference = getattr(type(algorithm), "vectorised_controller", None)
    if getattr(algorithm, "name", None) != "wang2020" or reference is None \
            or getattr(algorithm, "controller_class", None) is not reference:
        return f"algorithm {getattr(algorithm, 'name', algorithm)!r} is not wang2020 with its reference controller"
    m = algorithm.model
    if (m.sensing, m.communication, m.motion, m.clocks) != ("global", "neighbors", "grid", "async"):
        return "the robot model is not wang2020's"
    if faults is not None and (faults.describe() != type(faults)().describe()):
        return "a fault model is given"
    if record_messages:
        return "record_messages=True"
    ex = params.extra or {}
    lo, hi = ex.get("clock_rate_min", 1.0), ex.get("clock_rate_max", ex.get("clock_rate_min", 1.0))
    if lo != 1.0 or hi != 1.0:
        return f"clock rates clock_rate_min={lo!r}, clock_rate_max={hi!r} (the vectorised path runs rate 1)"
    for key in ("speed_min", "speed_max"):
        if key in ex and ex[key] != params.v:
            return f"{key}={ex[key]!r} differs from v={params.v!r}"
    return None


#: the surrounding waypoints of Alg. 2 lines 21-24 in their order W, S, E, N, and their bit of ``held``
_NEAR_DX = np.array([[-1], [0], [1], [0]], dtype=np.int64)
_NEAR_DY = np.array([[0], [-1], [0], [1]], dtype=np.int64)
_NEAR_BIT = np.arange(4, dtype=np.int64)[:, None]
#: bit of a unit offset (dx, dy) from a waypoint: W 1, S 2, E 4, N 8 (Alg. 2 lines 9, 21), the waypoint itself 16
_LUT = np.array([0, 1, 0, 2, 16, 8, 0, 4, 0], dtype=np.int64)


#: :data:`_LUT` on offsets clipped to [-2, 2], at index ``(5 dx + dy) mod 25`` (0 off the 3 x 3 centre)
_LUT25 = np.zeros(25, dtype=np.int64)
for _dx in (-1, 0, 1):
    for _dy in (-1, 0, 1):
        _LUT25[(5 * _dx + _dy) % 25] = _LUT[(_dx + 1) * 3 + (_dy + 1)]


def _cell_codes(x, y):
    """One integer per cell (x, y), distinct for distinct cells of coordinates below 2**31."""
    return x * (1 << 32) + y


def _count(a, b):
    """How often each element of ``a`` occurs in ``b`` (integer arrays), by sorting ``b``."""
    b = np.sort(b)
    return np.searchsorted(b, a, side="right") - np.searchsorted(b, a, side="left")


def _bits(dx, dy):
    """:data:`_LUT` of offsets (0 for anything farther than one step).

    Clipping to [-2, 2] keeps every offset of the 3 x 3 centre and sends the others to the ring
    around it (0 in :data:`_LUT25`); ``5 dx + dy`` is then in [-12, 12], distinct for distinct
    clipped offsets, and numpy reads a negative index from the end, i.e. modulo 25."""
    return _LUT25[np.minimum(np.maximum(dx, -2), 2) * 5 + np.minimum(np.maximum(dy, -2), 2)]


#: relative margin of :func:`_within`'s squared-distance screen (rounding errors are ~1e-16)
_SCREEN = 1e-9


def _within(dx, dy, lim):
    """``np.hypot(dx, dy) <= lim``, elementwise, computing ``hypot`` (slow) only near ``lim``.

    ``dx * dx + dy * dy`` is within a few ulps of the true squared distance, and ``hypot``
    within one ulp of the true distance; so a squared sum below ``(lim (1 - 1e-9))**2`` has
    ``hypot`` below ``lim`` and one above ``(lim (1 + 1e-9))**2`` has it above: only the band
    between is decided by ``hypot`` itself (grid agents exactly R apart land there)."""
    d2 = dx * dx + dy * dy
    lo, hi = (lim * (1 - _SCREEN)) ** 2, (lim * (1 + _SCREEN)) ** 2
    ok = d2 <= lo
    band = np.nonzero((d2 > lo) & (d2 <= hi))
    if len(band[0]):
        ok[band] = np.hypot(dx[band], dy[band]) <= lim
    return ok


#: line 18's minimum as one integer (:meth:`_Run._gradient`): a finite hop count (below
#: ``_HOP_CAP``), INF as ``_HOP_CAP``, no entry of the shape ``_NO_HOP``; times 2**32 plus the
#: entry's position (below 2**32).  A block's ``ghop`` holds these codes.
_HOP_CAP = 1 << 30
_NO_HOP = _HOP_CAP + 1
_POS_MASK = (1 << 32) - 1


class _Block:
    """One tick's receipts in msg_buff (every receiver's, sorted by receiver then sender ID) and,
    per receiver, what Algorithm 2 reads of them (:meth:`_Run._aggregate`), with the receiver's
    shape, waypoint and position it was computed from (recomputed when one changed).  A receipt's
    message is its sender's column of the tick's outbox ``(I, F)`` (:meth:`_Run.outbox`), read
    when needed: most receipts are never read past the goal managers."""

    __slots__ = ("R", "S", "I", "F", "btime", "present", "ghop", "gqx", "gqy", "held", "wait",
                 "kshape", "kwx", "kwy", "kpx", "kpy", "gshape")
    #: the per-receiver results of :meth:`_Run._aggregate` and the state they were computed from
    #: (``gshape``: the shape its gradient part was computed for, :meth:`_Run._gradient`)
    AGGREGATES = ("ghop", "gqx", "gqy", "held", "wait", "kshape", "kwx", "kwy", "kpx", "kpy", "gshape")

    def __init__(self, n, R, S, I, F, now, present=None) -> None:
        self.R, self.S, self.I, self.F = R, S, I, F     # I, F: by sender slot (the whole outbox)
        self.btime = now                       # every receiver's clock at receipt (all tick at rate 1)
        self.present = np.bincount(R, minlength=n) > 0 if present is None else present
        z = lambda: np.zeros(n, dtype=np.int64)  # noqa: E731
        self.ghop, self.gqx, self.gqy, self.held, self.wait = np.full(n, _NO_HOP), z(), z(), z(), z()
        self.kshape, self.kwx, self.kwy = np.full(n, -1), z(), z()   # shape -1: not computed yet
        self.gshape = np.full(n, -1)
        self.kpx, self.kpy = np.zeros(n), np.zeros(n)


class _StaleStates(UsageError):
    pass


class _States(Sequence):
    """The agents' ``state()`` tuples of one step, built on demand (observers, ``stop_when``).

    An observer may keep them past their step, as with the engine's tuples (the tree-link monitor
    reads the previous step's): the run calls :meth:`freeze` before it changes the agents when
    anything but itself still holds the object, so a later read answers for this step, never for a
    later one.  Only a read that could not be frozen (not expected) is refused."""

    def __init__(self, run, step: int) -> None:
        self._run, self._step, self._cache = run, step, {}
        self._frozen = False

    def values_of(self, key: str) -> list:
        """Every agent's ``state_value(state, key)`` of this step; a key the states do not have
        (``parent``: wang2020 keeps no tree) from the first agent's state alone (every agent's state
        has the same keys, :meth:`_Run.state`); ``completed`` (read every step by the
        ``completion_sound`` monitor) from its array while the run is at this step."""
        from swarmproof.invariants.result import state_value

        if key == "completed" and not self._frozen and self._run.t == self._step:
            return self._run.completed.tolist()
        if self._run.n == 0 or all(k != key for k, _ in self[0]):
            return [None] * self._run.n

        return [state_value(s, key) for s in self]

    def freeze(self) -> None:
        """Build every agent's state of this step now (the run is about to change them)."""
        if not self._frozen and self._run.t == self._step:
            for k in range(self._run.n):
                self[k]
            self._frozen = True

    def __len__(self) -> int:
        return self._run.n

    def __getitem__(self, k):
        if isinstance(k, slice):
            return tuple(self[i] for i in range(*k.indices(self._run.n)))
        n = self._run.n
        k = int(k)
        if not -n <= k < n:
            raise IndexError(f"agent {k} of {n}")
        if k < 0:
            k += n
        if self._frozen:
            return self._cache[k]
        if self._run.t != self._step:
            raise _StaleStates(f"states of step {self._step} read at step {self._run.t}",
                               fix="copy what an observer needs during observe()")
        got = self._cache.get(k)
        if got is None:
            got = self._cache[k] = self._run.state(k)
        return got


class _Run:
    """Every agent of one run as arrays (the fields of :class:`Wang2020Controller`)."""

    def __init__(self, ctrl, ids, poses, params, seed: int, clocks: AsyncClocks) -> None:
        n = len(ids)
        self.n = n
        self.t = 0
        self.ids = np.asarray(ids, dtype=np.int64)
        self.ids_l = self.ids.tolist()
        self.id_rank = np.empty(n, dtype=np.int64)
        self.by_rank = np.argsort(self.ids, kind="stable")          # slot of the i-th smallest ID
        self.id_rank[self.by_rank] = np.arange(n)
        self.rngs = [_robot_rng(seed, k) for k in range(n)]
        self.raw = [r.bit_generator.random_raw for r in self.rngs]    # their next 64 bits
        self.l = ctrl.l
        self.shapes = ctrl.shapes
        self.shape_sets = ctrl.shape_sets
        self.boxes = ctrl.boxes
        self.nshapes = len(self.shapes)
        self.last = self.nshapes - 1
        self.delta_t = ctrl.delta_t
        self.beta, self.p_random = ctrl.beta, ctrl.p_random
        self.timeout = ctrl.timeout
        self.clocks = clocks
        # dense membership grids of the shapes (Q lookups of whole arrays)
        self.qgrid = []
        self.qlen = np.array([len(x) for x in self.shapes], dtype=np.int64)
        for s in self.shapes:
            a = np.array(s, dtype=np.int64)
            lo = a.min(axis=0)
            g = np.zeros(tuple(a.max(axis=0) - lo + 1), dtype=bool)
            g[a[:, 0] - lo[0], a[:, 1] - lo[1]] = True
            self.qgrid.append((lo, g))
        # the same grids with a False border, for lookups clipped into them (_mains, lines 21-24)
        self.qpad = [(lo, np.pad(g, 1)) for lo, g in self.qgrid]
        i64 = lambda: np.zeros(n, dtype=np.int64)  # noqa: E731
        self.started = np.zeros(n, dtype=bool)
        self.completed, self.shape = i64(), i64()
        self.moving = np.zeros(n, dtype=bool)
        self.cx, self.cy, self.wx, self.wy, self.nx, self.ny = i64(), i64(), i64(), i64(), i64(), i64()
        self.Tx, self.Ty, self.qx, self.qy = i64(), i64(), i64(), i64()
        self.hop = np.full(n, INF, dtype=np.int64)
        self.last_check, self.waited = np.zeros(n), np.zeros(n)
        self.px, self.py = np.zeros(n), np.zeros(n)
        self.role, self.peer, self.hseq, self.hgx, self.hgy = i64(), i64(), i64(), i64(), i64()
        self.deadline = np.zeros(n)
        self.seq = i64()
        self.send = np.zeros(n, dtype=bool)     # a client's request to send in this tick's exchange
        self.sorted_ids = self.ids[self.by_rank]
        self.swaps = i64()
        self.took_role, self.took_peer, self.took_seq = i64(), i64(), i64()   # state "took" (0: None)
        self.blocks: list = []          # msg_buff: per tick, dict of arrays sorted by (receiver, sender id)
        self._heard = self._prev_heard = None
        self.prev_blocks: list = []
        self.cutoff = self.prev_cutoff = None
        self.grid_poses = poses
        self._nb = None                 # the last neighbour pairs: (xy, keys, receivers, senders)
        self._vl = None                 # the Verlet list (_verlet)
        self.moved = np.ones(n, dtype=bool)
        self._last = None               # the last tick's block, messages and broadcast flags

    # -- scalar pieces: copies of the reference's methods, on slot k ---------------------

    def _random_goal(self, k):
        Q = self.shapes[int(self.shape[k])]
        return Q[int(self.rngs[k].integers(len(Q)))]

    def _begin_shape(self, k, now):
        self.hop[k] = INF
        self.qx[k], self.qy[k] = self._random_goal(k)        # line 3
        self.Tx[k], self.Ty[k] = self._random_goal(k)        # line 4
        self.nx[k], self.ny[k] = self.wx[k], self.wy[k]      # line 5
        self.last_check[k] = now                             # line 7
        self.role[k] = 0

    def _switch(self, k, now):
        self.completed[k] += 1
        self.shape[k] = min(int(self.completed[k]), self.nshapes - 1)
        if self.completed[k] < self.nshapes:
            self._begin_shape(k, now)

    def _greedy(self, k):
        wx, wy, tx, ty = int(self.wx[k]), int(self.wy[k]), int(self.Tx[k]), int(self.Ty[k])
        if tx < wx:
            return wx - 1, wy
        if ty < wy:
            return wx, wy - 1
        if tx > wx:
            return wx + 1, wy
        if ty > wy:
            return wx, wy + 1
        return wx, wy

    def _gm(self, k, now, sid, m, mf):
        """``Wang2020Controller._goal_manager`` for receiver slot k and one received message from
        ``sid`` (``m``: its integer row, ``mf``: (px, py))."""
        mc = m[COMP]
        while mc > self.completed[k]:
            self._switch(k, now)
        if min(mc, self.last) != self.shape[k] or self.role[k] != 0:
            return
        T = (int(self.Tx[k]), int(self.Ty[k]))
        mT = (m[TX], m[TY])
        mp = (mf[0], mf[1])
        p = (float(self.px[k]), float(self.py[k]))
        if mT == T and mp > p:                                    # Alg. 4 lines 3-5
            rng = self.rngs[k]
            if rng.random() > self.p_random:                      # lines 6-9
                T = (int(self.qx[k]), int(self.qy[k]))
            else:
                T = self._random_goal(k)
            self.Tx[k], self.Ty[k] = T
            self.last_check[k] = now
        wx, wy = int(self.wx[k]), int(self.wy[k])
        mx, my = m[WPX], m[WPY]
        now_cost = abs(wx - T[0]) + abs(wy - T[1]) + abs(mx - mT[0]) + abs(my - mT[1])
        swap_cost = abs(wx - mT[0]) + abs(wy - mT[1]) + abs(mx - T[0]) + abs(my - T[1])
        if swap_cost < now_cost or (swap_cost == now_cost and self.rngs[k].random() < self.beta):
            if mp > p:                                            # client (Sec. III-A)
                self.seq[k] += 1
                self.role[k], self.hseq[k] = 1, self.seq[k]
                self.send[k] = True
            else:
                self.role[k], self.hseq[k] = 2, -1
            self.peer[k] = sid
            self.deadline[k] = now + self.timeout
            self.hgx[k], self.hgy[k] = T

    # -- the state of slot k, as Wang2020Controller.state() builds it ------------------------

    def state(self, k):
        if not self.started[k]:
            return (("cell", None), ("next", None), ("goal", None), ("priority", None), ("wp", None),
                    ("moving", False), ("shape", 0), ("completed", 0), ("done", False), ("hop", None),
                    ("q_u", None), ("handshake", None), ("ack", None), ("waited", 0.0), ("window", self.delta_t),
                    ("heard", ()), ("n_goals", len(self.shapes[0])), ("shape_box", self.boxes[0]),
                    ("spacing", self.l), ("took", None))
        wp = (int(self.wx[k]), int(self.wy[k]))
        ns = (int(self.nx[k]), int(self.ny[k]))
        moving = bool(self.moving[k])
        nxt = wp if moving else (None if ns == wp else ns)
        role = int(self.role[k])
        hs = None if role == 0 else (_ROLE[role], int(self.peer[k]), int(self.hseq[k]))
        hop = int(self.hop[k])
        tr = int(self.took_role[k])
        took = None if tr == 0 else (_ROLE[tr], int(self.took_peer[k]), int(self.took_seq[k]))
        shape = int(self.shape[k])
        completed = int(self.completed[k])
        return (("cell", (int(self.cx[k]), int(self.cy[k]))), ("next", nxt),
                ("goal", (int(self.Tx[k]), int(self.Ty[k]))), ("priority", (float(self.px[k]), float(self.py[k]))),
                ("wp", wp), ("moving", moving), ("shape", shape),
                ("completed", completed), ("done", completed >= self.nshapes),
                ("hop", None if hop == INF else hop), ("q_u", (int(self.qx[k]), int(self.qy[k]))),
                ("handshake", hs), ("ack", None),
                ("waited", float(self.waited[k])), ("window", float(self.delta_t)),
                ("heard", self._heard_of(k)),
                ("n_goals", len(self.shapes[shape])), ("shape_box", self.boxes[shape]), ("spacing", self.l),
                ("took", took))

    def heard_keys(self, previous: bool = False) -> np.ndarray:
        """``receiver * n + sender`` of every sender in msg_buff, sorted, unique (state key "heard");
        ``previous``: the same of the tick before."""
        if previous:
            if self._prev_heard is None:
                self._prev_heard = self._keys(self.prev_blocks, self.prev_cutoff)
            return self._prev_heard
        if self._heard is None:
            self._heard = self._keys(self.blocks, self.cutoff)
        return self._heard

    def _keys(self, blocks, cutoff) -> np.ndarray:
        n = self.n
        parts = []
        for b in blocks:
            alive = (b.btime >= cutoff)[b.R]
            parts.append((b.R * n + b.S)[alive])
        return np.unique(np.concatenate(parts)) if parts else np.zeros(0, np.int64)

    def _heard_of(self, k) -> tuple:
        """The IDs slot k heard in msg_buff (its part of :meth:`heard_keys`), from its own run of
        entries in each block: one agent's state costs a few searches, not the whole buffer's
        keys (an observer may read one agent's state every step)."""
        heard = set()
        for b in self.blocks:
            if b.btime[k] >= self.cutoff[k]:
                lo, hi = np.searchsorted(b.R, (k, k + 1))
                heard.update(b.S[lo:hi].tolist())
        return tuple(sorted(self.ids_l[s] for s in heard))

    def signature(self):
        """Everything a state holds but "heard", as arrays (with :meth:`heard_keys`: a step changed
        no state iff these are equal)."""
        ints = np.stack((self.started, self.cx, self.cy, self.nx, self.ny, self.Tx, self.Ty, self.wx, self.wy,
                         self.moving, self.shape, self.completed, self.hop, self.qx, self.qy, self.role,
                         np.where(self.role != 0, self.peer, 0), np.where(self.role != 0, self.hseq, 0),
                         self.took_role, self.took_peer, self.took_seq))
        floats = np.stack((self.px, self.py, self.waited))
        return ints, floats

    def outbox(self):
        """Algorithm 3's message of every agent (``Wang2020Controller.message``): an integer row
        (rows WPX ... COMP, a column per agent) and a float one (px, py): field-major, so a
        field of the tick's receipts is one contiguous row."""
        I = np.empty((_NI, self.n), dtype=np.int64)
        I[WPX], I[WPY], I[NSX], I[NSY] = self.wx, self.wy, self.nx, self.ny
        I[TX], I[TY], I[QX], I[QY] = self.Tx, self.Ty, self.qx, self.qy
        I[HOP], I[COMP] = self.hop, self.completed
        if ((self.hop >= _HOP_CAP) & (self.hop != INF)).any():
            raise AssertionError("a hop count of 2**30 or more: outside the gradient's codes (_Run._gradient)")
        return I, np.stack((self.px, self.py))

    def exchange(self, now) -> None:
        """The engine's exchange phase (engine/phases.py ``exchange``, between every agent's
        ``requests`` and every agent's ``step``) for the handshakes begun this tick: every
        client's request, in slot order, answered by its server (``Wang2020Controller.answer``),
        then every answer read by its client (``on_reply``), in the same order -- the engine's
        queue order; each peer is a neighbour (its message was just received)."""
        ks = np.flatnonzero(self.send)
        if not len(ks):
            return
        self.send[:] = False
        role, peer, deadline, Tx, Ty = self.role, self.peer, self.deadline, self.Tx, self.Ty
        ks = ks[role[ks] == 1]                            # else the handshake ended this tick (a shape switch)
        # each server answers the one client its peer names (a server is no client): no order between them
        srv = self.by_rank[np.searchsorted(self.sorted_ids, peer[ks])]
        ok = (role[srv] == 2) & (peer[srv] == self.ids[ks]) & ~(now[srv] > deadline[srv])
        a, s = ks[ok], srv[ok]
        oldx, oldy = Tx[s], Ty[s]
        Tx[s], Ty[s] = self.hgx[a], self.hgy[a]
        self.last_check[s] = now[s]
        role[s] = 0
        self.swaps[s] += 1
        self.took_role[s], self.took_peer[s], self.took_seq[s] = 2, self.ids[a], self.hseq[a]
        # every client reads its answer (its role is still 1: only servers changed above)
        live = ~(now[ks] > deadline[ks])
        role[ks[live]] = 0
        c = ks[ok & live]
        Tx[c], Ty[c] = oldx[live[ok]], oldy[live[ok]]
        self.last_check[c] = now[c]
        self.swaps[c] += 1
        self.took_role[c], self.took_peer[c], self.took_seq[c] = 1, peer[c], self.hseq[c]

    # -- one tick of every agent (Wang2020Controller.step) -------------------------------------

    def tick(self, poses, now, last_msgs, last_valid, phi):
        n, l = self.n, self.l
        x, y = poses[:, 0].copy(), poses[:, 1].copy()
        self.px, self.py = x, y
        cx, cy = np.rint(x / l), np.rint(y / l)
        at_cell = (np.abs(x - cx * l) <= _EPS * l) & (np.abs(y - cy * l) <= _EPS * l)
        cx, cy = cx.astype(np.int64), cy.astype(np.int64)
        fresh = ~self.started
        if fresh.any():                                           # Alg. 2 line 1, lines 2-7
            for k in np.flatnonzero(fresh).tolist():
                self.started[k] = True
                self.cx[k] = self.wx[k] = cx[k]
                self.cy[k] = self.wy[k] = cy[k]
                self._begin_shape(k, float(now[k]))
        arrived = self.moving & at_cell & (cx == self.wx) & (cy == self.wy)
        self.moving[arrived] = False                              # line 32 returns
        self.cx[arrived], self.cy[arrived] = cx[arrived], cy[arrived]
        self.last_check[arrived] = now[arrived]                   # line 33
        self.role[(self.role != 0) & (now > self.deadline)] = 0   # handshake timeout (Sec. III-A)

        # this tick's receipts: every neighbour within R that broadcast last tick, by sender ID
        R, S = self._receipts(poses, phi, last_valid)
        I, F = last_msgs                                          # by sender slot
        self._goal_managers(R, S, I, F, now)
        cutoff = now - self.delta_t                               # msg_buff: since clock() - Delta t
        last = self._last[0] if self._last is not None else None
        b = _Block(self.n, R, S, I, F, now, last.present if last is not None and last.R is R else None)
        self._carry_over(b, last_msgs, last_valid)
        kept = [x for x in self.blocks if (x.present & (x.btime >= cutoff)).any()]
        kept.append(b)
        self.prev_blocks, self.blocks = self.blocks, kept
        self.prev_cutoff, self.cutoff = self.cutoff, cutoff
        self._prev_heard, self._heard = self._heard, None
        self.exchange(now)                                        # the handshakes, before Alg. 2 (engine: 4b)
        return self._mains(now, cutoff)

    def _carry_over(self, b, msgs, valid) -> None:
        """Give block ``b`` the previous tick's block's aggregates (:meth:`_aggregate`) for every
        receiver whose receipts are the same in both: the same senders, in the same order, with
        the same messages.  A receiver's receipts can differ only if it moved, or one of its
        senders (in either block) moved, changed its message or its broadcast flag; the others'
        entries are equal, so what :meth:`_aggregate` computed from them (for the receiver's
        shape, waypoint and position stored beside it, checked when read) is equal too."""
        prev, self._last = self._last, (b, msgs, valid)
        if prev is None:
            return
        pb, pmsgs, pvalid = prev
        changed = msgs[0] != pmsgs[0]
        senders = (self.moved | (valid != pvalid) | changed[_WAIT_HELD].any(axis=0)
                   | (msgs[1] != pmsgs[1]).any(axis=0))
        dirty = self.moved.copy()
        dirty[pb.R[senders[pb.S]]] = True
        dirty[b.R[senders[b.S]]] = True
        for name in _Block.AGGREGATES:
            setattr(b, name, getattr(pb, name).copy())
        b.kshape[dirty] = -1                                     # not computed for these receipts
        # a sender that changed only its hop or q_u (and did not move) is in both blocks' lists of
        # the same receivers: their gradient alone is recomputed (_gradient)
        grad = changed[HOP] | changed[QX] | changed[QY]
        dirty[b.R[grad[b.S]]] = True
        b.gshape[dirty] = -1

    def _receipts(self, poses, phi, last_valid):
        """``(R, S)``: receiver and sender slots of the tick's deliveries, sorted by receiver, then
        sender ID: the engine's neighbours within R (:func:`~swarmproof.models.sensing.neighbor_pairs`,
        inclusive) that broadcast in the previous tick.  Also sets ``self.moved`` (the agents whose
        position differs from the last call's; every agent at the first).

        The neighbour pairs are kept from the last call (:meth:`_pairs`): only pairs with an agent
        that moved can differ (grid agents rest on their cells most ticks)."""
        K, PR, PS = self._pairs(poses[:, :2], phi)
        if last_valid.all():
            return PR, PS          # the same arrays while the pairs do not change (_Block reuses them)
        keep = last_valid[PS]
        return PR[keep], PS[keep]

    def _pairs(self, xy, phi):
        """Every ordered neighbour pair ``(receiver, sender)`` and its sort key
        ``receiver * n + id_rank[sender]`` (unique), sorted by the key: ``(K, R, S)``.

        The set is :func:`~swarmproof.models.sensing.neighbor_pairs`' (inclusive): every pair
        whose ``hypot`` distance is at most ``phi * INCLUSIVE_SLACK`` -- its k-d tree only
        proposes candidates, and its brute-force branch (up to 50 agents) gives the same set.  So
        after a first full computation, a call where few agents moved drops the pairs of those
        agents and adds theirs again from the same exact test (:func:`_within`) against every
        agent (``hypot`` is symmetric in sign, so the distance is the same bits whichever end is
        subtracted), then sorts the keys again (a stable sort of one sorted run and a short tail);
        the result is the same arrays as a full computation.  Where many agents moved (above 50
        agents) the same exact test runs on a kept list of candidate pairs (:meth:`_verlet`)."""
        n = self.n
        prev = self._nb
        if prev is not None:
            old = prev[0]           # (column by column: any(axis=1) on two columns is slower)
            moved = np.flatnonzero((xy[:, 0] != old[:, 0]) | (xy[:, 1] != old[:, 1]))
            if not len(moved):
                self.moved = np.zeros(n, dtype=bool)
                return prev[1:]
        else:
            moved = np.arange(n)
        mask = np.zeros(n, dtype=bool)
        mask[moved] = True
        self.moved = mask
        lim = phi * INCLUSIVE_SLACK
        if n > _BRUTE_MAX and (prev is None or len(moved) * 16 > n):   # many moved: the Verlet list
            got = self._verlet(xy, phi, lim, prev)
            self._nb = (xy.copy(),) + got
            return got
        if prev is None or len(moved) * 4 > n:      # (up to 50 agents) everything again: the engine's search
            i, j, _ = neighbor_pairs(xy, phi, True)
            K = np.sort(np.concatenate((i * n + self.id_rank[j], j * n + self.id_rank[i])))
            R = K // n
            S = self.by_rank[K - R * n]
        else:
            _, K0, R0, S0 = prev
            stay = ~(mask[R0] | mask[S0])
            dx = xy[None, :, 0] - xy[moved, 0][:, None]            # (moved, every agent)
            dy = xy[None, :, 1] - xy[moved, 1][:, None]
            near = _within(dx, dy, lim)
            near[np.arange(len(moved)), moved] = False             # not itself
            a, j = np.nonzero(near)
            c = moved[a]
            NK = c * n + self.id_rank[j]
            # the moved agents' neighbours as before (their edges are long, their range's border
            # rarely crossed): every pair is the same, as pairs are symmetric
            lo, hi = np.searchsorted(R0, moved), np.searchsorted(R0, moved, side="right")
            cnt = hi - lo
            if np.array_equal(cnt, np.bincount(a, minlength=len(moved))):
                at = np.repeat(lo - np.cumsum(cnt) + cnt, cnt) + np.arange(int(cnt.sum()))
                if np.array_equal(K0[at], np.sort(NK)):
                    self._nb = (xy.copy(),) + prev[1:]
                    return prev[1:]
            # each ordered pair once: (moved, any) from its row; (other, moved) only from the
            # moved agent's row when the other did not move (else its own row gives it)
            other = ~mask[j]
            R = np.concatenate((R0[stay], c, j[other]))
            S = np.concatenate((S0[stay], j, c[other]))
            K = np.concatenate((K0[stay], NK, j[other] * n + self.id_rank[c[other]]))
            o = np.argsort(K, kind="stable")
            K, R, S = K[o], R[o], S[o]
        self._nb = (xy.copy(), K, R, S)
        return K, R, S

    def _verlet(self, xy, phi, lim, prev):
        """``(K, R, S)`` of :meth:`_pairs` from a Verlet list: every pair within ``lim + skin``
        (``skin = phi / 6``) when the list was built, so every pair within ``lim`` now while no agent
        has moved more than ``skin / 2`` since (the triangle inequality; rebuilt otherwise); the
        exact test (:func:`_within`) on the candidates, in key order, gives the set sorted.
        Returns the last call's arrays themselves when the set did not change."""
        n = self.n
        skin = phi / 6.0
        vl = self._vl
        if vl is not None:
            d = xy - vl[0]
            far = float(((d * d).sum(axis=1)).max()) > (0.5 * skin * (1 - 1e-6)) ** 2
        if vl is None or far:
            pr = cKDTree(xy).query_pairs(r=(lim + skin) * _INFLATE, output_type="ndarray")
            i, j = pr[:, 0].astype(np.int64), pr[:, 1].astype(np.int64)
            keys = np.concatenate((i * n + self.id_rank[j], j * n + self.id_rank[i]))
            o = np.argsort(keys)
            VK = keys[o]
            VR = VK // n
            vl = self._vl = (xy.copy(), i, j, VK, VR, self.by_rank[VK - VR * n],
                             np.concatenate((np.arange(len(i)), np.arange(len(i))))[o], None)
        _, i, j, VK, VR, VS, VU, last = vl
        ok = _within(xy[j, 0] - xy[i, 0], xy[j, 1] - xy[i, 1], lim)[VU]
        # the last arrays are this list's of the same set (no other path made them since)
        if last is not None and prev is not None and prev[1] is last[1] and np.array_equal(ok, last[0]):
            return prev[1:]
        got = VK[ok], VR[ok], VS[ok]
        self._vl = vl[:7] + ((ok, got[0]),)
        return got

    def _goal_managers(self, R, S, I, F, now):
        """Algorithm 4 on every receipt of the tick, each receiver in sender-ID order (module
        docstring); the messages are the senders' columns of ``I`` and ``F``.

        Every receipt's effect is classified once, from its receiver's state at the start of the
        tick (:meth:`_gm_kinds`); then one pass in receipt order applies them.  A receiver's state
        changes only where a receipt acts on it, so its later kinds stay valid while it has done
        nothing but draw a number at equal cost and keep its goal (line 16 false); once it begins a
        handshake (lines 12, 18) only a higher shape count can act on it (a blocked agent returns,
        as in the reference); a higher shape count or a goal held by a larger agent (kind 1) can
        change anything, so that receiver's remaining receipts run through the scalar copy
        :meth:`_gm`, one by one, as the reference does."""
        if len(R) == 0:
            return
        E, kinds, gt = self._gm_kinds(R, S, I, F)
        if not len(E):
            return
        RE = R[E]
        nE = len(E)
        head = np.empty(nE, dtype=bool)       # each receiver's run of E
        head[0] = True
        np.not_equal(RE[1:], RE[:-1], out=head[1:])
        starts = np.flatnonzero(head)
        pos = np.arange(nE)
        # the first kind 1 at or after each entry (nE: none); its run ends at ``ends``
        nxt1 = np.minimum.accumulate(np.where(kinds == 1, pos, nE)[::-1])[::-1].tolist()
        ends = starts[1:].tolist() + [nE]
        raw, beta = self.raw, self.beta
        E_l, kinds_l, gt_l = E.tolist(), kinds.tolist(), gt.tolist()
        sid_e = self.ids[S[E]].tolist()
        hk, hc, hs = [], [], []              # the handshakes begun: receiver, client side, peer ID
        for k, i, end in zip(RE[starts].tolist(), starts.tolist(), ends):
            while True:
                kind = kinds_l[i]
                if kind == 1:      # the rest of this receiver's receipts, the reference's way
                    self._gm_rest(k, E_l[i], R, S, I, F, now)
                    break
                # kind 3: equal cost, the agent's own draw (line 16: ``rng.random() < beta``, the
                # double of the next 64 random bits, as numpy's PCG64 makes it); kind 2: a lower
                # cost (line 11).  Either begins a handshake: then only a kind 1 acts on it.
                if kind == 2 or (raw[k]() >> 11) * _DOUBLE_UNIT < beta:
                    j = nxt1[i + 1] if i + 1 < end else nE
                    if j < end:    # its handshake first (written below for the others)
                        self._begin_handshakes([k], [gt_l[i]], [sid_e[i]], now)
                        self._gm_rest(k, E_l[j], R, S, I, F, now)
                    else:
                        hk.append(k)
                        hc.append(gt_l[i])
                        hs.append(sid_e[i])
                    break
                i += 1
                if i == end:
                    break
        if hk:
            self._begin_handshakes(hk, hc, hs, now)

    def _gm_rest(self, k, e, R, S, I, F, now) -> None:
        """:meth:`_gm` on receiver k's receipts from receipt ``e`` to the end of its run."""
        end = int(np.searchsorted(R, k, side="right"))
        ids_s = self.ids[S[e:end]].tolist()
        rows, frows = I[:, S[e:end]].T.tolist(), F[:, S[e:end]].T.tolist()
        now_k = float(now[k])
        for sid_j, row, frow in zip(ids_s, rows, frows):
            self._gm(k, now_k, sid_j, row, frow)

    def _begin_handshakes(self, ks, client, sids, now) -> None:
        """:meth:`_gm`'s handshake (Sec. III-A) for receivers ``ks`` (each once), the client side
        where ``client`` (the sender lexically larger), with peers ``sids``."""
        ks = np.array(ks, dtype=np.int64)
        client = np.array(client, dtype=bool)
        kc, kv = ks[client], ks[~client]
        self.seq[kc] += 1
        self.role[kc], self.hseq[kc] = 1, self.seq[kc]
        self.send[kc] = True
        self.role[kv], self.hseq[kv] = 2, -1
        self.peer[ks] = sids
        self.deadline[ks] = now[ks] + self.timeout
        self.hgx[ks], self.hgy[ks] = self.Tx[ks], self.Ty[ks]

    def _gm_kinds(self, R, S, I, F):
        """What each receipt does to its receiver in :meth:`_gm`, from the receiver's current
        state: ``(E, kinds, gt)`` for the receipts E that can do anything, sorted (the others are
        no-ops of the reference too: another shape's message, a blocked receiver, or a swap that
        would raise the pairwise cost): kind 1 a higher shape count (Sec. III-B) or the
        receiver's goal held by a lexically larger sender (lines 3-9), 2 a swap that lowers the
        cost (line 11), 3 one at equal cost (line 16); ``gt``: the sender lexically larger (the
        handshake's client side)."""
        comp = I[COMP]                                   # by sender slot
        up = None                                        # a higher shape count: only while one spreads
        if comp.max() > self.completed.min():
            up = np.flatnonzero(comp[S] > self.completed[R])
        mcc = np.minimum(comp, self.last)
        shape = self.shape
        # Receipts that cannot act, screened per agent: a receiver in a handshake returns; and
        # when both ends rest on their goals (waypoint = goal) the cost now is 0 and a swap's is
        # 2 |w - m|, so only w = m acts -- then both goals are that cell, so a receiver whose goal
        # is some resting sender's goal is examined whole ("clash").
        at_goal = (self.wx == self.Tx) & (self.wy == self.Ty)
        sender_at_goal = (I[WPX] == I[TX]) & (I[WPY] == I[TY])
        mine_c = _cell_codes(self.Tx, self.Ty)
        held_c = _cell_codes(I[TX], I[TY])
        # how many resting senders hold my goal, not counting my own message
        clash = at_goal & (_count(mine_c, held_c[sender_at_goal]) > (sender_at_goal & (held_c == mine_c)))
        code = np.where(self.role == 0, np.where(at_goal & ~clash, 1, 2), 0)[R]
        free = (code == 2) | ((code == 1) & ~sender_at_goal[S])
        if not ((mcc == shape[0]).all() and (shape == shape[0]).all()):
            free &= mcc[S] == shape[R]                   # another shape's message returns
        if up is not None:
            free[up] = False
        if free.all():
            f, rf, sf = None, R, S
        else:
            f = np.flatnonzero(free)
            rf, sf = R[f], S[f]
        Tx, Ty = self.Tx[rf], self.Ty[rf]
        mTx, mTy = I[TX][sf], I[TY][sf]
        mpx, mpy = F[0][sf], F[1][sf]
        px = self.px[rf]
        gt = (mpx > px) | ((mpx == px) & (mpy > self.py[rf]))
        same = (mTx == Tx) & (mTy == Ty) & gt
        wx, wy, mx, my = self.wx[rf], self.wy[rf], I[WPX][sf], I[WPY][sf]
        # the cost now is the receiver's distance to its goal plus the sender's to its own: per agent
        mine = np.abs(self.wx - self.Tx) + np.abs(self.wy - self.Ty)
        theirs = np.abs(I[WPX] - I[TX]) + np.abs(I[WPY] - I[TY])
        now_c = mine[rf] + theirs[sf]
        swap_c = np.abs(wx - mTx) + np.abs(wy - mTy) + np.abs(mx - Tx) + np.abs(my - Ty)
        kind = np.where(swap_c <= now_c, np.where(swap_c == now_c, 3, 2), 0)
        kind[same] = 1
        nz = np.flatnonzero(kind)
        E, kinds, g = (nz if f is None else f[nz]), kind[nz], gt[nz]
        if up is not None and len(up):                   # merged in receipt order (disjoint from f)
            E = np.concatenate((E, up))
            o = np.argsort(E, kind="stable")
            E = E[o]
            kinds = np.concatenate((kinds, np.ones(len(up), dtype=kinds.dtype)))[o]
            g = np.concatenate((g, np.zeros(len(up), dtype=bool)))[o]
        return E, kinds, g

    def _aggregate(self, b, sel):
        """What Algorithm 2 reads of block ``b``, per receiver, for the receivers of entries ``sel``
        (all, or the stale ones), from their current shape, waypoint and position: the
        gradient's candidate of this block (line 18: the first entry of the smallest hop among
        this shape's entries), the surrounding waypoints it holds as goals (lines 21-22) and the
        ones it claims (line 26: wp) or a lexically larger sender heads for (line 28)."""
        R, S = b.R[sel], b.S[sel]
        E = len(R)
        if not E:
            return
        I, F = b.I, b.F                      # by sender slot: only the fields used are gathered
        head = np.empty(E, dtype=bool)       # first entry of each receiver's run (R is sorted)
        head[0] = True
        np.not_equal(R[1:], R[:-1], out=head[1:])
        starts = np.flatnonzero(head)
        gR = R[starts]
        wx, wy, px = self.wx[R], self.wy[R], self.px[R]
        fx = F[0][S]
        gt = (fx > px) | ((fx == px) & (F[1][S] > self.py[R]))
        wb = _bits(I[WPX][S] - wx, I[WPY][S] - wy) | np.where(gt, _bits(I[NSX][S] - wx, I[NSY][S] - wy), 0)
        b.wait[gR] = np.bitwise_or.reduceat(wb, starts)
        sm = np.minimum(I[COMP][S], self.last) == self.shape[R]
        b.held[gR] = np.bitwise_or.reduceat(np.where(sm, _bits(I[TX][S] - wx, I[TY][S] - wy) & 15, 0), starts)
        b.kshape[gR], b.kwx[gR], b.kwy[gR] = self.shape[gR], self.wx[gR], self.wy[gR]
        b.kpx[gR], b.kpy[gR] = self.px[gR], self.py[gR]
        self._gradient(b, R, S, starts, sm)

    def _gradient(self, b, R, S, starts=None, sm=None):
        """The gradient part of :meth:`_aggregate` alone (line 18: per receiver, the first entry of
        the smallest hop among this shape's entries), for entries ``R, S`` of whole receivers:
        it reads only the receiver's shape and the senders' shape count, hop and q_u."""
        E = len(R)
        I = b.I
        if starts is None:
            head = np.empty(E, dtype=bool)
            head[0] = True
            np.not_equal(R[1:], R[:-1], out=head[1:])
            starts = np.flatnonzero(head)
            sm = np.minimum(I[COMP][S], self.last) == self.shape[R]
        gR = R[starts]
        # the smallest hop and the first entry holding it, as one minimum of (code, position): the
        # codes keep the order of finite hop counts (below _HOP_CAP, Run.outbox), INF and none
        code = np.where(sm, np.minimum(I[HOP][S], _HOP_CAP), _NO_HOP)
        kmin = np.minimum.reduceat((code << 32) | np.arange(E), starts)
        b.ghop[gR] = kmin >> 32
        sf = S[kmin & _POS_MASK]
        b.gqx[gR], b.gqy[gR] = I[QX][sf], I[QY][sf]
        b.gshape[gR] = self.shape[gR]

    def _mains(self, now, cutoff):
        """Algorithm 2 lines 9-35 for every agent at a waypoint; returns (movers, dx, dy)."""
        n = self.n
        M = ~self.moving
        wx, wy, Tx, Ty = self.wx, self.wy, self.Tx, self.Ty
        # lines 9-14: greedy next_step (W, S, E, N)
        nx = np.where(Tx < wx, wx - 1, np.where(Ty < wy, wx, np.where(Tx > wx, wx + 1, wx)))
        ny = np.where(Tx < wx, wy, np.where(Ty < wy, wy - 1, np.where(Tx > wx, wy, np.where(Ty > wy, wy + 1, wy))))
        self.nx = np.where(M, nx, self.nx)
        self.ny = np.where(M, ny, self.ny)
        # msg_buff, block by block, oldest first (the deque's order)
        best = np.full(n, _NO_HOP, dtype=np.int64)
        bqx, bqy = np.zeros(n, np.int64), np.zeros(n, np.int64)
        held = np.zeros(n, np.int64)
        wait = np.zeros(n, np.int64)
        for b in self.blocks:
            use = M & b.present & (b.btime >= cutoff)
            stale = use & ((b.kshape != self.shape) | (b.kwx != wx) | (b.kwy != wy) | (b.kpx != self.px)
                           | (b.kpy != self.py))
            if stale.any():
                self._aggregate(b, np.flatnonzero(stale[b.R]))
            stale = use & (b.gshape != self.shape)          # only the gradient's senders changed
            if stale.any():
                sel = np.flatnonzero(stale[b.R])
                self._gradient(b, b.R[sel], b.S[sel])
            wait |= np.where(use, b.wait, 0)
            held |= np.where(use, b.held, 0)
            h = np.where(use, b.ghop, _NO_HOP)
            # line 18: the first of the smallest hop; an older block keeps ties; none finite -> the
            # first entry (in codes: finite < INF < none, so a block's candidate wins iff smaller)
            take = h < best
            if take.any():
                best = np.minimum(best, h)
                bqx, bqy = np.where(take, b.gqx, bqx), np.where(take, b.gqy, bqy)
        g = best != _NO_HOP
        self.hop = np.where(g, np.where(best == _HOP_CAP, INF, best + 1), self.hop)        # line 19
        self.qx = np.where(g, bqx, self.qx)                                                  # line 20
        self.qy = np.where(g, bqy, self.qy)
        if g.any():                                                                          # lines 21-24
            # the four surrounding waypoints at once, rows W, S, E, N (bits 1, 2, 4, 8 of held)
            cxa, cya = wx + _NEAR_DX, wy + _NEAR_DY
            q = np.zeros((4, n), dtype=bool)
            for si, (lo, pad) in enumerate(self.qpad):
                on = g & (self.shape == si)
                if not on.any():
                    continue
                # clipped into the padded grid: anything outside Q's box reads its False border
                ix = np.minimum(np.maximum(cxa - (lo[0] - 1), 0), pad.shape[0] - 1)
                iy = np.minimum(np.maximum(cya - (lo[1] - 1), 0), pad.shape[1] - 1)
                q |= pad[ix, iy] & on
            # the first surrounding waypoint (W, S, E, N) in Q that no entry holds as its goal
            free = q & ((held >> _NEAR_BIT) & 1 == 0)
            pick = np.flatnonzero(free.any(axis=0))
            if len(pick):
                d = free[:, pick].argmax(axis=0)
                self.qx[pick], self.qy[pick] = cxa[d, pick], cya[d, pick]
                self.hop[pick] = 0
        # Sec. III-B: hop-count above |A| -> the shape is complete
        qlen = self.qlen[self.shape]
        sw = M & (self.completed < self.nshapes) & (self.hop != INF) & (self.hop > qlen)
        for k in np.flatnonzero(sw).tolist():
            self._switch(k, float(now[k]))
            self.nx[k], self.ny[k] = self._greedy(k)
        # lines 25-29: wait_flag (any entry claims next_step, or a larger agent heads there)
        nx, ny = self.nx, self.ny
        flag = (wait & _bits(nx - wx, ny - wy)) != 0
        # line 30: move when no flag and waited more than Delta t
        go = M & ~flag & ((now - self.last_check) > self.delta_t)
        stay = go & (nx == wx) & (ny == wy)
        self.last_check[stay] = now[stay]
        mv = go & ~stay
        self.wx = np.where(mv, nx, wx)
        self.wy = np.where(mv, ny, wy)
        self.moving |= mv
        self.waited = np.where(mv, now - self.last_check, self.waited)
        k = np.flatnonzero(mv)
        return k, nx[k] - self.cx[k], ny[k] - self.cy[k]


def simulate_fast(algorithm, lattice, initial, params, *, seed: int, max_steps: int | None = None,
                  allow_violations: bool = False, stop_when_static: bool | int = True,
                  progress=None, stop_when=None, record_every: int = 1, observers=(),
                  faults=None, record_messages: bool = False, record_clamps: bool = True) -> SimulationResult:
    """:func:`~swarmproof.reference_impl.engine.simulate` for ``wang2020``, vectorised (module
    docstring): the same arguments and the same result, bit for bit.

    The run as the engine's: its checks (:func:`unsupported`, then the engine's ``preflight``), the
    engine's grid motion and clocks and every agent's arrays (:func:`_start`), the steps with the
    engine's phases (:func:`_ticks`), then the trace and the result.

    Raises
    ------
    UsageError
        The run is outside what the vectorised path covers (:func:`unsupported` says why), or
        any error :func:`~swarmproof.reference_impl.engine.simulate` raises for bad input.
    """
    why = unsupported(algorithm, params, faults=faults, record_messages=record_messages)
    if why is not None:
        raise UsageError(f"the vectorised wang2020 path does not cover this run: {why}",
                         fix="run the per-robot reference: drop --vectorised (swarmproof simulate), or call swarmproof.reference_impl.engine.simulate")
    seed, faults, events, broken = preflight(algorithm, lattice, initial, params, seed, allow_violations, faults)
    n = initial.n
    broken = list(broken)
    run, mover, clocks = _start(algorithm, lattice, initial, params, seed)
    ids, poses = run.ids, run.grid_poses
    max_steps, window = run_caps(algorithm, params, n, max_steps, stop_when_static)
    record_every, observers = _check_outputs(record_every, observers)
    rec = Recording(record_every, poses, None, False)
    status, t, states = _ticks(run, mover, clocks, rec, events, float(params.range), max_steps, window,
                               observers, progress, stop_when)
    if progress is not None:
        progress(t, max_steps)
    if states is None:
        states = tuple(run.state(k) for k in range(n))
    rec.finish(t, poses, None, states)
    meta = run_meta(algorithm, lattice, params, seed, status, t, max_steps, window, broken, faults, clocks,
                    {"grid_spacing": mover.spacing, **mover.describe()}, record_every, None)
    trace = rec.trace(ids, events, meta)
    return SimulationResult(status=status, steps=t, trace=trace, broken_assumptions=tuple(broken),
                            seed=seed, static_window=window, max_steps=max_steps, observers=observers,
                            crash=None)


def _start(algorithm, lattice, initial, params, seed: int):
    """What the engine builds before step 0, for the vectorised path: the start poses (headings
    wrapped), the engine's grid motion (:class:`~swarmproof.reference_impl.engine.motion.GridMotion`)
    and clocks (:class:`~swarmproof.reference_impl.engine.clocks.AsyncClocks`), and every agent's
    fields (:class:`_Run`, from one controller's constants).  Returns ``(run, mover, clocks)``;
    ``run.ids`` and ``run.grid_poses`` are the run's ID and pose arrays."""
    from swarmproof.models.se2 import wrap_angle

    n = initial.n
    ids = np.asarray(initial.ids, dtype=np.int64)
    ids_list = ids.tolist()
    poses = np.zeros((n, 3))
    poses[:] = initial.poses
    poses[:, 2] = wrap_angle(poses[:, 2])
    mover = GridMotion(params, n, seed)
    mover.start(poses, n, ids_list)
    clocks = AsyncClocks(params, n, seed)
    ctrl = algorithm.controller(ids_list[0], params, lattice, _robot_rng(seed, 0))
    return _Run(ctrl, ids, poses, params, seed, clocks), mover, clocks


def _check_outputs(record_every, observers) -> tuple:
    """``(record_every, observers)`` checked as the engine checks them: a whole number >= 1, and a
    tuple of streaming monitors (``start(ids)`` and ``observe(t, poses, states, present)``)."""
    if not isinstance(record_every, (int, np.integer)) or int(record_every) < 1:
        raise UsageError(f"record_every={record_every!r} must be an integer >= 1", fix="1 records every step")
    record_every = int(record_every)
    observers = tuple(observers or ())
    for ob in observers:
        if not (callable(getattr(ob, "start", None)) and callable(getattr(ob, "observe", None))):
            raise UsageError(f"observer={ob!r} has no start(ids) and observe(t, poses, states, present)",
                             fix="use a streaming monitor such as ConnectivityMonitor")
    return record_every, observers


def _ticks(run, mover, clocks, rec, events, phi, max_steps, window, observers, progress, stop_when) -> tuple:
    """Step 0's record and observation, then the steps until a stop rule holds, with the engine's
    phases (engine/run.py): activation (every clock ticks, rate 1), sensing, delivery and every
    agent's Algorithms 2-4 (:meth:`_Run.tick`), grid motion (:func:`_grid_motion`), recording
    (:func:`_record_step`) and observers, then the stop rules (:func:`_stop_status`).

    Returns ``(status, steps, states)``: ``states`` the last step's states when built, else None.
    """
    n, ids, poses = run.n, run.ids, run.grid_poses
    present = np.ones(n, dtype=bool)
    idx = np.arange(n)
    states = tuple(run.state(k) for k in range(n))
    rec.states.append(states)
    status = "step_cap"
    quiet = t = 0
    lazy = _States(run, 0)
    for ob in observers:
        ob.start(ids.copy())
        ob.observe(0, _ro(poses), lazy, _ro(present))
    finished = False
    if stop_when is not None and stop_when(0, poses, lazy, present):
        status, finished = "stopped", True
    last_msgs, last_valid = run.outbox(), np.zeros(n, dtype=bool)
    outbox = None
    sig = run.signature()
    while not finished and t < max_steps:
        if sys.getrefcount(lazy) > 2:        # kept by an observer (2: the name and the call's argument)
            lazy.freeze()
        lazy = None
        n_events = len(events)
        decide, bcast, tau0 = clocks.ticks(t, idx)                 # 1. activation
        if not decide.all():
            raise AssertionError("a rate-1 clock skipped a tick")   # unsupported() rules this out
        movers, dx, dy = run.tick(poses, tau0, last_msgs, last_valid, phi)   # 2.-4.
        new_outbox = run.outbox()
        same_poses = _grid_motion(mover, poses, movers, dx, dy, events, ids, t)   # 5. motion
        t += 1
        run.t = t
        changed, sig, states = _record_step(run, rec, t, poses, present, events, n_events, sig, states)  # 6.
        lazy = _States(run, t)
        for ob in observers:
            ob.observe(t, _ro(poses), lazy, _ro(present))
        quiet_step = (not changed and same_poses and outbox is not None
                      and np.array_equal(new_outbox[0], outbox[0]) and np.array_equal(new_outbox[1], outbox[1]))
        outbox = new_outbox
        last_msgs, last_valid = new_outbox, bcast
        quiet = quiet + 1 if quiet_step else 0
        if progress is not None and t % PROGRESS_EVERY == 0:
            progress(t, max_steps)
        stop = _stop_status(run, t, quiet, window, stop_when, poses, lazy, present)
        if stop is not None:
            status = stop
            break
    return status, t, states


def _grid_motion(mover, poses, movers, dx, dy, events, ids, t) -> bool:
    """The engine's grid motion (engine/motion.py ``_grid_motion``), vectorised: ``movers`` at a cell
    start crossing the edge ``(dx, dy)`` (one ``"edge"`` event names them), every agent on an edge
    advances ``v dt / l`` of it and stops at the far cell.  Returns whether no pose changed."""
    cells, edge, frac, gstep, spacing = mover.cells, mover.edge, mover.frac, mover.step, mover.spacing
    if len(movers):
        free = ~(edge[movers].any(axis=1))
        st = movers[free]
        edge[st, 0], edge[st, 1] = dx[free], dy[free]
        frac[st] = 0.0
        if len(st):
            events.append(Event(t, "edge", tuple(ids[st].tolist())))
    on = np.flatnonzero((edge[:, 0] != 0) | (edge[:, 1] != 0))      # edge.any(axis=1), cheaper
    if len(on):
        f = frac[on] + gstep
        arr = f >= 1.0
        a, b = on[arr], on[~arr]
        cells[a] += edge[a]
        edge[a] = 0
        frac[a] = 0.0
        poses[a, 0], poses[a, 1] = cells[a, 0] * spacing, cells[a, 1] * spacing
        fb = f[~arr]
        frac[b] = fb
        poses[b, 0] = (cells[b, 0] + fb * edge[b, 0]) * spacing
        poses[b, 1] = (cells[b, 1] + fb * edge[b, 1]) * spacing
    return len(on) == 0


def _record_step(run, rec, t, poses, present, events, n_events, sig, states) -> tuple:
    """The engine's recording of step ``t``: the frame when ``rec`` keeps the step, and whether any
    agent's state changed (:meth:`_Run.signature` and :meth:`_Run.heard_keys` against the last
    step); the states are rebuilt only for a kept step after a change.

    Returns ``(changed, signature, states)``; ``states`` None when changed and not yet built."""
    record = rec.keeps(t, events, n_events)
    if record:
        rec.frame(t, poses, present)
    new_sig = run.signature()
    changed = not (np.array_equal(new_sig[0], sig[0]) and np.array_equal(new_sig[1], sig[1])
                   and np.array_equal(run.heard_keys(), run.heard_keys(previous=True)))
    if changed:
        states = None
    if record:
        if states is None:
            states = tuple(run.state(k) for k in range(run.n))
        rec.states.append(states)
    return changed, new_sig, states


def _stop_status(run, t, quiet, window, stop_when, poses, lazy, present) -> str | None:
    """The engine's stop rules after step ``t``, in its order: every agent detected its last shape
    complete (004 Sec. III-B: ``"finished"``), ``window`` quiet steps (``"static"``), ``stop_when``
    (``"stopped"``); None: go on."""
    if bool((run.completed >= run.nshapes).all()):
        return "finished"
    if window and quiet >= window:
        return "static"
    if stop_when is not None and stop_when(t, poses, lazy, present):
        return "stopped"
    return None
